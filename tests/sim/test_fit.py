"""The curve reader, the fit's pieces and the saved batteries (issue #14)."""
import json
import tomllib

import numpy as np
import pytest

from helpers import ROOT
from zuml_studio.sim.batteries import BatteryFileError, battery_names, load_battery, save_battery
from zuml_studio.sim.chemistry import load_chemistry
from zuml_studio.sim.curve import Curve, CurveError, read_curve, read_curve_csv
from zuml_studio.sim.fit import Battery, cc_current, cv_mask, fit, guess_series, simulate_curve

CURVES = ROOT / "tests" / "data" / "curves"
TRAINING = tomllib.loads((CURVES / "training.toml").read_text())


def synthetic(chem: str = "LiPo", capacity: float = 1500.0, series: int = 3) -> Curve:
    """A CC-CV charge made by the model itself: a fit must find the battery again."""
    battery = Battery(load_chemistry(chem), capacity, series)
    t = np.arange(0.0, 5400.0, 10.0)
    i = np.full(len(t), 1.5)
    pack = battery.pack(0.1, 25.0)
    v, cur = [], []
    for k in range(len(t)):
        target = battery.chem.charge_end_v * series
        a = i[k] if not cur or v[-1] < target - 1e-3 else max(0.0, pack.current_for_voltage(target, 10.0))
        v.append(pack.step(a, 10.0) if k else pack.step(a, 1e-3))
        cur.append(a)
    return Curve(t, np.array(v), np.array(cur), None, 0, "synthetic")


def test_a_fit_finds_the_capacity_of_a_model_made_charge_again():
    curve = synthetic()
    result = fit(curve, "LiPo", 3, only_capacity=True)
    assert result.params["capacity_mah"] == pytest.approx(1500, rel=0.03)
    assert result.figures["rmse_v_per_cell_mv"] < 2


def test_cv_part_is_where_the_voltage_is_held_and_the_current_falls():
    curve = synthetic()
    cv = cv_mask(curve, "LiPo")
    assert cv.any() and not cv[:10].any() and cv[-1]
    assert np.all(curve.i[cv] < 1.5)
    assert not cv_mask(curve, "NiMh").any()          # Ni charges have no voltage hold


def test_driving_by_voltage_in_cv_reproduces_the_logged_current():
    curve = synthetic()
    run = simulate_curve(Battery(load_chemistry("LiPo"), 1500.0, 3), curve, cv_mask(curve, "LiPo"), 0.1)
    assert np.max(np.abs(run.i - curve.i)) < 0.02


def test_curve_csv_round_trips_and_bad_lines_are_named():
    curve = read_curve(CURVES / "nicd_4s_akkumatik_08c.csv")
    again = read_curve_csv(curve.to_csv(), "x")
    assert np.allclose(again.v, curve.v, atol=1e-4) and again.temp is not None
    with pytest.raises(CurveError, match="data line 3"):
        read_curve_csv("time_s,voltage_v,current_a\n0,1,1\n1,x,1\n" + "".join(f"{k},1,1\n" for k in range(2, 20)))
    with pytest.raises(CurveError, match="header"):
        read_curve_csv("a,b,c\n1,2,3\n")
    with pytest.raises(CurveError, match="time must rise"):
        read_curve_csv("time_s,voltage_v,current_a\n" + "".join(f"{k % 5},1,1\n" for k in range(20)))


def test_a_file_that_is_neither_a_log_nor_a_curve_is_a_precise_error(tmp_path):
    other = tmp_path / "other.csv"
    other.write_text("nothing,here\n1,2\n")
    with pytest.raises(CurveError, match="other.csv: not a log file"):
        read_curve(other)
    notes = tmp_path / "notes.md"             # starts with '#' like a curve's comment, is neither
    notes.write_text("# My pack\n\nCharged at 1C.\n")
    with pytest.raises(CurveError, match=r"notes.md: not a log file .*; nor a curve CSV \(its header: time_s,"):
        read_curve(notes)


def test_the_longest_charge_of_a_cycle_log_is_taken():
    curve = read_curve(ROOT / "tests" / "data" / "logs" / "X6_LiFe_10-3A_Cycle_2.txt")
    assert curve.t[0] == 0 and np.all(curve.i >= 0) and curve.i.max() > 9 and 300 < curve.t[-1] < 400


def test_saved_battery_round_trips_and_is_listed(tmp_path):
    chem = load_chemistry("NiMh")
    from dataclasses import replace
    fitted = Battery(replace(chem, w0=0.05, ocv_v=tuple(v + 0.01 for v in chem.ocv_v)), 1234.0, 4)
    path = save_battery("4S 2000 NiMH receiver pack", fitted, "some.log", root=tmp_path)
    assert path.parent == tmp_path / "batteries"
    assert battery_names(tmp_path) == ["4S 2000 NiMH receiver pack"]
    again = load_battery("4S 2000 NiMH receiver pack", tmp_path)
    assert again == fitted
    doc = json.loads(path.read_text())
    assert set(doc["parameters"]) == {"w0", "ocv_v"}      # only what differs from the chemistry


def test_a_damaged_or_missing_battery_file_says_which_and_why(tmp_path):
    with pytest.raises(BatteryFileError, match="no saved battery"):
        load_battery("nope", tmp_path)
    save_battery("pack", Battery(load_chemistry("LiPo"), 1000.0, 3), root=tmp_path)
    f = tmp_path / "batteries" / "pack.json"
    doc = json.loads(f.read_text())
    doc["parameters"] = {"r0_ohm": -1.0}
    f.write_text(json.dumps(doc))
    with pytest.raises(BatteryFileError, match="r0_ohm must be > 0"):
        load_battery("pack", tmp_path)
    doc["parameters"] = {"dip_v_per_charge": -0.1}
    f.write_text(json.dumps(doc))
    with pytest.raises(BatteryFileError, match="dip_v_per_charge must be >= 0"):
        load_battery("pack", tmp_path)
    f.write_text("{not json")
    with pytest.raises(BatteryFileError, match="not a battery file"):
        load_battery("pack", tmp_path)
    assert battery_names(tmp_path) == []               # a damaged file is not offered


def test_scipy_is_imported_only_when_a_fit_runs():
    import subprocess
    import sys
    code = ("import sys, zuml_studio.cli.main, zuml_studio.sim.fit, zuml_studio.sim.compare, "
            "zuml_studio.ui.window.main_window, zuml_studio.ui.sim.compare_dialog; print('scipy' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert out.stdout.strip() == "False", out.stderr


@pytest.mark.parametrize("name", sorted(TRAINING))
def test_the_cell_count_is_guessed_right_on_every_real_charge(name):
    # The Ultramat 4S NiMH pack peaks at 1.65 V per cell: from its highest voltage it looked like 5 cells.
    entry = TRAINING[name]
    assert guess_series(read_curve(CURVES / f"{name}.csv"), entry["chemistry"]) == entry["cells"]


def test_a_nimh_logs_single_tap_is_not_taken_for_its_cell_count():
    curve = read_curve(ROOT / "tests" / "data" / "realdata" / "icharger3010B_2500NiMh_lines.txt")
    assert curve.cells == 0                     # its 5.2 V "cell 1" is no cell (logs.model.connected_cells)
    assert guess_series(curve, "NiMh") == 4


def test_a_lone_sensor_dropout_is_not_taken_for_the_packs_temperature():
    # The 308DUO log reads 0 °C for one second amid 21-23 °C.
    curve = read_curve(ROOT / "tests" / "data" / "logs" / "308DUO_LiFe_2.3Ah_Laden_0_CH1.txt")
    assert curve.temp is not None and curve.temp.min() > 15.0


def test_at_bounds_names_the_packs_size_resistance_and_ocv_only():
    from zuml_studio.sim.fit import Param, at_bounds

    params = [Param("capacity_mah", 500.0, 20000.0, True), Param("r_scale", 0.1, 10.0, True),
              Param("ocv_offset_v", -0.15, 0.15), Param("start_soc", 0.0, 0.95), Param("r2_ohm", 1e-4, 2.0, True)]
    values = {"capacity_mah": 19950.0, "r_scale": 9.98, "ocv_offset_v": 0.0, "start_soc": 0.95, "r2_ohm": 1e-4}
    assert at_bounds(params, values) == [{"name": "capacity_mah", "value": 19950.0, "bound": "upper"},
                                         {"name": "r_scale", "value": 9.98, "bound": "upper"}]


def test_a_charge_that_starts_at_its_held_voltage_has_no_cv_figure_only_a_dash_and_why():
    # The X6 LiFe top-up: 10 A for 9 s, then held at 3.60 V/cell. Its 10 A is no CC phase, and the 0.14 A its
    # first hold's edge once gave as the CC current made the CV figure "336 %".
    from zuml_studio.sim.compare import real_end
    from zuml_studio.sim.fit_report import figure_lines, quality_lines
    curve = read_curve(ROOT / "tests" / "data" / "logs" / "X6_LiFe_10-3A_Cycle_2.txt")
    result = fit(curve, "LiFe", 6, only_capacity=True)
    figures = result.figures
    assert figures["rmse_i_cv_pct"] is None and figures["no_cc_phase"]
    assert figures["quality"]["held_current"]["rmse"] is None
    assert figures["quality"]["held_current"]["note"] == "no CC phase"
    assert any("– over" in line and "no CC phase" in line for line in quality_lines(figures["quality"]))
    assert any("CV: – (no CC phase" in line for line in figure_lines(figures))
    assert real_end(curve, "LiFe", 6)["values"]["share"] == "–"       # nor the log's end a share of it


def test_a_hold_after_an_overshoot_is_measured_against_the_voltage_held():
    # The 308DUO turns to CV at a 7.29 V overshoot and holds 7.20 V: 1.2 % under that peak, the hold once ended at
    # its 560th second, and the tail that followed was taken for CC (its current 2.62 A, the charger's 3.0 A).
    curve = read_curve(ROOT / "tests" / "data" / "curves" / "life_2s_308duo_05c.csv")
    cv = cv_mask(curve, "LiFe")
    assert cv[-1] and cv[np.flatnonzero(cv)[0]:-1].sum() >= 50
    assert cc_current(curve, cv) == pytest.approx(2.995, abs=0.01)
