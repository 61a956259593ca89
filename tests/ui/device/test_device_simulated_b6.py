"""The simulated iMAX B6 as a device in the window (issue 32 §4): picked from the port list, started and
stopped by the panel, its EEPROM kept in the session folder; while connected the panel draws its display
and its four buttons, which press the simulated ones live. The test rehearses the B6 workflow: upload, pick
the slot on the display, set the current, hold START, watch the curve, STOP. It waits for what the
display and the panel show, never for a time."""
import pytest
from PySide6.QtCore import Qt

from chargers import NEEDS_FIRMWARE_SIM
from device_helpers import WAIT_MS, click_flash, connect
from helpers import compiled
from zuml_studio.device.links.ports import SIMULATED_B6

pytestmark = NEEDS_FIRMWARE_SIM

BENCH = """MACRO Bench
  AKK_TYPE=LiPo
  CHARGE_SECTION
    FAZE
    CONSTANT_I=INPUT
    IF(V>4.1S) STOP_FAZE()
    END_FAZE
  END_SECTION
END_MACRO
"""


def lcd(panel) -> tuple[str, str]:
    return panel.front_panel.text()


def wait_lcd(qtbot, panel, test) -> None:
    """Until the display passes ``test`` (it is shown when it never does)."""
    def shown():
        assert test(lcd(panel)), lcd(panel)
    qtbot.waitUntil(shown, timeout=WAIT_MS)


def test_the_b6_workflow_on_the_simulated_b6_in_the_window(qtbot, make_panel, editor, tmp_path, monkeypatch):
    monkeypatch.setenv("ZUML_STUDIO_DATA_DIR", str(tmp_path / "data"))
    panel = make_panel(size=(1366, 768))
    assert panel.ports.combo.itemData(1) == SIMULATED_B6
    assert not panel.front_panel.isVisible()
    connect(qtbot, panel, SIMULATED_B6)
    assert panel.front_panel.isVisible() and all(b.isVisible() for b in panel.front_panel.buttons.values())
    assert "cell 4 not balanced" in panel.info_label.full_text()   # the simulated B6 has its receive wire
    wait_lcd(qtbot, panel, lambda shown: shown[0] == "no macros")

    # upload two macros: LiPo, then Bench (by name: a new slot)
    editor.set("LiPo")
    click_flash(qtbot, panel)
    editor.value = (compiled(BENCH), "Bench")
    click_flash(qtbot, panel)
    assert panel.slot_names() == ["LiPo", "Bench"]

    buttons = panel.front_panel.buttons
    # pick the slot on the display: INC goes to the next one
    wait_lcd(qtbot, panel, lambda shown: shown[0] == "1 LiPo")
    qtbot.mouseClick(buttons["inc"], Qt.MouseButton.LeftButton)
    wait_lcd(qtbot, panel, lambda shown: shown[0] == "2 Bench")
    # set the current: START shows it, INC adds 0.1 A
    qtbot.mouseClick(buttons["start"], Qt.MouseButton.LeftButton)
    wait_lcd(qtbot, panel, lambda shown: shown[1] == "charge at 1.00A")
    for want in ("charge at 1.10A", "charge at 1.20A"):
        qtbot.mouseClick(buttons["inc"], Qt.MouseButton.LeftButton)
        wait_lcd(qtbot, panel, lambda shown, want=want: shown[1] == want)
    # hold START until the charger runs (the firmware wants 0.5 s of it), then let go
    qtbot.mousePress(buttons["start"], Qt.MouseButton.LeftButton)
    wait_lcd(qtbot, panel, lambda shown: shown[0].startswith("C1 "))
    qtbot.mouseRelease(buttons["start"], Qt.MouseButton.LeftButton)

    # the curve: the run's telemetry plotted in its phase band, at the current set on the panel
    qtbot.waitUntil(lambda: panel.plot.band_count() >= 1, timeout=WAIT_MS)
    def charging_at_the_current_set():
        current = panel.series.buffer.column("current")
        assert len(current) > 0 and abs(float(current[-1]) - 1.2) < 0.06, list(current)[-3:]
    qtbot.waitUntil(charging_at_the_current_set, timeout=WAIT_MS)
    phase = panel.plot.phases()[0]
    assert (phase.section, phase.index) == ("charge", 1) and not phase.closed

    # STOP on the front panel ends the run, as the display and the phase list say
    qtbot.mouseClick(buttons["stop"], Qt.MouseButton.LeftButton)
    wait_lcd(qtbot, panel, lambda shown: shown == ("end Bench", "stopped"))
    qtbot.waitUntil(lambda: any(p.closed and p.reason == "stopped" for p in panel.plot.phases()), timeout=WAIT_MS)

    b6 = panel.connection.simulated_b6
    with qtbot.waitSignal(panel.connectedChanged, timeout=WAIT_MS) as gone:
        qtbot.mouseClick(panel.connect_button, Qt.MouseButton.LeftButton)
    assert gone.args == [False]
    assert b6.proc.poll() is not None and not panel.front_panel.isVisible()

    # the next session: the same charger, its macros (and calibration) kept in the session folder
    connect(qtbot, panel, SIMULATED_B6)
    assert panel.slot_names() == ["LiPo", "Bench"]
    assert "not calibrated" not in lcd(panel)[1]
    assert (tmp_path / "data" / "simulated-imaxb6-eeprom.bin").stat().st_size == 1024


def test_a_simulated_b6_that_cannot_start_says_why(qtbot, make_panel, monkeypatch):
    from zuml_studio.virtual import simulated_b6

    def broken(board):
        from zuml_studio.virtual.firmware_sim import FirmwareBuildError
        raise FirmwareBuildError("avr-gcc not found: the firmware cannot be built (apt-get install …)")

    monkeypatch.setattr("zuml_studio.virtual.firmware_sim.build_device", broken)
    assert simulated_b6.SimulatedB6                          # the module the panel starts it with
    panel = make_panel()
    with qtbot.waitSignal(panel.connectedChanged, timeout=WAIT_MS) as failed:
        assert panel.connect_to(SIMULATED_B6)
    assert failed.args == [False]
    assert "avr-gcc not found" in panel.message_text() and not panel.front_panel.isVisible()


@pytest.mark.parametrize("dark", [False, True])
def test_the_front_panel_of_a_b6_heard_on_its_tx_shows_its_display_only(qtbot, make_panel, dark):
    panel = make_panel()
    panel.front_panel.listen()
    panel.front_panel.show_lcd("C1 12.422V 0.98A", "   12mAh --C  3m")
    assert panel.front_panel.isVisible() and lcd(panel) == ("C1 12.422V 0.98A", "   12mAh --C  3m")
    assert not any(b.isVisible() for b in panel.front_panel.buttons.values())
    panel.front_panel.show_device(None)
    panel.front_panel.show_lcd("late", "line")                # after the link closed: not shown
    assert not panel.front_panel.isVisible() and lcd(panel) == ("", "")
