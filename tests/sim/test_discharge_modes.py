"""Issue 11.1: CC, CV and CC-CV hold their current in both sections, within the charger's limits."""
import pytest

from simhelp import macro, run

# 3S LiPo 2000 mAh; the iMAX B6 model: 5 A / 50 W charge, 1 A / 5 W discharge.
LIPO = dict(capacity=2000, series=3)


def lipo(charge: str = "", discharge: str = "") -> str:
    return macro(charge, discharge, intro="AKK_TYPE=LiPo")


def test_storage_discharge_cc_cv_takes_charge_out_and_ends_on_its_current():
    text = lipo(discharge="FAZE CONSTANT_I=0.5C CONSTANT_V=3.8S IF(I<0.05C) STOP_FAZE END_FAZE")
    r = run(text, "discharge", soc=1.0, **LIPO)
    (phase,) = r.phases
    assert phase.reason == "IF(I<0.05C) STOP_FAZE"
    assert phase.mah_out > 500 and phase.mah_in == 0
    assert phase.end_s > 600                          # not one tick
    a = r.log.arrays()
    assert a["current_a"].min() >= -1.0 - 1e-9       # never more than the 1 A discharge limit
    assert a["voltage_v"][-1] == pytest.approx(3 * 3.8, abs=0.05)


def test_discharge_cv_alone_is_limited_to_the_entered_current():
    text = lipo(discharge="FAZE CONSTANT_V=3.9S IF(I<0.1A) STOP_FAZE END_FAZE")
    r = run(text, "discharge", soc=1.0, current=0.3, **LIPO)
    a = r.log.arrays()
    assert a["current_a"].min() == pytest.approx(-0.3, abs=1e-6)
    assert r.phases[0].reason == "IF(I<0.1A) STOP_FAZE" and r.phases[0].mah_out > 100


def test_discharge_cc_is_clipped_by_the_charger_power_and_says_so():
    text = lipo(discharge="FAZE CONSTANT_I=1C IF(V<3.3S) STOP_FAZE END_FAZE")
    r = run(text, "discharge", soc=1.0, **LIPO)
    (phase,) = r.phases
    a = r.log.arrays()
    assert -a["current_a"].max() <= 5.0 / a["voltage_v"].min() + 1e-6
    assert phase.clip_limit == "5 W discharge limit"
    assert phase.clip_text.startswith("asked 2.00 A, charger gave 0.4")
    assert phase.clipped_s == pytest.approx(phase.end_s - phase.start_s, abs=2)


@pytest.mark.parametrize("body", ["FAZE CONSTANT_I=1C IF(V>4.1S) STOP_FAZE END_FAZE",
                                  "FAZE CONSTANT_V=4.1S IF(I<0.1A) STOP_FAZE END_FAZE",
                                  "FAZE CONSTANT_I=1C CONSTANT_V=4.1S IF(I<0.1A) STOP_FAZE END_FAZE"])
def test_charge_cc_cv_and_cc_cv_put_charge_in_within_the_limits(body):
    r = run(lipo(charge=body), current=2.0, soc=0.2, **LIPO)
    (phase,) = r.phases
    assert phase.mah_in > 800 and phase.mah_out == 0
    a = r.log.arrays()
    assert a["current_a"].max() <= 2.0 + 1e-9 and a["current_a"].min() >= 0.0
    assert not phase.clip_limit


def test_charge_clipped_by_the_charger_current_limit():
    text = macro("FAZE CONSTANT_I=3C IF(V>1.5S) STOP_FAZE END_FAZE", intro="AKK_TYPE=NiCd")
    r = run(text, capacity=2000, series=4, model="NiCd", sensor=False)
    assert r.phases[0].clip_text == "asked 6.00 A, charger gave 5.00 A: 5 A charge limit"
