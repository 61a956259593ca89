"""The Device panel against the C firmware: the ATmega32 image on simavr (`zuml firmware-sim`)
behind a pty, reached as a real charger is: connect, Compile & Flash, the slot list, START, the
live plot from its telemetry, STOP, disconnect."""
import pytest
from PySide6.QtCore import Qt

from chargers import NEEDS_FIRMWARE_SIM, FirmwareSims
from device_helpers import WAIT_MS, click_flash, connect

pytestmark = NEEDS_FIRMWARE_SIM


@pytest.fixture
def firmware_port(tmp_path):
    sims = FirmwareSims(tmp_path)
    yield sims.start()
    sims.stop()


def test_the_panel_flashes_lists_starts_and_monitors_the_firmware(qtbot, make_panel, editor, firmware_port):
    editor.set("LiPo")                                     # the firmware-sim's battery: lithium, 3 cells
    panel = make_panel()
    panel.rate.setValue(10)
    connect(qtbot, panel, firmware_port)
    assert panel.is_connected()
    info = panel.info_label.full_text()
    assert "generic ATmega32 (not a B6)" in info and "EEPROM 431 bytes" in info, info
    assert panel.slot_names() == []
    assert panel.free_label.text().startswith("431 of 431 bytes free")

    text = click_flash(qtbot, panel)
    assert text.startswith("Flashed LiPo into slot 0: 43 bytes,") and text.endswith("verified.")
    assert panel.slot_names() == ["LiPo"]
    assert panel.table.item(0, 1).text() == "LiPo" and panel.table.item(0, 4).text() == "ok"
    assert panel.free_label.text().startswith("388 of 431 bytes free")

    panel.set_start_params(task="charge", capacity_mah=2000, current_a=1.0, series=3, sensor=False)
    with qtbot.waitSignal(panel.telemetryReceived, timeout=WAIT_MS, check_params_cb=lambda n: n > 15):
        with qtbot.waitSignal(panel.startFinished, timeout=WAIT_MS) as started:
            qtbot.mouseClick(panel.start_button, Qt.MouseButton.LeftButton)
        assert started.args == [True, "Started LiPo (slot 0): charge."]
    qtbot.waitUntil(lambda: panel.plot.band_count() >= 1, timeout=WAIT_MS)
    phase = panel.plot.phases()[0]
    assert (phase.section, phase.index) == ("charge", 1) and not phase.closed
    current = panel.series.buffer.column("current")
    assert abs(float(current[-1]) - 1.0) < 0.05           # the firmware's regulated 1 A, as telemetry says

    with qtbot.waitSignal(panel.operationFinished, timeout=WAIT_MS) as stopped:
        qtbot.mouseClick(panel.stop_button, Qt.MouseButton.LeftButton)
    assert stopped.args[0] == "stop" and stopped.args[1]
    qtbot.waitUntil(lambda: any(p.closed for p in panel.plot.phases()), timeout=WAIT_MS)
    assert panel.plot.phases()[0].reason == "stopped"
    table = panel.live.phase_table.phases            # the firmware's EVENT detail, listed as the simulator lists it
    qtbot.waitUntil(lambda: table.rowCount() == 1 and table.index(0, 6).data() == "stopped", timeout=WAIT_MS)

    with qtbot.waitSignal(panel.connectedChanged, timeout=WAIT_MS) as gone:
        qtbot.mouseClick(panel.connect_button, Qt.MouseButton.LeftButton)
    assert gone.args == [False]
