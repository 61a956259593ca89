"""A macro against a real log (sim/compare.py): the start the log implies, a charger that can do
what the log's charger did, and each charge's own peak."""
import numpy as np
import pytest

from helpers import MACROS, ROOT
from zuml_studio.lang.compiler import compile_source
from zuml_studio.sim.compare import compare, log_charger, real_end, start_setup
from zuml_studio.sim.curve import read_curve
from zuml_studio.sim.fit_report import figure_lines

CURVES = ROOT / "tests" / "data" / "curves"


def record(name: str) -> bytes:
    return compile_source((MACROS / f"{name}.zuml").read_text()).record


def test_without_a_capacity_the_pack_is_what_the_logs_charge_implies():
    # The 406DUO pack starts at 3.73 V per cell, about a third full: 1113 mAh filled the rest.
    curve = read_curve(CURVES / "lipo_4s_406duo_3c.csv")
    soc, _ = start_setup(curve, "LiPo", 4)
    result = compare(curve, record("LiPo"), None, 4, None)
    assert 0.1 < soc < 0.6
    assert result.sim.capacity_mah == pytest.approx(curve.mah[-1] / (1 - soc), abs=1)


def test_the_simulated_charger_delivers_the_logs_current_and_power():
    # 6 A into a 5S pack is 126 W: a B6's 50 W would have run the macro at 2.4 A.
    curve = read_curve(CURVES / "lipo_5s_x8_27c.csv")
    limits = log_charger(curve, "imax_b6")
    assert limits.max_charge_w >= float((curve.v * curve.i).max())
    assert limits.max_charge_a >= float(curve.i.max())
    result = compare(curve, record("LiPo"), None, 5, None)
    first_phase = result.sim.log.arrays()["current_a"][:600]
    assert np.median(first_phase) == pytest.approx(result.sim.interpreter.params.current_a, rel=0.02)


def test_a_small_logs_charger_keeps_the_b6_limits():
    limits = log_charger(read_curve(CURVES / "nimh_4s_akkumaster_02c.csv"), "imax_b6")
    assert (limits.max_charge_a, limits.max_charge_w) == (5.0, 50.0)


def test_each_peak_is_read_over_its_own_charge():
    # The default model fills the Polaron pack later than the log: its peak lies past the log's end,
    # where a peak read over the common time could only find the log's last sample.
    curve = read_curve(CURVES / "nimh_5s_polaron_03c.csv")
    result = compare(curve, record("NiMh-dV"), None, 5, None)
    peak, model_end = result.report["peak"], result.report["ends"]["model"]
    assert peak["model_mah"] > curve.mah[-1]
    assert peak["model_dv_mv_per_cell"] > 1.0
    assert model_end["mah"] >= peak["model_mah"]


def test_the_real_end_says_why_in_english_for_the_report_and_in_the_users_language_when_shown():
    curve = read_curve(CURVES / "nimh_4s_estation_1c.csv")
    end = real_end(curve, "NiMh", 4)
    assert end["kind"] == "dv" and end["why"] == f"voltage {end['values']['drop']} mV per cell below its peak (-dV)"
    report = {"rmse_v_per_cell_mv": 1.0, "rmse_i_cv_pct": None, "peak": None, "temp_rise": None,
              "ends": {"real": end, "model": {"time_s": 60.0, "mah": 10.0, "why": "default: dT/dt>1C/min"}}}
    lines = figure_lines(report)
    assert lines[-2].endswith(end["why"]) and lines[-1].endswith("default: dT/dt>1C/min")


def test_a_lipo_charge_ends_by_its_macro_not_by_the_default_temperature_rise():
    # Was: the LiPo model rose 9 °C in 6 minutes at 3C (its heat capacity a bare cell's) and the
    # default dT/dt > 1 °C/min ended the charge; the recordings' sensors rose 2.1 and 2.4 °C in all.
    curve = read_curve(CURVES / "lipo_4s_406duo_3c.csv")
    result = compare(curve, record("LiPo"), None, 4, None)
    assert not result.report["ends"]["model"]["why"].startswith("default:")
    assert result.report["temp_rise"]["model_c"] == pytest.approx(result.report["temp_rise"]["real_c"], abs=2.0)
