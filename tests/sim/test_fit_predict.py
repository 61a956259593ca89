"""A fitted model on its own log's program (sim/fit_predict.py, issue 35 §4, issue 33 §2): the log's current and
end written as a macro, run on the simulator with the fitted battery from the fit's start state, predicts the log's
charge within 10 % and its end time within 10 %; a model that does not is said not to be trusted."""
import tomllib

import pytest

from helpers import ROOT
from zuml_studio.domain.chemistry import load_chemistry
from zuml_studio.sim.curve import read_curve
from zuml_studio.sim.fit import fit
from zuml_studio.sim.fit_checks import HEAT_PARAMS
from zuml_studio.sim.fit_discharge import fit_curve
from zuml_studio.sim.fit_predict import TRUST_PCT, own_program, predict_own, trust_words

CURVES = ROOT / "tests" / "data" / "curves"
TRAINING = tomllib.loads((CURVES / "training.toml").read_text())
LIMIT_PCT = 10.0
# What the model cannot reach yet, and why (docs/fit.md "Its own program").
MISSES = {
    "nimh_4s_akkumaster_02c": "the log's end is no -dV a program can state: its own 1-minute voltage falls the 19.2 mV "
                              "(4.8 mV/cell) it ends below its peak at 788 mAh, 52 min before the charger stopped at "
                              "918 mAh, so its DELTA_PEAK>0.02V ends the log itself 14 % short; the model, whose fall "
                              "is 3.4 mV/cell, never reaches 20 mV and its 1.5x capacity limit ends it 14 % on "
                              "(docs/fit.md \"Its own program\")",
}


@pytest.mark.parametrize("name", [pytest.param(n, marks=pytest.mark.xfail(reason=MISSES[n], strict=True))
                                  if n in MISSES else n for n in sorted(TRAINING)])
def test_the_fitted_model_predicts_its_own_logs_charge_and_end(name):
    entry = TRAINING[name]
    result = fit_curve(read_curve(CURVES / f"{name}.csv"), entry["chemistry"], entry["cells"])
    prediction = predict_own(result)
    assert prediction is not None
    assert abs(prediction["charge_error_pct"]) <= LIMIT_PCT, prediction
    assert abs(prediction["time_error_pct"]) <= LIMIT_PCT, prediction


def test_the_program_is_the_logs_current_and_its_end():
    result = fit(read_curve(CURVES / "nimh_4s_estation_1c.csv"), "NiMh", 4, only_capacity=True)
    text, params = own_program(result)
    # Its 12.1 mV/cell drop, 48 mV on the pack, to the hundredth the byte code keeps; no probe in the log.
    assert "CONSTANT_I=INPUT" in text and "IF(DELTA_PEAK>0.05V) STOP_FAZE" in text
    assert (params.task, params.current_a, params.series, params.sensor) == ("charge", 1.0, 4, False)
    result = fit(read_curve(CURVES / "lipo_4s_406duo_3c.csv"), "LiPo", 4, only_capacity=True)
    text, params = own_program(result)
    assert "CONSTANT_V=16.77V" in text and "IF(I<0.574A) STOP_FAZE" in text and params.sensor
    # The Akkumatik NiCd discharge's charger held its end voltage and stepped its current down: so does the program.
    result = fit_curve(read_curve(CURVES / "nicd_4s_akkumatik_dis_1c.csv"), "NiCd", 4)
    text, params = own_program(result)
    assert "IF(V<3.44V) STOP_FAZE" in text and "CONSTANT_V=3.44V" in text and "IF(I<0.205A) STOP_FAZE" in text
    assert (params.task, params.current_a) == ("discharge", 0.998)


def test_heat_terms_are_not_fitted_without_a_probe():
    # The eStation NiMH log has no temperature: its heat loss went to its bound and the model warmed 20 °C at
    # 1 A, a charge its -dV macro then ended by dT/dt after 35 min (600 mAh of the log's 1000).
    curve = read_curve(CURVES / "nimh_4s_estation_1c.csv")
    assert curve.temp is None
    result = fit(curve, "NiMh", 4)
    chem = load_chemistry("NiMh")
    assert not set(HEAT_PARAMS) & set(result.params)
    assert (result.battery.chem.ha_w_per_k, result.battery.chem.cth_j_per_k, result.battery.chem.k_t_v_per_k) == (
        chem.ha_w_per_k, chem.cth_j_per_k, chem.k_t_v_per_k)
    prediction = predict_own(result)
    assert prediction["why"].startswith("IF(DELTA_PEAK") and prediction["ended_by"] == "own_end"
    # ... and with a sensor on the pack, as the simulator runs a macro by default, the charger's dT/dt end comes
    # only once the model is full (its fitted capacity in: 800 of 769 mAh; with the heat terms fitted to the voltage
    # it came at 583 of 785 mAh, three quarters full).
    prediction = predict_own(result, sensor=True)
    assert prediction["model_mah"] >= result.params["capacity_mah"]


def test_a_prediction_far_off_says_not_to_trust_the_model_and_why():
    far = {"real_mah": 2800.0, "model_mah": 617.0, "charge_error_pct": -78.0, "real_s": 10000.0, "model_s": 1080.0,
           "time_error_pct": -89.2, "trusted": False, "why": "IF(DELTA_PEAK>0.04V) STOP_FAZE", "ended_by": "own_end"}
    words = trust_words(far)
    assert "do not trust" in words and "617" in words and "2800" in words and "-78 %" in words
    assert "ends there after 18 min: IF(DELTA_PEAK>0.04V)" in words and f"{TRUST_PCT:g} %" in words
    assert "never reaches the log's own end" in trust_words({**far, "ended_by": "backup"})
    assert "the charger's own limit ends it" in trust_words({**far, "ended_by": "charger", "why": "default: T>60"})
    assert trust_words({**far, "trusted": True}) is None and trust_words(None) is None
