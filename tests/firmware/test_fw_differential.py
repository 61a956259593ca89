"""The C core (host build) against the Python interpreter on the same battery model: the same phases
in the same order, the same end reasons, phase ends on the same tick, coulomb counts within 1 mAh."""
import pytest
from hypothesis import HealthCheck, assume, event, given, settings, strategies as st

from helpers import MACROS, compiled
from host_core import CoreRunner, python_run, start_error_category
from strategies import macros
from zuml_studio.lang.decoder import decode_record
from zuml_studio.lang.record import DecodeError, RecordTooLarge, encode
from zuml_studio.sim.interpreter import Measurement, StartError, StartParams
from zuml_studio.sim.simulate import BatterySetup

CHEMISTRIES = ("Pb", "NiCd", "NiMh", "LiPo", "LiIon", "LiFe")


def assert_same(record, params, setup, tick_s, limit_s, core, measurement=Measurement()):
    try:
        py = python_run(record, params, setup, tick_s, limit_s, measurement)
    except StartError as exc:
        c = core.run(record, params, setup, tick_s, limit_s, measurement)
        assert c.start_error == start_error_category(str(exc))
        return None
    c = core.run(record, params, setup, tick_s, limit_s, measurement)
    assert c.start_error is None
    where = f"tick {tick_s}s, {params}"
    assert [(p.section, p.index, p.repetition, p.cycle_pass, p.offset) for p in c.phases] == \
           [(p.section, p.index, p.repetition, p.cycle_pass, p.offset) for p in py.phases], where
    for mine, ref in zip(c.phases, py.phases):
        assert (mine.start_tick, mine.end_tick, mine.reason) == (ref.start_tick, ref.end_tick, ref.reason), where
        assert abs(mine.mah_in - ref.mah_in) <= 1.0 and abs(mine.mah_out - ref.mah_out) <= 1.0, (mine, ref)
    assert c.signals == py.signals, where
    assert c.end_reason == py.end_reason, where
    return py


@pytest.fixture(scope="module")
def core(core_lib):
    return CoreRunner(core_lib)


LIBRARY_MACROS = sorted(p.stem for p in MACROS.glob("*.zuml"))


def test_the_library_is_there():
    assert len(LIBRARY_MACROS) >= 10


@pytest.mark.parametrize("task", ["charge", "discharge", "train"])
@pytest.mark.parametrize("name", LIBRARY_MACROS)
def test_library_macro_runs_the_same_on_the_core(core, name, task):
    params = StartParams(task, 2, 2000, 2.0, None, 3, True)
    assert assert_same(compiled(name), params, BatterySetup(), 5.0, 12 * 3600, core).phases


# The cases of tests/sim/test_acceptance.py: (macro, task, capacity, series, current, sensor, soc, ambient, reps)
ACCEPTANCE = [
    ("NiMh-dV", "charge", 2000, 4, 2.0, False, None, 25.0, 1),
    ("NiMh-dV", "charge", 2000, 4, 2.0, True, None, 25.0, 1),
    ("NiMh", "charge", 2000, 4, 0.4, False, None, 25.0, 1),
    ("NiMh-dV", "charge", 2000, 4, 0.4, False, None, 25.0, 1),
    ("NiCd-dV", "charge", 1000, 4, 1.0, False, None, 25.0, 1),
    ("NiMh-dV", "charge", 1000, 4, 1.0, False, None, 25.0, 1),
    ("NiCd", "charge", 2000, 4, 2.0, False, None, 25.0, 1),
    ("NiMh", "charge", 2000, 4, 2.0, False, None, 25.0, 1),
    ("LiIon-CCCV", "charge", 5000, 1, 5.0, True, None, 25.0, 1),
    ("LiPo", "charge", 2000, 3, 2.0, True, None, 25.0, 1),
    ("LiFe-CCCV", "charge", 2300, 1, 2.3, True, None, 25.0, 1),
    ("Pb-float", "charge", 7000, 6, 1.75, True, 0.2, 25.0, 1),
    ("LiPo", "train", 2000, 3, 2.0, True, None, 25.0, 3),
    ("NiMh-dV", "charge", 2000, 4, 2.0, True, None, 58.0, 1),
    ("LiPo", "discharge", 2000, 3, None, True, None, 40.0, 1),
]


@pytest.mark.parametrize("case", ACCEPTANCE, ids=lambda c: "-".join(map(str, c[:6])))
def test_acceptance_case_runs_the_same_on_the_core(core, case):
    name, task, capacity, series, current, sensor, soc, ambient, reps = case
    params = StartParams(task, reps, capacity, current, None, series, sensor)
    assert assert_same(compiled(name), params, BatterySetup(None, soc, ambient), 1.0, 48 * 3600, core).phases


def test_the_heatsink_case_pauses_on_both(core):
    params = StartParams("discharge", 1, 2000, None, None, 3, True)
    py = assert_same(compiled("LiPo"), params, BatterySetup(None, None, 40.0), 1.0, 48 * 3600, core)
    assert any(s[0] == "pause" for s in py.signals)


def test_noisy_measurements_run_the_same(core):
    params = StartParams("charge", 1, 2000, 2.0, None, 4, False)
    assert_same(compiled("NiMh-dV"), params, BatterySetup(), 1.0, 48 * 3600, core, Measurement(noise_v=0.003, seed=7))


@st.composite
def runs(draw):
    try:
        record = encode(draw(macros())).record
        decode_record(record)
    except (RecordTooLarge, DecodeError):
        assume(False)
    params = StartParams(draw(st.sampled_from(["charge", "discharge", "train"])), draw(st.integers(1, 3)),
                         draw(st.sampled_from([300, 2000, 5000])),
                         draw(st.none() | st.sampled_from([0.1, 1.0, 2.5])),
                         draw(st.none() | st.sampled_from([1.3, 4.2, 12.0])),
                         draw(st.integers(1, 6)), draw(st.booleans()))
    setup = BatterySetup(draw(st.sampled_from(CHEMISTRIES)), draw(st.none() | st.sampled_from([0.5])),
                         draw(st.sampled_from([25.0, 45.0])))
    return record, params, setup, draw(st.sampled_from([10.0, 30.0]))


@settings(max_examples=2000, deadline=None, suppress_health_check=list(HealthCheck), derandomize=True)
@given(runs())
def test_generated_macros_run_the_same_on_the_core(core, run):
    record, params, setup, tick_s = run
    py = assert_same(record, params, setup, tick_s, 3600, core)
    event("refused at start by both" if py is None else f"ran {min(len(py.phases), 3)}{'+' * (len(py.phases) > 2)} phase(s)")
