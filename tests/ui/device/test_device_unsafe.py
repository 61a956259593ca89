"""The Device panel runs the safety check before Compile & Flash, Restore and Start; what it
refuses goes ahead only after a dialog that names the danger (issue 12, point 1)."""
import os

import pytest
from PySide6.QtWidgets import QMessageBox

from device_helpers import WAIT_MS, connect
from helpers import compiled, unsafe_record
from zuml_studio.lang.eeprom import pack, slots
from zuml_studio.ui.device import unsafe_dialog as dp
from zuml_studio.ui.device.unsafe_dialog import confirm_unsafe, unsafe_dialog

pytestmark = pytest.mark.skipif(os.name != "posix", reason="the virtual chargers use ptys here")

FAST_NIMH = """MACRO Fast
  AKK_TYPE=NiMh
  CHARGE_SECTION
    FAZE
      CONSTANT_I=5A
      IF(DELTA_PEAK>0.005S) STOP_FAZE
    END_FAZE
  END_SECTION
END_MACRO
"""


@pytest.fixture
def asked(monkeypatch):
    """Replace the dialog: asked.answer is what the user clicks; asked.calls what was shown."""
    class Asked:
        answer = False
        calls = []

    def ask(parent, action, problems):
        Asked.calls.append((action, list(problems)))
        return Asked.answer
    monkeypatch.setattr(dp, "confirm_unsafe", ask)
    return Asked


def test_the_dialog_names_each_danger_and_defaults_to_cancel(qtbot):
    box = unsafe_dialog(None, "Flash", ["the macro charges at 5.00 A; the battery allows 4 A"])
    qtbot.addWidget(box)
    assert "1 danger" in box.text()
    assert "• the macro charges at 5.00 A; the battery allows 4 A" in box.informativeText()
    assert "fire" in box.informativeText()
    assert box.defaultButton() is not box.go_ahead and box.go_ahead.text() == "Flash anyway"


@pytest.mark.parametrize("click_go_ahead", [True, False])
def test_confirm_unsafe_is_true_only_for_the_go_ahead_button(qtbot, monkeypatch, click_go_ahead):
    shown = []

    def exec_(box):
        shown.append(box)
        (box.go_ahead if click_go_ahead else box.button(QMessageBox.StandardButton.Cancel)).click()
        return 0
    monkeypatch.setattr(QMessageBox, "exec", exec_)
    assert confirm_unsafe(None, "Start", ["E303 (byte 19): too high"]) is click_go_ahead
    assert shown and "E303" in shown[0].informativeText()


def test_flash_past_the_passport_asks_and_cancel_writes_nothing(qtbot, make_panel, editor, asked):
    editor.value = (compiled(FAST_NIMH), "Fast")
    panel = make_panel()
    connect(qtbot, panel)
    device = panel.connection.virtual_device
    with qtbot.waitSignal(panel.flashFinished, timeout=WAIT_MS) as flashed:
        panel.flash()
    ok, text = flashed.args
    assert not ok and text.startswith("Not flashed: the safety check refused it:")
    assert "5.00 A" in text and "allows 4 A" in text
    assert asked.calls[0][0] == "Flash" and device.commits == 0

    asked.answer = True
    with qtbot.waitSignal(panel.flashFinished, timeout=WAIT_MS) as flashed:
        panel.flash()
    assert flashed.args[0], flashed.args[1]
    assert [s.name for s in slots(device.eeprom_image)] == ["Fast"]


def test_restore_of_an_unsafe_image_asks_first(qtbot, make_panel, asked, tmp_path):
    path = tmp_path / "image.bin"
    path.write_bytes(pack([compiled("NiMh"), unsafe_record()], 1024))
    panel = make_panel()
    connect(qtbot, panel)
    device = panel.connection.virtual_device
    with qtbot.waitSignal(panel.operationFinished, timeout=WAIT_MS) as done:
        panel.restore(path)
    assert done.args[:2] == ["restore", False]
    assert "slot 1 (Hot): E303" in done.args[2] and device.commits == 0
    asked.answer = True
    with qtbot.waitSignal(panel.operationFinished, timeout=WAIT_MS) as done:
        panel.restore(path)
    assert done.args[:2] == ["restore", True], done.args
    assert [s.name for s in slots(device.eeprom_image)] == ["NiMh", "Hot"]


def test_start_asks_and_then_the_charger_refuses_as_the_last_line(qtbot, make_panel, editor, asked):
    editor.value = (unsafe_record(), "Hot")
    panel = make_panel()
    panel.v_chem.setCurrentIndex(panel.v_chem.findData("LiIon"))
    panel.v_cells.setValue(1)
    connect(qtbot, panel)
    with qtbot.waitSignal(panel.flashFinished, timeout=WAIT_MS) as flashed:
        panel.flash(force=True)
    assert flashed.args[0], flashed.args[1]
    panel.set_start_params(current_a=1.0, sensor=False)
    with qtbot.waitSignal(panel.startFinished, timeout=WAIT_MS) as started:
        panel.start()
    ok, text = started.args
    assert not ok and text.startswith("Not started: the safety check forbids Hot:") and "E303" in text
    asked.answer = True
    with qtbot.waitSignal(panel.startFinished, timeout=WAIT_MS) as started:
        panel.start()
    ok, text = started.args
    assert not ok and text.startswith("The charger refused to start:") and "E303" in text
    assert [a for a, _ in asked.calls] == ["Start", "Start"]
    assert panel.connection.virtual_device.state == "idle"
