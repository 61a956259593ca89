"""Issue 11.5: the values entered at start are checked before a run (warnings, never a refusal)."""
from simhelp import record_of
from zuml_studio.sim.charger_model import load_charger
from zuml_studio.sim.interpreter import StartParams
from zuml_studio.sim.start_check import start_warnings


def test_minus_dv_unreliable_at_the_entered_current():
    record = record_of("NiMh-dV")
    (w,) = start_warnings(record, StartParams("charge", 1, 2000, 0.4, None, 4))
    assert w == ("charge phase 1: 0.40 A is 0.20C of 2000 mAh; NiMh shows no reliable -dV below 0.3C (0.60 A): "
                 "a timer or a default will end this charge")
    assert start_warnings(record, StartParams("charge", 1, 2000, 1.0, None, 4)) == []
    (w,) = start_warnings(record_of("NiCd-dV"), StartParams("charge", 1, 2000, 0.8, None, 4))
    assert "NiCd shows no reliable -dV below 0.5C (1.00 A)" in w


def test_a_current_above_the_chargers_limit():
    record = record_of("LiPo")
    found = start_warnings(record, StartParams("train", 1, 2000, 6.0, None, 3), load_charger("imax_b6"))
    assert found == ["discharge phase 1: asks 2.00 A; the iMAX B6 gives at most 1 A (discharge)",
                     "charge phase 1: asks 6.00 A; the iMAX B6 gives at most 5 A (charge)"]


def test_nothing_to_say_when_a_value_is_missing_or_the_record_is_broken():
    assert start_warnings(record_of("NiMh-dV"), StartParams()) == []
    assert start_warnings(b"\x00garbage", StartParams()) == []
