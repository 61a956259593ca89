"""Simulate > Compare with Log… (issue #14): overlay, difference, Fit, Save Battery, Model box."""
import pytest

import helpers

CURVES = helpers.ROOT / "tests" / "data" / "curves"


@pytest.fixture
def dialog(qtbot, monkeypatch, tmp_path):
    monkeypatch.setenv("ZUML_STUDIO_CONFIG_DIR", str(tmp_path))
    from zuml_studio.ui.sim.compare_dialog import CompareDialog

    d = CompareDialog(lambda: helpers.compiled("LiPo"))
    qtbot.addWidget(d)
    d.chemistry.setCurrentIndex(d.chemistry.findData("LiPo"))
    d.show()
    return d


def curves_of(plot):
    return [item for item in plot.listDataItems()]


def wait_for(qtbot, dialog, action):
    """Fit and Simulate run off the GUI thread: their figures arrive with workDone."""
    with qtbot.waitSignal(dialog.workDone, timeout=120_000):
        action()


def test_log_and_simulation_on_the_same_axes_with_their_difference(dialog, qtbot):
    assert dialog.load_log(str(CURVES / "lipo_4s_406duo_3c.csv"))
    assert dialog.cells.value() == 4
    dialog.capacity.setValue(1500)
    wait_for(qtbot, dialog, dialog.compare_macro)
    assert len(curves_of(dialog.v_plot)) == 2 and len(curves_of(dialog.d_plot)) == 1
    text = dialog.figures.text()
    assert "RMSE voltage" in text and "real ended" in text and "model ended" in text


def test_fit_draws_the_fitted_model_and_save_offers_it_in_the_model_box(dialog, tmp_path, qtbot):
    from zuml_studio.ui.sim.params_form import ParamsForm

    dialog.load_log(str(CURVES / "lipo_4s_406duo_3c.csv"))
    assert not dialog.save_button.isEnabled()
    wait_for(qtbot, dialog, dialog.fit_log)
    assert dialog.save_button.isEnabled()
    # 3.83 -> 4.20 V/cell covers under half the pack: its capacity is said not fixed, not given (issue 35 §2).
    assert "capacity not fixed by this log" in dialog.figures.text() and "fitted: capacity " not in dialog.figures.text()
    assert "fitted: internal resistance" in dialog.figures.text()
    # What the fitted model predicts on the log's own program, next to the log (issue 35 §4): it follows it.
    assert "On its own log's program: 1116 mAh predicted, 1112 mAh logged (+0.3 %)" in dialog.figures.text()
    assert "do not trust" not in dialog.figures.text()
    assert len(curves_of(dialog.v_plot)) == 2
    assert dialog.save_as("4S 1500 LiPo")
    form = ParamsForm()
    index = form.model.findData("battery:4S 1500 LiPo")
    assert index > 0 and form.model.itemText(index) == "4S 1500 LiPo (fitted)"
    form.model.setCurrentIndex(index)
    setup = form.battery_setup()
    assert setup.battery == "4S 1500 LiPo" and setup.chemistry is None
    form.deleteLater()


def test_a_file_that_is_not_a_log_is_said_in_the_dialog(dialog, tmp_path):
    bad = tmp_path / "x.csv"
    bad.write_text("hello\n")
    assert not dialog.load_log(str(bad))
    assert "not a log file" in dialog.figures.text()
    assert not dialog.fit_button.isEnabled()


def test_main_window_has_the_menu_entry(make_window):
    window = make_window()
    texts = [a.text() for a in window.menuBar().actions()]
    sim_menu = window.menuBar().actions()[texts.index("&Simulate")].menu()
    assert "Compare with &Log…" in [a.text() for a in sim_menu.actions()]
    dialog = window.compare_with_log()
    assert dialog.isVisible()
    dialog.close()


def test_a_saved_battery_reaches_the_virtual_charger_box_and_the_charger(make_window, monkeypatch, tmp_path, qtbot):
    monkeypatch.setenv("ZUML_STUDIO_CONFIG_DIR", str(tmp_path))
    from zuml_studio.device.virtual_charger import BatterySpec
    from zuml_studio.sim.batteries import save_battery
    from zuml_studio.sim.chemistry import load_chemistry
    from zuml_studio.sim.fit import Battery

    window = make_window()
    dialog = window.compare_with_log()
    assert dialog.chemistry.currentData() == "NiMh"        # no run yet: the default
    dialog.chemistry.setCurrentIndex(dialog.chemistry.findData("LiPo"))
    dialog.load_log(str(CURVES / "lipo_4s_406duo_3c.csv"))
    wait_for(qtbot, dialog, dialog.fit_log)
    assert dialog.save_as("4S 1500 LiPo")
    box = window.device_panel.v_chem
    box.setCurrentIndex(box.findData("battery:4S 1500 LiPo"))
    assert window.device_panel.virtual_battery() == "battery:4S 1500 LiPo"
    spec = BatterySpec.parse("battery:4S 1500 LiPo")
    assert spec.chemistry == "LiPo" and spec.cells == 4 and str(spec) == "battery:4S 1500 LiPo"
    assert spec.model() == dialog.fitted.battery.chem
    save_battery("plain", Battery(load_chemistry("NiMh"), 2000.0, 4))
    dialog.close()


def test_a_log_that_names_its_battery_type_sets_the_chemistry(dialog):
    dialog.chemistry.setCurrentIndex(dialog.chemistry.findData("Pb"))
    assert dialog.load_log(str(helpers.ROOT / "tests" / "data" / "logs" / "308DUO_LiFe_2.3Ah_Laden_0_CH1.txt"))
    assert dialog.chemistry.currentData() == "LiFe" and dialog.cells.value() == 2


def test_fit_runs_off_the_gui_thread_and_a_failed_fit_is_said(dialog, qtbot, monkeypatch):
    import threading

    from zuml_studio.ui.sim import compare_dialog

    dialog.load_log(str(CURVES / "lipo_4s_406duo_3c.csv"))
    ran_on = []

    def failing_fit(*args):
        ran_on.append(threading.current_thread())
        raise ValueError("the optimiser found no fit")
    monkeypatch.setattr(compare_dialog, "fit_curve", failing_fit)
    wait_for(qtbot, dialog, dialog.fit_log)
    assert ran_on and ran_on[0] is not threading.main_thread()
    assert "the optimiser found no fit" in dialog.figures.text()
    assert dialog.fit_button.isEnabled() and not dialog.save_button.isEnabled()


def test_the_cell_count_follows_the_chosen_chemistry(dialog):
    # A curve CSV names no chemistry: read as NiMH the 4S LiPo pack would be 11 cells.
    dialog.chemistry.setCurrentIndex(dialog.chemistry.findData("NiMh"))
    assert dialog.load_log(str(CURVES / "lipo_4s_406duo_3c.csv"))
    assert dialog.cells.value() == 11
    dialog.chemistry.setCurrentIndex(dialog.chemistry.findData("LiPo"))
    assert dialog.cells.value() == 4


def test_a_gap_in_the_log_is_not_drawn_and_has_no_difference(dialog, tmp_path):
    """The real iCharger 3010B charge with a 3.2 h hole (tests/logs/logdata.py): the longest
    charge stops at the hole; a curve across it (as a plain curve CSV may hold) has its line
    and the model's difference broken there."""
    import dataclasses
    import math
    import sys

    import numpy as np
    sys.path.insert(0, str(helpers.ROOT / "tests" / "logs"))
    from logdata import GAP_AFTER_LINE, GAP_S, gapped_3010b_lov
    from zuml_studio.logs import read_log

    path = tmp_path / "gapped_3010b.lov"
    path.write_bytes(gapped_3010b_lov())
    assert dialog.load_log(str(path))
    assert len(dialog.curve.t) == GAP_AFTER_LINE + 1
    before, after = 2.0 * GAP_AFTER_LINE / 60, (2.0 * (GAP_AFTER_LINE + 1) + int(GAP_S)) / 60
    d = read_log(gapped_3010b_lov()).arrays()
    dialog.curve = dataclasses.replace(dialog.curve, t=d["t"], v=d["voltage"], i=d["current"], temp=None)
    t = dialog.curve.t
    dialog._draw(t, dialog.curve.v * 1.01, "model")          # a model line at the log's own times
    for plot in (dialog.v_plot, dialog.d_plot):
        for item in curves_of(plot):
            x, y = item.getData()
            joins = [k for k in range(len(x) - 1) if math.isfinite(y[k]) and math.isfinite(y[k + 1])
                     and x[k] <= before and x[k + 1] >= after]
            assert joins == [] and np.isnan(y).any()


def test_fit_with_a_cell_count_the_charge_cannot_have_is_refused_at_once(dialog, qtbot):
    dialog.chemistry.setCurrentIndex(dialog.chemistry.findData("NiMh"))
    assert dialog.load_log(str(CURVES / "nimh_4s_ultramat_05c.csv"))
    dialog.cells.setValue(5)
    wait_for(qtbot, dialog, dialog.fit_log)
    text = dialog.figures.text()
    assert "5 cells do not fit this charge" in text and "--cells 4" in text and dialog.fitted is None


@pytest.mark.parametrize("action", ["fit_log", "compare_macro"])
def test_a_discharge_log_is_fitted_and_compared_as_a_discharge(dialog, qtbot, action, monkeypatch):
    # issue 27: an AkkuMaster "Entladen" export (no direction column) was fitted as a charge; issue 26:
    # it is a discharge, fitted and compared as one
    dialog._record = lambda: helpers.compiled("NiMh")
    dialog.chemistry.setCurrentIndex(dialog.chemistry.findData("NiMh"))
    assert dialog.load_log(str(helpers.ROOT / "tests" / "data" / "logs" /
                               "AkkuMasterC4_2007-12-28-EmpfaengerAA4-Entladen.csv"))
    assert "158 min of discharge, 396 mAh out" in dialog.log_label.text()
    wait_for(qtbot, dialog, getattr(dialog, action))
    text = dialog.figures.text()
    assert "of the discharge" in text and "delivered 395.8 mAh (real)" in text, text
    assert len(curves_of(dialog.v_plot)) == 2
    if action == "fit_log":
        # its pack steps down by one cell's voltage at 362 mAh: the fit finds the weak cell, Save keeps it
        assert "a weak cell: one cell holds " in text, text
        assert dialog.save_as("AkkuMaster weak cell")
        from zuml_studio.sim.batteries import load_battery_cells
        _battery, cells = load_battery_cells("AkkuMaster weak cell")
        assert len(cells) == 4 and cells[3].capacity_mah < cells[0].capacity_mah == cells[2].capacity_mah


def test_simulate_macro_takes_the_resistance_from_the_logs_rests_and_says_so(dialog, qtbot):
    # issue 26, decision (a): the eStation BC6 pauses its 1 A charge every minute
    dialog._record = lambda: helpers.compiled("NiMh")
    dialog.chemistry.setCurrentIndex(dialog.chemistry.findData("NiMh"))
    assert dialog.load_log(str(helpers.ROOT / "tests" / "data" / "logs" / "eStationBC6_2008-07-05_EmpfaengerAA.osd"))
    dialog.cells.setValue(4)
    wait_for(qtbot, dialog, dialog.compare_macro)
    first = dialog.figures.text().splitlines()[0]
    assert first == "resistance 125 mΩ/cell measured at 34 rests from 2:37:38", first


def test_a_cycle_logs_discharge_is_chosen_and_fitted_on_its_own(dialog, qtbot):
    dialog.chemistry.setCurrentIndex(dialog.chemistry.findData("NiMh"))
    log = str(helpers.ROOT / "tests" / "data" / "logs" / "eStationBC6_2008-07-05_EmpfaengerAA.osd")
    assert dialog.load_log(log)
    assert dialog.direction.isEnabled() and dialog.direction.currentData() == "charge"
    assert "min of charge" in dialog.log_label.text()
    dialog.direction.setCurrentIndex(dialog.direction.findData("discharge"))
    dialog.direction.activated.emit(dialog.direction.currentIndex())        # as a user's choice does
    assert dialog.curve.direction == "discharge" and "min of discharge" in dialog.log_label.text()
    wait_for(qtbot, dialog, dialog.fit_log)
    assert "delivered" in dialog.figures.text() and dialog.fitted.figures["direction"] == "discharge"
    assert dialog.load_log(str(CURVES / "lipo_4s_406duo_3c.csv"))
    assert not dialog.direction.isEnabled()                 # a curve CSV holds one direction


def test_a_log_with_a_balance_tap_per_cell_shows_its_cells_in_the_pack_cells_hues(dialog, qtbot):
    from zuml_studio.ui.base import theme
    logs = helpers.ROOT / "tests" / "data" / "logs"
    assert dialog.load_log(str(logs / "406DUO_Turnigy_4S_1500_A_Charge_0_CH1.txt"))
    assert dialog.cells.value() == 4
    names = [item.name() for item in curves_of(dialog.v_plot)]
    assert names == ["cell 1", "cell 2", "cell 3", "cell 4", "log"]     # under the pack's line
    hues = theme.colours(dialog.plots.palette()).plot.pack_cells
    assert [item.opts["pen"].color().name() for item in curves_of(dialog.v_plot)[:4]] == list(hues[:4])
    wait_for(qtbot, dialog, dialog.compare_macro)
    assert [item.name() for item in curves_of(dialog.v_plot)][-2:] == ["log", "simulation"]
    dialog.cells.setValue(3)                      # taps that are not one per cell of the pack: no cells drawn
    dialog._draw(None, None, "")
    assert [item.name() for item in curves_of(dialog.v_plot)] == ["log"]


def test_a_log_without_taps_draws_no_cells(dialog):
    assert dialog.load_log(str(CURVES / "lipo_4s_406duo_3c.csv"))
    assert [item.name() for item in curves_of(dialog.v_plot)] == ["log"]
