"""The live view says why each phase ended (issue 26): under the plot, the simulator's phase table lists the
charger's phases from its EVENT frames (start, end, the end reason, what went in, the pack at the end) with a
warning sign where a default, the balancer or a protection ended one; the run's line and the finish message name
the rule that ended the run, as the simulator's table does."""
import os

import pytest

from device_helpers import WAIT_MS, connect
from zuml_studio.protocol.messages import DeviceEvent, Telemetry
from zuml_studio.sim.reasons import shown_reason
from zuml_studio.ui.device.live_view import LiveView

CEILING = "balancer: cell 4 reached 4.20V (ceiling)"


def frame(t: float, mah_in: float, volts: float = 16.4, *, running: bool = True, mask: int = 0,
          temp: float | None = 26.0, run: int = 1) -> Telemetry:
    return Telemetry(t, "charge", "charge" if running else "", 1, 0, run, run if running else 0, running, False,
                     temp is not None, volts, 2.2 if running else 0.0, temp, 30.0, mah_in, 0.0, (4.08, 4.08, 4.08, 4.16),
                     balance_mask=mask)


def feed_weak_cell_run(series) -> None:
    """A 4S LiPo charge as the virtual charger reports it: C1 ends by the macro's IF(V>4.1S), C2 by the
    balancer's ceiling on cell 4 while the balancer bleeds it, then the macro ends."""
    series.add_event(DeviceEvent(0, 0.0, "section", "charge"))
    series.add_event(DeviceEvent(1, 0.0, "phase_start", "charge", 1, 1, 12))
    for k in range(1, 11):
        series.add_telemetry(frame(k * 60.0, k * 36.0, 15.0 + k * 0.1, mask=0b1000 if k > 8 else 0))
    series.add_event(DeviceEvent(2, 630.0, "phase_end", "charge", 1, 1, 12, "IF(V>4.1S) STOP_FAZE"))
    series.add_event(DeviceEvent(3, 630.0, "phase_start", "charge", 2, 1, 20))
    series.add_telemetry(frame(660.0, 380.0, 16.5, mask=0b1000, run=2))
    series.add_event(DeviceEvent(4, 700.0, "phase_end", "charge", 2, 1, 20, CEILING))
    series.add_event(DeviceEvent(5, 700.0, "finish", detail="end of macro"))
    series.add_telemetry(frame(700.0, 400.0, 16.3, running=False))


def test_the_phase_table_lists_each_phase_with_its_end_reason(qtbot):
    view = LiveView()
    qtbot.addWidget(view)
    feed_weak_cell_run(view.series)
    view.update_phases()
    table = view.phase_table
    model = table.phases
    assert model.rowCount() == 2
    reason = model.index(0, 6).data(), model.index(1, 6).data()
    assert reason == ("IF(V>4.1S) STOP_FAZE", shown_reason(CEILING))
    assert not table.is_flagged(0) and table.is_flagged(1)          # the balancer, not the macro, ended C2
    assert "per-cell ceiling" in table.phases.flag_tip(1) and "weak cell" in table.phases.flag_tip(1)
    first, second = view.series.phases_copy()[1]
    assert (first.mah_in, round(first.v_end, 2), first.temp_end) == (360.0, 16.0, 26.0)
    assert second.mah_in == 40.0                    # up to the run's last counters, from the frame after the end
    assert first.bled_s == (0.0, 0.0, 0.0, 120.0)   # the frames with cell 4's balance bit: 2 minutes
    assert model.index(0, 11).data() == "balancer: cell 4 2 min"
    assert model.index(1, 11).data() == ""          # no second frame in C2: no time to count


def test_the_runs_line_names_its_end_and_the_phase_that_warns(qtbot):
    view = LiveView()
    qtbot.addWidget(view)
    feed_weak_cell_run(view.series)
    view.update_phases()
    text = view.summary.text()
    assert "end: end of macro" in text and "in 400 mAh" in text
    assert "⚠ 1 phase ended by a default" in text
    assert "phase 2: one cell reached the charger's per-cell ceiling" in text


def test_a_running_phase_is_listed_as_running_and_without_a_sensor_has_no_temperature(qtbot):
    view = LiveView()
    qtbot.addWidget(view)
    view.series.add_event(DeviceEvent(0, 0.0, "phase_start", "charge", 1, 1, 12))
    view.series.add_telemetry(frame(60.0, 36.0, temp=None))
    view.update_phases()
    model = view.phase_table.phases
    assert model.index(0, 6).data() == "(running)" and model.index(0, 4).data() == "…"
    assert "end: (running)" in view.summary.text()
    view.series.add_event(DeviceEvent(1, 90.0, "phase_end", "charge", 1, 1, 12, "protection: cell 3 over max"))
    view.update_phases()
    assert model.index(0, 10).data() == "—"        # no sensor: no temperature, not "nan"
    assert view.phase_table.is_flagged(0)           # a protection ended it: the user must look


def test_the_finish_comes_with_the_phase_that_ended_the_run(qtbot):
    view = LiveView()
    qtbot.addWidget(view)
    feed_weak_cell_run(view.series)
    [(finish, last)] = view.new_finishes()
    assert finish.detail == "end of macro" and last.reason == CEILING and last.warns
    assert view.new_finishes() == []


def test_the_chosen_earlier_run_shows_its_own_phases(qtbot):
    view = LiveView()
    qtbot.addWidget(view)
    feed_weak_cell_run(view.series)
    view.new_run("LiPo")
    view.run_started("LiPo", 4)
    view.update_phases()
    assert view.phase_table.phases.rowCount() == 0 and view.summary.text() == ""
    view.runChosen.emit(0)
    assert view.phase_table.phases.rowCount() == 2


HELD = """MACRO Held
  AKK_TYPE=LiPo
  CHARGE_SECTION
    FAZE
    CONSTANT_I=INPUT
    IF(V>4.25S) STOP_FAZE()
    END_FAZE
  END_SECTION
END_MACRO
"""


@pytest.mark.skipif(os.name != "posix", reason="the built-in virtual charger uses a pty here")
def test_a_weak_cell_charge_on_the_virtual_charger_ends_by_the_balancer_and_says_so(qtbot, make_panel, editor):
    # a constant current to a pack voltage its held weak cell never lets it reach: the balancer ends the phase
    editor.set(HELD)
    panel = make_panel(size=(1354, 560))
    bar = panel.bar
    bar.v_chem.setCurrentIndex(bar.v_chem.findData("LiPo"))
    bar.v_mah.setValue(2200)
    bar.v_cells.setValue(4)
    bar.v_weak.setValue(15)
    bar.v_speed.setValue(20000)
    connect(qtbot, panel)
    with qtbot.waitSignal(panel.flashFinished, timeout=WAIT_MS) as flashed:
        panel.flash()
    assert flashed.args[0], flashed.args[1]
    panel.set_start_params(current_a=2.2, sensor=True)
    with qtbot.waitSignal(panel.startFinished, timeout=WAIT_MS) as started:
        panel.start()
    assert started.args[0], started.args[1]
    qtbot.waitUntil(lambda: "finished" in panel.message_text(), timeout=WAIT_MS)
    table = panel.live.phase_table
    qtbot.waitUntil(lambda: table.phases.rowCount() >= 1 and "end of macro" in panel.live.summary.text(),
                    timeout=WAIT_MS)
    last = table.phases.rowCount() - 1
    assert table.phases.index(last, 6).data().startswith("balancer: cell 4 reached")
    assert table.is_flagged(last)
    assert "last phase ⚠ C1: balancer: cell 4 reached" in panel.message_text()
    assert panel.live.phase_box.isVisible() and panel.live.body.sizes()[1] > 0


def test_in_a_low_dock_the_plot_keeps_its_height_and_the_phases_come_back_when_it_grows(qtbot, make_panel):
    from zuml_studio.ui.device.live_view import PLOT_MIN_H
    panel = make_panel(size=(1354, 358))            # the Device dock's room in a 1366x768 window
    feed_weak_cell_run(panel.live.series)
    panel.live.update_phases()
    qtbot.waitUntil(lambda: panel.plot.height() > 0)
    assert panel.plot.height() >= PLOT_MIN_H
    assert not panel.live.phase_table.isVisible()   # no room for a row: not a table of headers alone
    panel.resize(1354, 760)
    qtbot.waitUntil(lambda: panel.live.phase_table.isVisible())
    assert panel.plot.height() >= PLOT_MIN_H and panel.live.phase_table.height() > 0


def test_in_the_charge_mode_the_phases_stand_under_the_run_controls(make_window, qtbot):
    w = make_window()
    w.resize(1366, 768)
    qtbot.waitUntil(lambda: w.size().width() == 1366)
    w.modes.switch("charge")
    panel = w.device_panel
    qtbot.waitUntil(panel.controls_scroll.is_stacked)
    assert panel.controls_scroll.isAncestorOf(panel.live.phase_box)
    assert panel.live.phase_table.isColumnHidden(3) and not panel.live.phase_table.isColumnHidden(6)
    w.modes.switch("write")
    w.device_dock.show()
    w.device_dock.raise_()
    qtbot.waitUntil(lambda: not panel.controls_scroll.is_stacked())
    assert panel.live.body.isAncestorOf(panel.live.phase_box) and not panel.live.phase_table.isColumnHidden(3)
