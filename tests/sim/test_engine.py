"""The C simulation engine (sim/engine.py, firmware/host/engine.c) against the Python interpreter, the
reference: on the same start, the same phases (every field: section, index, repetition, offset, start and
end, reason, charge counts, end state, pauses, clip, cells, balancer), the same events, the same totals
and the same sample log, bit for bit (the C models do the Python's double operations in its order)."""
import numpy as np
import pytest
from hypothesis import HealthCheck, event, given, settings

from differential_cases import ACCEPTANCE, ISSUE_11, runs
from helpers import MACROS, compiled
from zuml_studio.sim import engine
from zuml_studio.sim.interpreter import Measurement, StartError, StartParams
from zuml_studio.sim.simulate import BatterySetup, EngineError, prepare, simulate

pytestmark = pytest.mark.skipif(engine.library() is None, reason=f"{engine.missing_text()}")

LIBRARY_MACROS = sorted(p.stem for p in MACROS.glob("*.zuml"))


def both(record, params, setup=BatterySetup(), tick_s=1.0, limit_s=None, measurement=Measurement()):
    """Runs the reference and the engine; asserts every result equal; returns the reference's interpreter
    (None when both refused the start, with the same StartError)."""
    try:
        ref = prepare(record, params, setup, tick_s=tick_s, measurement=measurement).interpreter
    except StartError as exc:
        with pytest.raises(StartError) as again:
            prepare(record, params, setup, tick_s=tick_s, measurement=measurement)
        assert str(again.value) == str(exc)
        return None
    mine = prepare(record, params, setup, tick_s=tick_s, measurement=measurement).interpreter
    if limit_s is not None:
        ref.limit_s = mine.limit_s = limit_s
    assert engine.unavailable(mine) is None
    ref.run()
    engine.run(mine)
    where = f"tick {tick_s}s, {params}, {setup}"
    assert [(p.section, p.index, p.repetition, p.cycle_pass, p.offset, p.start_s, p.end_s, p.reason)
            for p in mine.phases] == [(p.section, p.index, p.repetition, p.cycle_pass, p.offset, p.start_s, p.end_s,
                                       p.reason) for p in ref.phases], where
    assert mine.phases == ref.phases, where
    assert mine.events == ref.events, where
    assert (mine.time_s, mine.q_in, mine.q_out, mine.end_reason, mine.finished) == \
           (ref.time_s, ref.q_in, ref.q_out, ref.end_reason, ref.finished), where
    a, b = mine.log.arrays(), ref.log.arrays()
    assert list(a) == list(b)
    for name in b:
        assert np.array_equal(a[name], b[name]), f"{where}: column {name} differs first at sample " \
                                                 f"{int(np.argmax(a[name] != b[name]))}"
    return ref


@pytest.mark.parametrize("task", ["charge", "discharge", "train"])
@pytest.mark.parametrize("name", LIBRARY_MACROS)
def test_every_library_macro_runs_the_same_in_c(name, task):
    assert both(compiled(name), StartParams(task, 2, 2000, 2.0, None, 3, True), tick_s=5.0, limit_s=12 * 3600).phases


@pytest.mark.parametrize("case", ACCEPTANCE, ids=lambda c: "-".join(map(str, c[:6])))
def test_acceptance_case_runs_the_same_in_c(case):
    name, task, capacity, series, current, sensor, soc, ambient, reps = case
    params = StartParams(task, reps, capacity, current, None, series, sensor)
    assert both(compiled(name), params, BatterySetup(None, soc, ambient)).phases


@pytest.mark.parametrize("case", sorted(ISSUE_11))
def test_issue_11_semantics_run_the_same_in_c(case):
    record, task, current, template, sensor, soc = ISSUE_11[case]
    both(record, StartParams(task, 2, 2000, current, None, 3, sensor, template), BatterySetup(None, soc),
         limit_s=12 * 3600)


def test_a_heatsink_pause_runs_the_same_in_c():
    ref = both(compiled("LiPo"), StartParams("discharge", 1, 2000, None, None, 3, True), BatterySetup(None, None, 40.0))
    assert any(p.pauses for p in ref.phases)


def test_a_clipped_current_runs_the_same_in_c():
    record = compiled("MACRO T\nAKK_TYPE=LiPo SERIES=3\nDISCHARGE_SECTION\nFAZE CONSTANT_I=3A IF(V<3.3S) STOP_FAZE "
                      "END_FAZE\nEND_SECTION\nCHARGE_SECTION\nEND_SECTION\nEND_MACRO\n")
    ref = both(record, StartParams("discharge", 1, 2000, None, None, 3, True))
    assert ref.phases[0].clip_limit and ref.phases[0].clipped_s > 0


@pytest.mark.parametrize("charger, series, spread, weak", [
    ("imax_b6", 3, (3.0, 10.0, 2.0), 0.0),
    ("imax_b6", 4, None, 20.0),
    ("imax_b6", 6, (10.0, 30.0, 10.0), 10.0),
    ("icharger_406duo", 12, (3.0, 10.0, 2.0), 0.0),
    ("icharger_406duo", 12, (5.0, 20.0, 5.0), 15.0),
])
@pytest.mark.parametrize("task", ["charge", "discharge", "train"])
def test_unequal_cells_and_the_balancer_run_the_same_in_c(charger, series, spread, weak, task):
    setup = BatterySetup(charger=charger, cell_spread=spread, weak_cell_pct=weak, seed=3)
    ref = both(compiled("LiPo"), StartParams(task, 1, 2000, 2.0, None, series, True), setup, limit_s=12 * 3600)
    assert ref._per_cell and all(len(p.cells_end) == series for p in ref.phases)


def test_the_balancer_ceiling_ends_a_charge_the_same_in_c():
    # no IF(V>...) that would end the charge first: a cell of the weak pack reaches the ceiling
    record = compiled("MACRO T\nAKK_TYPE=LiPo SERIES=4\nCHARGE_SECTION\nFAZE CONSTANT_I=1C IF(tf>3h) STOP_FAZE "
                      "END_FAZE\nEND_SECTION\nEND_MACRO\n")
    ref = both(record, StartParams("charge", 1, 2000, None, None, 4, True), BatterySetup(weak_cell_pct=20.0))
    assert ref.phases[0].reason.startswith("balancer: cell 4 reached")


def test_the_simulation_limit_and_a_quantised_reading_run_the_same_in_c():
    ref = both(compiled("NiMh-dV"), StartParams("charge", 1, 2000, 2.0, None, 4, False), limit_s=1800,
               measurement=Measurement(lsb_v=0.005))
    assert ref.end_reason.startswith("limit:")


@settings(max_examples=150, deadline=None, suppress_health_check=list(HealthCheck), derandomize=True)
@given(runs())
def test_generated_macros_run_the_same_in_c(run):
    record, params, setup, tick_s = run
    ref = both(record, params, setup, tick_s, 3600)
    event("refused at start by both" if ref is None else f"ran {min(len(ref.phases), 3)} phase(s)")


def test_simulate_says_which_engine_ran_and_why_the_reference_did():
    record, params = compiled("NiMh-dV"), StartParams("charge", 1, 2000, 2.0, None, 4, False)
    assert simulate(record, params).engine == "c"
    assert simulate(record, params).to_json()["engine"] == "c"
    assert simulate(record, params, engine="python").engine == "python"
    noisy = simulate(record, params, measurement=Measurement(noise_v=0.003))
    assert noisy.engine == "python" and "noise" in noisy.engine_note
    with pytest.raises(EngineError, match="noise"):
        simulate(record, params, engine="c", measurement=Measurement(noise_v=0.003))
    assert simulate(record, params, tick_s=0.5).engine == "python"


def test_without_the_library_auto_runs_the_reference_and_c_names_the_build(monkeypatch):
    monkeypatch.setattr(engine, "_library", [None])
    record, params = compiled("NiMh-dV"), StartParams("charge", 1, 2000, 2.0, None, 4, False)
    result = simulate(record, params)
    assert result.engine == "python" and "C compiler" in result.engine_note
    with pytest.raises(EngineError, match="not built"):
        simulate(record, params, engine="c")



def test_a_run_stopped_between_chunks_ends_as_the_reference_stopped_there():
    record, params = compiled("NiMh"), StartParams("train", 3, 2000, 1.0, None, 4, False)
    mine = prepare(record, params).interpreter
    stops = []

    def on_chunk(time_s):
        stops.append(time_s)
        return "cancelled" if len(stops) == 2 else None

    engine.run(mine, on_chunk=on_chunk)
    ref = prepare(record, params).interpreter
    while ref.time_s < stops[-1]:
        ref.advance(1)
    ref.stop("cancelled")
    assert (mine.end_reason, mine.phases[-1].reason) == ("cancelled", "cancelled")
    assert mine.phases == ref.phases and mine.events == ref.events
    assert np.array_equal(mine.log.arrays()["voltage_v"], ref.log.arrays()["voltage_v"])


def test_lithium_diffusion_runs_the_same_in_c_for_a_pack_and_unequal_cells():
    # LiIon has solid-state diffusion (diffusion_tau_s): its surface state in C as in Python, in a CC-CV tail,
    # a discharge and a balanced pack of unequal cells.
    for task in ("charge", "discharge"):
        both(compiled("LiIon-CCCV"), StartParams(task, 1, 5000, 5.0, None, 1, True), limit_s=6 * 3600)
    setup = BatterySetup(charger="icharger_406duo", cell_spread=(5.0, 20.0, 5.0), weak_cell_pct=15.0, seed=3)
    ref = both(compiled("LiIon-CCCV"), StartParams("charge", 1, 3000, 3.0, None, 4, True), setup, limit_s=6 * 3600)
    assert ref._per_cell
