"""The simulator panel: runs off the GUI thread, fills plot and phase table, shows
errors and cancels in the panel, exports, and links phases back to the source."""
import os

import pyqtgraph as pg
import pytest
from PySide6.QtCore import QPoint, Qt

from helpers import WAIT_MS
from zuml_studio.sim.samples import COLUMNS
from zuml_studio.ui.sim.params_form import FROM_AKK
from zuml_studio.ui.plots.phase_table import DEFAULT_TIP, NOTES_COLUMN, REASON_COLUMN, TIMER_TIP
from zuml_studio.ui.sim.sim_panel import STALE_HINT

LIPO = dict(capacity_mah=2000, current_a=2.0, series=3)
NIMH = dict(capacity_mah=2000, current_a=2.0, series=4, sensor=False)
UNDEF_MACRO = ("MACRO U\nAKK_TYPE=Undef\nCHARGE_SECTION\nFAZE\nCONSTANT_I=INPUT\nIF(V>4.1S) STOP_FAZE\n"
               "END_FAZE\nEND_SECTION\nEND_MACRO\n")


def cell(table, row, col, role=Qt.ItemDataRole.DisplayRole):
    return table.model().index(row, col).data(role)


def rows(table):
    return table.model().rowCount()


def reasons(table):
    return [cell(table, r, REASON_COLUMN) for r in range(rows(table))]


def band_counts(panel):
    return [len(item.spans()) for item in panel.plot.band_items]


def test_object_names_and_interface(panel):
    assert panel.objectName() == "simulatorPanel"
    assert panel.findChild(pg.GraphicsLayoutWidget, "simPlot") is panel.plot
    assert panel.findChild(object, "phaseTable") is panel.table
    assert panel.result() is None
    f = panel.form
    assert (f.task.currentData(), f.capacity.value(), f.current.value(), f.series.value()) == ("charge", 2000, 2.0, 4)
    assert f.model.currentText() == FROM_AKK and f.model.currentData() is None
    assert f.initial.text() == "auto" and f.ambient.value() == 25 and f.sensor.isChecked() and f.auto.isChecked()
    assert not f.repetitions.isEnabled()


def test_lipo_seed_fills_plot_and_phase_table(panel, run):
    result = run("LiPo", **LIPO)
    assert panel.result() is result
    assert rows(panel.table) == 2
    assert reasons(panel.table) == ["IF(V>4.1S) STOP_FAZE", "IF(I<0.1A) STOP_FAZE"]
    assert all(len(column) == len(result.log) > 1000 for column in panel.plot.data.values())
    width = panel.plot.vplot.vb.width()
    for name, curve in panel.plot.curves.items():
        x, y = curve.getData()              # what is drawn: the view's samples, or their min/max per pixel
        assert x is not None and 0 < len(x) == len(y) <= max(2 * len(result.log), 4 * width + 8), name
    assert band_counts(panel) == [2, 2, 2]
    assert [label.toPlainText() for label in panel.plot.labels if label.isVisible()] == \
        ["C1: IF(V>4.1S) STOP_FAZE", "C2: IF(I<0.1A) STOP_FAZE"]
    # 1:21:06 since the LiPo resistance and heat capacity were retuned to the 406DUO and X8 recordings
    # (docs/validation.md): the cooler pack has a little more resistance, so the CV part is longer.
    assert "total 1:21:06" in panel.totals.text() and "end: end of macro" in panel.totals.text()
    assert "LiPo model 2000 mAh × 3 cells" in panel.run_label.text()
    assert not panel.is_running() and not panel.form.cancel_button.isEnabled()


def test_simulation_runs_in_a_process_of_its_own(panel, run, monkeypatch):
    import zuml_studio.ui.sim.worker as worker

    jobs = []
    real = worker.SimJob.start

    def spy(job):
        jobs.append(job)
        return real(job)

    monkeypatch.setattr(worker.SimJob, "start", spy)
    result = run("LiPo", **LIPO)
    assert jobs and jobs[0].worker.pid not in (None, os.getpid())
    assert result.interpreter.finished and len(result.log) > 1000     # the run came back whole


def test_a_crashed_simulation_process_is_an_error_message(panel, qtbot, compiled):
    import signal

    import zuml_studio.ui.sim.worker as worker

    panel.form.auto.setChecked(False)
    panel.set_record(compiled("LiPo"), "LiPo")
    panel.form.set_values(task="train", repetitions=255, **LIPO)
    with qtbot.assertNotEmitted(panel.simulationFinished, wait=100):
        panel.simulate()
        job = worker.SimJob.running()[-1]
        qtbot.waitUntil(lambda: job.worker.pid is not None and "simulated" in panel.form.progress_label.text(),
                        timeout=30_000)
        os.kill(job.worker.pid, signal.SIGKILL)
        assert panel.wait(30_000)
    assert "the simulation process ended unexpectedly" in panel.message_text()
    assert panel.result() is None and not panel.is_running()


def test_nimh_seed_without_sensor_flags_the_default_end(panel, run):
    result = run("NiMh", **NIMH)
    assert result.phases[0].by_default
    assert rows(panel.table) == 1
    assert panel.table.is_flagged(0)
    assert DEFAULT_TIP in cell(panel.table, 0, REASON_COLUMN, Qt.ItemDataRole.ToolTipRole)
    assert cell(panel.table, 0, REASON_COLUMN).startswith("default:")
    assert not cell(panel.table, 0, REASON_COLUMN, Qt.ItemDataRole.DecorationRole).isNull()
    assert "ended by a default" in panel.totals.text()
    assert panel.plot.labels[0].toPlainText().startswith("⚠ C1")


def test_nimh_dv_macro_ends_on_its_own_delta_peak(panel, run):
    run("NiMh-dV", **NIMH)
    assert reasons(panel.table) == ["IF(DELTA_PEAK>0.01S) STOP_FAZE"]
    assert not panel.table.is_flagged(0)
    v = panel.plot.data["voltage_v"]
    assert v.max() > v[-1] > v[0]        # rose to a peak, then the small -dV


def test_no_record_keeps_the_last_result_and_says_so(panel, run):
    result = run("LiPo", **LIPO)
    panel.set_record(None)
    assert panel.result() is result
    assert rows(panel.table) == 2
    assert panel.hint.isVisibleTo(panel) and panel.hint.text() == STALE_HINT
    assert "showing the last valid version" in panel.message_text()


def test_valid_record_again_clears_the_hint(panel, run, compiled):
    run("LiPo", **LIPO)
    panel.set_record(None)
    panel.set_record(compiled("LiPo"), "LiPo")
    assert not panel.hint.isVisibleTo(panel)


def test_cancel_stops_a_long_training_and_says_cancelled(panel, qtbot, compiled):
    panel.form.auto.setChecked(False)
    panel.set_record(compiled("LiPo"), "LiPo")
    panel.form.set_values(task="train", repetitions=255, **LIPO)
    with qtbot.assertNotEmitted(panel.simulationFinished, wait=100):
        panel.simulate()
        assert panel.is_running() and panel.form.cancel_button.isEnabled()
        panel.cancel()
        assert panel.wait(30_000)
    assert "cancelled" in panel.message_text()
    result = panel.result()
    if result is not None:          # stopped between chunks: the run so far is shown
        assert result.interpreter.end_reason == "cancelled"
        assert result.interpreter.time_s < 40 * 3600
    assert not panel.is_running() and not panel.form.cancel_button.isEnabled()


def test_cancel_mid_run_shows_the_run_so_far(panel, qtbot, compiled):
    panel.form.auto.setChecked(False)
    panel.set_record(compiled("LiPo"), "LiPo")
    panel.form.set_values(task="train", repetitions=255, **LIPO)
    panel.simulate()
    label = panel.form.progress_label
    qtbot.waitUntil(lambda: "simulated" in label.text() and not label.text().startswith("0 s"), timeout=30_000)
    panel.cancel()
    assert panel.wait(30_000)
    assert "cancelled after" in panel.message_text()
    assert "cancelled" in panel.form.progress_label.text()
    result = panel.result()
    it = result.interpreter          # stopped between two chunks of the child, long before the 255th repetition
    assert it.end_reason == "cancelled" and 3600 <= it.time_s and result.repetitions()[-1]["repetition"] < 255
    assert rows(panel.table) == len(result.phases) >= 1
    assert len(panel.plot.data["time_s"]) == len(result.log)
    assert len(panel.plot.curves["voltage"].xData) > 0


def test_export_csv_and_png(panel, run, tmp_path):
    run("LiPo", **LIPO)
    csv_path, png_path = tmp_path / "run.csv", tmp_path / "plot.png"
    assert panel.export_csv(str(csv_path)) is not False
    lines = csv_path.read_text().splitlines()
    assert lines[0] == ",".join(COLUMNS + ("cell1_v", "cell2_v", "cell3_v", "balance_mask"))   # 3 cells
    assert len(lines) == len(panel.result().log) + 1
    assert panel.export_png(str(png_path)) is not False
    data = png_path.read_bytes()
    assert data.startswith(b"\x89PNG") and len(data) > 5000


def test_export_failures_are_messages_not_exceptions(panel, run, tmp_path):
    assert panel.export_csv(str(tmp_path / "x.csv")) is False          # nothing simulated yet
    run("LiPo", **LIPO)
    assert panel.export_csv(str(tmp_path / "no" / "such" / "dir.csv")) is False
    assert "cannot write" in panel.message_text()


def test_start_error_is_shown_in_the_panel(panel, qtbot, compiled):
    panel.form.auto.setChecked(False)
    panel.set_record(compiled(UNDEF_MACRO), "U", {"chemistry": "Undef"})
    with qtbot.assertNotEmitted(panel.simulationFinished, wait=100):
        panel.simulate()
        assert panel.wait(30_000)
    assert "has no battery model" in panel.message_text()
    assert "b00020" in panel.message.styleSheet()
    assert panel.result() is None and not panel.is_running()
    # The same macro with a chosen model runs.
    panel.form.set_values(chemistry="LiPo")
    with qtbot.waitSignal(panel.simulationFinished, timeout=30_000):
        panel.simulate()
    assert panel.message.text() == "" and panel.result().chemistry == "LiPo"


def test_missing_model_is_an_error_message(panel, qtbot, compiled, monkeypatch):
    panel.form.auto.setChecked(False)
    panel.set_record(compiled("LiPo"), "LiPo")
    panel.form.model.addItem("Unobtainium", "Unobtainium")
    panel.form.model.setCurrentText("Unobtainium")
    panel.simulate()
    assert panel.wait(30_000)
    assert panel.message.text().startswith("cannot simulate:") and panel.result() is None


def test_a_damaged_named_battery_file_is_said_and_the_panel_goes_on(panel, compiled, monkeypatch, tmp_path):
    # a battery file edited by hand after it was listed: an infinite capacity (once taken), then garbage
    monkeypatch.setenv("ZUML_STUDIO_CONFIG_DIR", str(tmp_path))
    (tmp_path / "batteries").mkdir()
    doc = ('{"format": 1, "name": "Pack", "chemistry": "NiMh", "capacity_mah": Infinity, "series": 4, '
           '"parameters": {}}')
    (tmp_path / "batteries" / "Pack.json").write_text(doc)
    panel.form.auto.setChecked(False)
    panel.set_record(compiled("NiMh"), "NiMh")
    panel.form.add_named_batteries()
    panel.form.model.setCurrentIndex(panel.form.model.findData("battery:Pack"))
    assert panel.form.model.currentData() == "battery:Pack"
    for text, said in ((doc, "capacity_mah must be a finite number, not inf"), ("[garbage", "not a battery file")):
        (tmp_path / "batteries" / "Pack.json").write_text(text)
        panel.simulate()
        assert panel.wait(30_000)
        assert panel.message.text().startswith("cannot simulate: ") and said in panel.message.text()
        assert panel.result() is None and panel.isVisible()


def test_simulate_without_a_record_says_why(panel):
    panel.simulate()
    assert "nothing to simulate" in panel.message_text()
    assert not panel.is_running()


def test_declared_values_prefill_but_never_override_the_user(panel, compiled):
    panel.form.auto.setChecked(False)
    panel.set_record(compiled("LiPo"), "LiPo", {"chemistry": "LiPo", "series": 3, "capacity_mah": 1500})
    assert (panel.form.series.value(), panel.form.capacity.value()) == (3, 1500)
    assert "LiPo" in panel.form.model.toolTip() and panel.form.model.currentData() is None
    panel.form.capacity.setValue(2200)              # the user types a capacity
    panel.set_record(compiled("NiMh"), "NiMh", {"chemistry": "NiMh", "series": 6, "capacity_mah": 900})
    assert panel.form.capacity.value() == 2200
    assert panel.form.series.value() == 6           # not typed by the user: follows the macro


def test_auto_resimulate_runs_the_latest_record_once(panel, qtbot, compiled):
    assert panel.form.auto_resimulate()
    panel.form.set_values(**LIPO)
    results = []
    panel.simulationFinished.connect(results.append)
    panel.set_record(compiled("NiMh-dV"), "NiMh-dV")
    panel.set_record(compiled("LiPo"), "LiPo")          # within the debounce: only this one runs
    qtbot.waitUntil(lambda: len(results) == 1, timeout=30_000)
    qtbot.wait(500)
    assert len(results) == 1 and results[0].interpreter.program.name == "LiPo"
    qtbot.waitUntil(lambda: not panel.is_running(), timeout=30_000)
    panel.set_record(compiled("LiPo"), "LiPo")          # the same record: nothing to do
    qtbot.wait(500)
    assert len(results) == 1 and not panel.is_running()


def test_auto_resimulate_follows_parameter_changes(panel, qtbot, run):
    run("LiPo", **LIPO)
    panel.form.auto.setChecked(True)
    with qtbot.waitSignal(panel.simulationFinished, timeout=30_000) as blocker:
        panel.form.set_values(capacity_mah=1000)
    assert blocker.args[0].capacity_mah == 1000


def test_without_auto_a_change_marks_the_run_outdated(panel, run, compiled, qtbot):
    run("LiPo", **LIPO)
    panel.set_record(compiled("NiMh-dV"), "NiMh-dV")
    assert not panel.is_running()
    qtbot.waitUntil(lambda: "Simulate" in panel.hint.text(), timeout=10_000)


def test_training_totals_list_the_measured_capacities(panel, run):
    result = run("LiPo", task="train", repetitions=2, **LIPO)
    assert rows(panel.table) == 6 == len(result.phases)
    assert band_counts(panel) == [6, 6, 6]
    assert "measured capacity per discharge" in panel.totals.text()
    assert "rep 2" in cell(panel.table, 3, 1)


def test_double_click_on_a_row_emits_the_faze_offset(panel, run, qtbot):
    result = run("LiPo", **LIPO)
    with qtbot.waitSignal(panel.phaseActivated) as blocker:
        panel.table.doubleClicked.emit(panel.table.model().index(1, 0))
    assert blocker.args == [result.phases[1].offset]
    assert result.phases[0].offset != result.phases[1].offset


def test_ctrl_double_click_on_a_band_emits_the_faze_offset(panel, run, qtbot):
    result = run("LiPo", **LIPO)
    qtbot.wait(50)
    p = result.phases[1]
    plot = panel.plot
    vb = plot.tplot.vb
    scene_pos = vb.mapViewToScene(pg.Point((p.start_s + p.end_s) / 2, sum(vb.viewRange()[1]) / 2))
    pos = plot.mapFromScene(scene_pos)
    at = QPoint(pos.x(), pos.y())
    ctrl = Qt.KeyboardModifier.ControlModifier
    with qtbot.assertNotEmitted(panel.phaseActivated):      # a plain double-click is the window's (maximise)
        double_click(qtbot, plot.viewport(), at)
    with qtbot.waitSignal(panel.phaseActivated, timeout=WAIT_MS) as blocker:
        double_click(qtbot, plot.viewport(), at, ctrl)
    assert blocker.args == [p.offset]


def double_click(qtbot, widget, at, modifier=Qt.KeyboardModifier.NoModifier):
    """What Qt delivers for a double click: press, release, double-click, release."""
    left = Qt.MouseButton.LeftButton
    qtbot.mousePress(widget, left, modifier, at)
    qtbot.mouseRelease(widget, left, modifier, at)
    qtbot.mouseDClick(widget, left, modifier, at)
    qtbot.mouseRelease(widget, left, modifier, at)


def test_selecting_a_row_highlights_its_band(panel, run):
    run("LiPo", **LIPO)
    panel.table.selectRow(1)
    assert panel.plot._selected == 1
    assert panel.plot.phase_at(panel.result().phases[0].start_s + 1) == 0


def test_a_new_run_replaces_a_running_one(panel, qtbot, compiled):
    panel.form.auto.setChecked(False)
    panel.set_record(compiled("LiPo"), "LiPo")
    panel.form.set_values(task="train", repetitions=255, **LIPO)
    panel.simulate()
    panel.form.set_values(task="charge")
    with qtbot.waitSignal(panel.simulationFinished, timeout=30_000) as blocker:
        panel.simulate()
    assert blocker.args[0].interpreter.params.task == "charge"
    assert panel.wait(30_000) and panel.result() is blocker.args[0]


@pytest.mark.parametrize("macro, values", [("NiMh-dV", NIMH), ("LiPo", LIPO)])
def test_renders_as_a_bottom_dock(panel, run, macro, values, tmp_path):
    """Renders at the dock's size; set ZUML_SCREENSHOT_DIR to keep the images for a look."""
    run(macro, **values)
    out_dir = os.environ.get("ZUML_SCREENSHOT_DIR") or str(tmp_path)
    for w, h in ((1400, 380), (1000, 300)):
        panel.resize(w, h)
        panel.plot._view_changed()
        image = panel.grab()
        path = os.path.join(out_dir, f"simpanel_{macro}_{w}x{h}.png")
        assert image.save(path)
        assert os.path.getsize(path) > 10_000
    assert panel.plot.width() >= 280 and panel.table.width() >= 180


def test_heat_sink_pauses_are_bands_in_the_plot_and_notes_in_the_table(panel, run):
    """Issue 11.6: a 40 °C run pauses on the heat sink; the plot, the table and the totals say so."""
    result = run("LiPo", task="discharge", ambient_c=40.0, **LIPO)
    (phase,) = result.phases
    pauses = len(phase.pauses)
    assert pauses > 5
    assert [len(item.spans()) for item in panel.plot.pause_items] == [pauses] * 3
    item = panel.plot.pause_items[0]
    assert item.spans()[0] == pytest.approx(tuple(phase.pauses[0]))
    assert item._tips[0].startswith("heat-sink pause ")
    notes = cell(panel.table, 0, NOTES_COLUMN)
    assert notes.startswith(f"heat-sink pause {pauses}x") and "charger gave 0.40 A: 5 W discharge limit" in notes
    assert f"{pauses} heat-sink pauses" in panel.totals.text()
    panel.resize(1366, 400)
    panel.grab().save("/tmp/sim_pauses.png")
    run("LiPo", task="charge", ambient_c=25.0, **LIPO)
    assert [len(item.spans()) for item in panel.plot.pause_items] == [0, 0, 0]


def test_a_charge_cut_by_its_timer_is_flagged_and_the_entered_current_warned(panel, run):
    """Issue 11.5 and 11.7: 0.2C on the -dV macro: a warning before the run, ⚠ in table and plot."""
    run("NiMh-dV", **dict(NIMH, current_a=0.4))
    assert "NiMh shows no reliable -dV below 0.3C" in panel.message_text()
    assert panel.table.is_flagged(0)
    assert TIMER_TIP in cell(panel.table, 0, REASON_COLUMN, Qt.ItemDataRole.ToolTipRole)
    assert cell(panel.table, 0, NOTES_COLUMN).startswith("timer before full: 1600 mAh put in")
    assert panel.plot.labels[0].toPlainText() == "⚠ C1: IF(tf>4h) STOP_FAZE (timer before full)"
    assert "cut by a timer before full" in panel.totals.text()
    panel.grab().save("/tmp/sim_timer.png")


def test_a_start_template_gives_the_start_values(panel, run):
    result = run("NiMh-dV", template=1, **dict(NIMH, current_a=0.1, capacity_mah=500))
    assert result.interpreter.params.template == 1
    assert result.capacity_mah == 2000 and result.interpreter.params.current_a == 1.0


def test_a_long_training_gets_a_label_per_phase_a_few_per_event_loop_turn(panel, run, qtbot):
    from zuml_studio.ui.sim.charge_plot import LABELS_PER_TURN

    result = run("LiPo", task="train", repetitions=6, **LIPO)
    assert len(result.phases) > LABELS_PER_TURN
    qtbot.waitUntil(lambda: len(panel.plot.labels) == len(result.phases), timeout=5000)
    assert band_counts(panel) == [len(result.phases)] * 3
    run("LiPo", task="charge", **LIPO)      # fewer phases: the extra labels go
    assert len(panel.plot.labels) == 2
