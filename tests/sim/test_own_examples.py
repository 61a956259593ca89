"""The app's own examples trust themselves (issue 25): every standard macro other than the seed's six
(kept verbatim, with their documented notes) and every wizard output checks without a warning and,
charged on the battery it is for, ends every phase by its own conditions with no warning sign. The
one default that may end a charge without a sign is the dT/dt of a full nickel pack: ZUML cannot
write dT/dt, the charger watches it whenever a sensor is connected, and it is a fast nickel
charge's normal end (docs/simulator.md)."""
import pytest

from zuml_studio import data
from zuml_studio.lang.compiler import compile_source
from zuml_studio.sim.interpreter import StartParams
from zuml_studio.sim.reasons import end_advice
from zuml_studio.sim.simulate import simulate
from zuml_studio.ui.sim.params_form import DEFAULTS
from zuml_studio.wizard import Answers, new_macro

SEED = {"LiFe", "LiIon", "LiPo", "NiCd", "NiMh", "Pb"}
OWN = [p for p in data.standard_macros() if p.stem not in SEED]
WIZARD = [("NiMh", 4, 2000), ("NiCd", 4, 1000), ("Pb", 6, 7000), ("LiPo", 3, 2200), ("LiIon", 1, 5000),
          ("LiFe", 4, 2300), ("NiMh", 1, 800), ("LiPo", 6, 5000)]


def _warnings(text: str) -> list[str]:
    return [f"{d.code}: {d.message}" for d in compile_source(text).diagnostics if d.is_error or d.is_warning]


def _flagged(run) -> list[str]:
    return [f"{p.section} {p.index}: {p.reason} ({end_advice(p)})" for p in run.phases if p.warns]


def test_the_standard_macros_beyond_the_seed_are_there():
    assert {p.stem for p in OWN} == {"NiMh-dV", "NiCd-dV", "LiIon-CCCV", "LiFe-CCCV", "Pb-float"}


@pytest.mark.parametrize("path", OWN, ids=[p.stem for p in OWN])
@pytest.mark.parametrize("sensor", [True, False], ids=["sensor", "no-sensor"])
def test_a_standard_macro_charges_clean_with_the_panels_start_values(path, sensor):
    text = path.read_text(encoding="utf-8")
    assert _warnings(text) == []
    start = StartParams("charge", 1, DEFAULTS["capacity_mah"], DEFAULTS["current_a"], None, DEFAULTS["series"], sensor)
    run = simulate(compile_source(text).record, start)
    assert run.phases and _flagged(run) == []


@pytest.mark.parametrize("chemistry,series,mah", WIZARD, ids=[f"{c}-{s}S-{m}" for c, s, m in WIZARD])
@pytest.mark.parametrize("sensor", [True, False], ids=["sensor", "no-sensor"])
@pytest.mark.parametrize("task", ["charge", "discharge", "train"])
def test_a_wizard_macro_runs_clean_on_the_battery_it_declares(chemistry, series, mah, sensor, task):
    text = new_macro(Answers(chemistry, series, mah, None, sensor))
    assert _warnings(text) == []
    run = simulate(compile_source(text).record, StartParams(task, 1, None, None, None, None, sensor))
    assert run.phases and _flagged(run) == []


def test_the_nimh_dv_macro_at_1c_with_a_sensor_ends_full_by_the_chargers_dtdt_and_says_why():
    """The model (and the dT/dt method it follows) warms a full NiMH pack at 1C by 1 °C/min minutes
    before its -dV: the end is the charger's, shown without a warning sign and explained."""
    text = (data.standard_macros_dir() / "NiMh-dV.zuml").read_text(encoding="utf-8")
    run = simulate(compile_source(text).record, StartParams("charge", 1, 2000, 2.0, None, 4, True))
    (phase,) = run.phases
    assert phase.reason == "default: dT/dt>1C/min" and phase.full_by_dtdt and not phase.warns
    assert "the pack was full" in end_advice(phase)


def test_a_default_that_ends_a_charge_early_is_flagged_with_its_fix():
    """A charge with no end of its own: the 1.5 x capacity guard ends it, with a warning and the fix."""
    text = "MACRO M\n AKK_TYPE=NiMh\n CHARGE_SECTION\n  FAZE\n   CONSTANT_I=1C\n  END_FAZE\n END_SECTION\nEND_MACRO\n"
    run = simulate(compile_source(text).record, StartParams("charge", 1, 2000, None, None, 4, False))
    (phase,) = run.phases
    assert phase.reason == "default: capacity 1.5x" and phase.warns
    assert "-dV (IF(DELTA_PEAK>0.01S)) for nickel" in end_advice(phase)


def test_a_timer_is_before_full_by_the_packs_state_not_by_one_phases_charge():
    """A top-up after a full charge puts little in and ends by its timer: the pack is full, no sign.
    A timer that ends a charge half way is flagged."""
    full = new_macro(Answers("NiMh", 4, 2000, None, False))         # -dV, then a 2 h trickle top-up
    run = simulate(compile_source(full).record, StartParams("charge", 1, None, None, None, None, False))
    assert run.phases[-1].reason == "IF(tf>2h) STOP_FAZE" and not run.phases[-1].timer_before_full
    short = "MACRO M\n AKK_TYPE=NiMh\n CHARGE_SECTION\n  FAZE\n   CONSTANT_I=0.5C\n   IF(tf>1h) STOP_FAZE\n" \
            "  END_FAZE\n END_SECTION\nEND_MACRO\n"
    run = simulate(compile_source(short).record, StartParams("charge", 1, 2000, None, None, 4, False))
    assert run.phases[0].timer_before_full and run.phases[0].warns
    assert "give the timer more time" in end_advice(run.phases[0])
