"""The window's "iMAX B6 (ZUML) through a USBasp": connecting asks that the battery be disconnected; Upload
(Ctrl+U) and Compile & Flash write the store through the programmer (the real avrdude against the emulated
STK500v1 programmer, tests/stk500_chip.py), leave the templates and the calibration alone, and refuse what
the safety check refuses, judged with the chip's own templates; Start is off (runs start on the front panel)."""
import pytest
from PySide6.QtCore import Qt

from device_helpers import WAIT_MS, connect
from stk500_chip import Atmega32, Stk500Programmer
from b6_eeprom import ZUML_FLASH, b6_eeprom
from tools import AVRDUDE, needs
from zuml_studio.device.isp_store import IMAGE_SIZE, TEMPLATES_AT
from zuml_studio.lang.eeprom import slots
from zuml_studio.ui.device import confirm_dialogs

pytestmark = needs(AVRDUDE)
LIPO = """MACRO LiPo-B6
  AKK_TYPE=LiPo
  CHARGE_SECTION
    FAZE
    CONSTANT_I=INPUT
    IF(V>4.1S) STOP_FAZE()
    END_FAZE
  END_SECTION
END_MACRO
"""
# Unsafe only through the charger's start template 2 (factory: 3S LiPo): 13.5 V is 4.5 V per cell
WALK = LIPO.replace("LiPo-B6", "Walk").replace("  CHARGE_SECTION", "  START_SHABLON=2\n  CHARGE_SECTION").replace(
    "CONSTANT_I=INPUT\n    IF(V>4.1S)", "CONSTANT_I=1A\n    IF(V>13.5V)")


@pytest.fixture
def b6():
    chip = Atmega32(flash=bytearray(ZUML_FLASH), eeprom=bytearray(b6_eeprom()), lfuse=0x3F, hfuse=0xC9)
    with Stk500Programmer(chip) as programmer:
        yield chip, f"isp:stk500v1@{programmer.port}"


@pytest.fixture
def battery_off(monkeypatch):
    asked = []
    monkeypatch.setattr(confirm_dialogs, "confirm_programmer", lambda parent: asked.append(parent) or True)
    return asked


def test_upload_and_compile_and_flash_through_the_programmer(make_window, qtbot, tmp_path, b6, battery_off):
    chip, target = b6
    before = bytes(chip.eeprom)
    source = tmp_path / "lipo.zuml"
    source.write_text(LIPO)
    w = make_window(str(source))
    panel = w.device_panel
    assert panel.ports.combo.itemText(2) == "iMAX B6 (ZUML) through a USBasp"
    connect(qtbot, panel, target)
    assert battery_off and "iMAX B6 (ZUML firmware)" in panel.message_text()
    assert "zuml-fw 0.2 imaxb6" in panel.bar.info_label.toolTip()
    assert not panel.run.start_button.isEnabled() and "front panel" in panel.run.start_button.toolTip()

    with qtbot.waitSignal(panel.flashFinished, timeout=WAIT_MS) as flashed:
        w.upload()                                              # Ctrl+U
    assert flashed.args[0] is True, flashed.args[1]
    assert flashed.args[1].startswith("Flashed LiPo-B6 into slot 0")
    assert [s.name for s in slots(bytes(chip.eeprom[:IMAGE_SIZE]))] == ["LiPo-B6"]
    assert chip.eeprom[TEMPLATES_AT:] == before[TEMPLATES_AT:] and chip.erases == 0
    assert panel.charger.table.rowCount() == 1

    w.editor.setPlainText(WALK)
    w.validate_now()
    written = bytes(chip.eeprom)
    with qtbot.waitSignal(panel.flashFinished, timeout=WAIT_MS) as flashed:
        qtbot.mouseClick(panel.flash_button, Qt.MouseButton.LeftButton)
    assert flashed.args[0] is False
    assert "E303" in flashed.args[1] and "[start template 2: " in flashed.args[1]
    assert bytes(chip.eeprom) == written


def test_without_the_battery_disconnected_it_does_not_connect(make_panel, qtbot, b6, monkeypatch):
    chip, target = b6
    monkeypatch.setattr(confirm_dialogs, "confirm_programmer", lambda parent: False)
    panel = make_panel()
    assert not panel.connect_to(target)
    assert panel.connection.state == "disconnected" and "disconnect the battery first" in panel.message_text()


def test_a_chip_without_the_zuml_firmware_does_not_connect(make_panel, qtbot, b6, battery_off):
    chip, target = b6
    chip.flash[:] = b"\xff" * len(chip.flash)
    panel = make_panel()
    with qtbot.waitSignal(panel.connectedChanged, timeout=WAIT_MS) as blocker:
        assert panel.connect_to(target)
    assert blocker.args == [False]
    assert "does not run the ZUML firmware" in panel.message_text()


def test_backup_and_restore_through_the_programmer(make_panel, qtbot, tmp_path, b6, battery_off):
    from helpers import compiled
    from zuml_studio.lang.eeprom import pack
    chip, target = b6
    chip.eeprom[:] = b6_eeprom([compiled(LIPO)])
    panel = make_panel()
    connect(qtbot, panel, target)
    assert panel.charger.slot_names() == ["LiPo-B6"]
    with qtbot.waitSignal(panel.operationFinished, timeout=WAIT_MS) as saved:
        panel.backup(tmp_path / "b6.bin")
    assert saved.args[:2] == ["backup", True], saved.args
    assert (tmp_path / "b6.bin").read_bytes() == bytes(chip.eeprom[:IMAGE_SIZE])
    (tmp_path / "two.bin").write_bytes(pack([compiled(LIPO), compiled("NiMh")], IMAGE_SIZE))
    before = bytes(chip.eeprom)
    with qtbot.waitSignal(panel.operationFinished, timeout=WAIT_MS) as restored:
        panel.restore(tmp_path / "two.bin")
    assert restored.args[:2] == ["restore", True], restored.args
    assert panel.charger.slot_names() == ["LiPo-B6", "NiMh"]
    assert chip.eeprom[TEMPLATES_AT:] == before[TEMPLATES_AT:]


def test_what_needs_the_serial_requests_says_so_through_the_programmer(make_panel, qtbot, b6, battery_off):
    from zuml_studio.device.errors import DeviceError
    chip, target = b6
    panel = make_panel()
    connect(qtbot, panel, target)
    client = panel.connection.client
    with pytest.raises(DeviceError, match="through the programmer only its macro store is reached"):
        client.request("CAL_READ")
    with pytest.raises(DeviceError, match="front panel"):
        client.start(0)
