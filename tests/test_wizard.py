"""zuml new / the wizard: every chemistry's macro checks clean and simulates to its intended end."""
import pytest

from zuml_studio.lang.compiler import compile_source
from zuml_studio.sim.interpreter import StartParams
from zuml_studio.sim.simulate import simulate
from zuml_studio.wizard import Answers, WizardError, new_macro

CASES = [  # chemistry, cells, mAh, sensor, intended end of each charge phase
    ("NiMh", 4, 2000, False, ["IF(DELTA_PEAK>0.02V) STOP_FAZE", "IF(tf>2h) STOP_FAZE"]),
    ("NiCd", 4, 1000, False, ["IF(DELTA_PEAK>0.05V) STOP_FAZE", "IF(tf>2h) STOP_FAZE"]),
    ("Pb", 6, 7000, True, ["IF(I<0.02C) STOP_FAZE", "IF(tf>24h) STOP_FAZE"]),
    ("LiPo", 3, 2200, True, ["IF(I<0.05C) STOP_FAZE"]),
    ("LiIon", 1, 5000, True, ["IF(I<0.05C) STOP_FAZE"]),
    ("LiFe", 4, 2300, True, ["IF(I<0.05C) STOP_FAZE"]),
]


@pytest.mark.parametrize("chemistry,series,mah,sensor,ends", CASES, ids=[c[0] for c in CASES])
def test_generated_macro_checks_clean_and_charges_to_its_intended_end(chemistry, series, mah, sensor, ends):
    for with_sensor in (False, True):
        assert compile_source(new_macro(Answers(chemistry, series, mah, None, with_sensor))).diagnostics == []
    result = compile_source(new_macro(Answers(chemistry, series, mah, None, sensor)))
    run = simulate(result.record, StartParams("charge", 1, None, None, None, None, sensor))
    assert [p.reason for p in run.phases] == ends


@pytest.mark.parametrize("chemistry,series,mah", [(c[0], c[1], c[2]) for c in CASES])
def test_generated_discharge_ends_at_the_chemistry_end_voltage(chemistry, series, mah):
    record = compile_source(new_macro(Answers(chemistry, series, mah))).record
    run = simulate(record, StartParams("discharge", 1, None, None, None, None, False))
    assert run.phases[0].reason.startswith("IF(V<") and not run.phases[0].by_default


def test_a_nickel_charge_above_2c_needs_the_sensor_and_a_fast_one_states_its_temperature_end():
    with pytest.raises(WizardError, match="needs the temperature sensor"):
        new_macro(Answers("NiCd", 4, 1000, 3))
    text = new_macro(Answers("NiCd", 4, 1000, 3, True))
    assert "IF(T>45)" in text and compile_source(text).diagnostics == []
    assert "IF(T>45)" in new_macro(Answers("NiMh", 4, 2000, 1))


def test_low_rate_nickel_charge_is_timed_and_a_rate_between_is_refused():
    text = new_macro(Answers("NiMh", 4, 2000, 0.1))
    assert "DELTA_PEAK" not in text and "IF(tf>900min)" in text
    assert compile_source(text).diagnostics == []
    with pytest.raises(WizardError, match="no reliable -dV"):
        new_macro(Answers("NiMh", 4, 2000, 0.25))


@pytest.mark.parametrize("answers,needle", [(Answers("LiS", 1, 1000), "no template"),
                                            (Answers("LiPo", 0, 1000), "0 cells in series: choose 1 to 255"),
                                            (Answers("LiPo", 1, 70000), "a capacity of 70000 mAh: choose 2 to 65534"),
                                            (Answers("LiPo", 1, 1000, 9), "a charge rate of 9C: choose 0.01C to 5C")])
def test_bad_answers_get_a_precise_error_with_the_value(answers, needle):
    with pytest.raises(WizardError, match=needle):
        new_macro(answers)


def test_the_comment_counts_the_cells_in_english():
    assert "// LiPo, 1 cell, 1000 mAh" in new_macro(Answers("LiPo", 1, 1000))
    assert "// LiPo, 3 cells, 1000 mAh" in new_macro(Answers("LiPo", 3, 1000))
