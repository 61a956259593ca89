"""The interpreter's semantics (spec §3), one behaviour per test."""
import numpy as np
import pytest

from simhelp import macro, record_of, run, start
from zuml_studio.lang.compiler import compile_source
from zuml_studio.sim.interpreter import StartError
from zuml_studio.sim.program import CommandStep, DefaultDischarge, PhaseCode, Program

CC_TO_V = "FAZE CONSTANT_I=1C IF(V>1.40S) STOP_FAZE END_FAZE"
DIS_TO_V = "FAZE CONSTANT_I=0.5C IF(V<1.10S) STOP_FAZE END_FAZE"


def test_program_walks_the_bytes_per_task():
    prog = Program(record_of(macro(CC_TO_V, DIS_TO_V, tail="MUSIC(STOP)")))
    kinds = lambda task, n=1: [type(s).__name__ for s in prog.steps(task, n)]
    assert kinds("charge") == ["SectionStart", "PhaseCode", "CommandStep"]
    assert kinds("discharge") == ["SectionStart", "PhaseCode", "CommandStep"]
    assert kinds("train", 2) == ["SectionStart", "PhaseCode", "SectionStart", "PhaseCode"] * 2 + ["CommandStep"]


def test_cycle_repeats_its_phases_and_keeps_their_index():
    body = "CYCLE(3) FAZE CONSTANT_I=0.1C IF(tf>10s) STOP_FAZE END_FAZE LIGHT(FAST) END_CYCLE"
    steps = list(Program(record_of(macro(body))).steps("charge"))
    phases = [s for s in steps if isinstance(s, PhaseCode)]
    assert [(p.index, p.cycle_pass) for p in phases] == [(1, 1), (1, 2), (1, 3)]
    assert sum(isinstance(s, CommandStep) for s in steps) == 3


def test_empty_discharge_section_discharges_at_0_1_a_to_the_chemistry_end_voltage():
    steps = list(Program(record_of(macro(CC_TO_V))).steps("discharge"))
    assert any(isinstance(s, DefaultDischarge) for s in steps)
    r = run(macro(CC_TO_V), "discharge", capacity=500, series=2, soc=0.3)
    (phase,) = r.phases
    assert phase.reason == "default: empty discharge section, V<1.00V/cell"
    assert r.log.current_a[5] == pytest.approx(-0.1)
    assert phase.v_end < 2.0


def test_commands_become_events_in_order():
    r = run(macro(CC_TO_V, tail="MUSIC(STOP) LIGHT(ON)"), capacity=2000, series=1, soc=0.5)
    kinds = [(e.kind, e.detail) for e in r.interpreter.events if e.kind in ("music", "light", "finish")]
    assert kinds == [("music", "MUSIC(STOP)"), ("light", "LIGHT(ON)"), ("finish", "end of macro")]


def test_input_values_come_from_the_start_parameters_or_a_precise_error():
    text = macro("FAZE CONSTANT_I=INPUT IF(V>1.4S) STOP_FAZE END_FAZE")
    with pytest.raises(StartError, match="INPUT"):
        start(text, capacity=2000, series=1)
    r = run(text, capacity=2000, series=1, current=0.7, soc=0.5)
    assert r.log.current_a[3] == pytest.approx(0.7)


def test_relative_units_use_declared_capacity_and_series_first():
    text = macro(CC_TO_V, intro="AKK_TYPE=NiMh SERIES=3 CAPACITY=1000")
    r = run(text, capacity=5000, series=8, soc=0.5)
    assert r.log.current_a[3] == pytest.approx(1.0)           # 1C of the declared 1000 mAh
    assert r.phases[0].v_end == pytest.approx(4.2, abs=0.01)   # 1.40 V x the declared 3 cells


def test_cc_cv_in_one_phase_limits_current_then_holds_voltage():
    r = run("LiFe-CCCV", capacity=2300, series=1, current=2.3)
    a = r.log.arrays()
    assert a["current_a"].max() == pytest.approx(2.3)
    assert a["voltage_v"].max() <= 3.6 + 1e-3


def test_charge_ex_pulses_charge_then_discharge_and_measures_at_its_point():
    body = "FAZE CHARGE_EX(30, 1C, 2, 0.5C, 2) IF(tf>5min) STOP_FAZE END_FAZE"
    r = run(macro(body), capacity=2000, series=1, soc=0.3)
    i = r.log.current_a
    assert i[0] == pytest.approx(2.0) and i[29] == pytest.approx(2.0)
    assert i[30] == pytest.approx(-1.0) and i[31] == pytest.approx(-1.0) and i[32] == pytest.approx(2.0)
    v = r.log.voltage_v
    # tV=2: the reading is taken at the end of the discharge pulse and held for the period.
    assert v[40] == v[50] == v[31]
    assert r.phases[0].mah_out > 0 and r.phases[0].mah_in > r.phases[0].mah_out


def test_trickle_switches_on_at_v1_and_off_at_v2():
    # Thresholds about the NiMH OCV near full (1.39 V at 85 %, retuned from the recordings).
    body = "FAZE TRICKLE(0.5C, 1.40S, 1.50S) IF(tf>2h) STOP_FAZE END_FAZE"
    r = run(macro(body), capacity=2000, series=1, soc=0.85)
    a = r.log.arrays()
    on = a["current_a"] > 0
    assert on.any() and (~on).any()
    assert a["voltage_v"].max() < 1.50 + 0.02


def test_macro_time_stops_the_macro_skips_the_rest_and_runs_the_conclusion():
    text = macro("FAZE CONSTANT_I=0.1C IF(V>1.6S) STOP_FAZE END_FAZE FAZE CONSTANT_I=0.1C IF(tf>1h) STOP_FAZE END_FAZE",
                 intro="AKK_TYPE=NiMh IF(tm>10min) STOP_MACRO", tail="MUSIC(STOP)")
    r = run(text, capacity=2000, series=1)
    assert [p.reason for p in r.phases] == ["IF(tm>10min) STOP_MACRO"]      # the second phase never runs
    assert r.interpreter.end_reason == "IF(tm>10min) STOP_MACRO"
    assert r.interpreter.time_s == pytest.approx(601)
    kinds = [e.kind for e in r.interpreter.events]
    # The conclusion signals the end, whatever ended the macro (docs/simulator.md).
    assert kinds[-3:] == ["phase_end", "music", "finish"]
    assert r.phases[0].timer_before_full


def test_macro_wide_heatsink_thresholds_replace_the_defaults():
    text = compile_source("MACRO T\nAKK_TYPE=LiPo\nIF(Tc>50) PAUSE_MACRO\nIF(Tc<45) CONTINUE_MACRO\n"
                          "DISCHARGE_SECTION\nFAZE CONSTANT_I=1A IF(V<3S) STOP_FAZE END_FAZE\nEND_SECTION\n"
                          "END_MACRO\n")
    assert text.ok
    r = run("MACRO T\nAKK_TYPE=LiPo\nIF(Tc>50) PAUSE_MACRO\nIF(Tc<45) CONTINUE_MACRO\nDISCHARGE_SECTION\n"
            "FAZE CONSTANT_I=1A IF(V<3S) STOP_FAZE END_FAZE\nEND_SECTION\nEND_MACRO\n", "discharge",
            capacity=2000, series=3, ambient=30)
    pauses = [e for e in r.interpreter.events if e.kind in ("pause", "resume")]
    assert pauses[0].detail == "Tc>50" and pauses[1].detail == "Tc<45"


def test_capacity_default_only_without_a_sensor_and_only_while_charging():
    body = "FAZE CONSTANT_I=1C IF(tf>3h) STOP_FAZE END_FAZE"
    r = run(macro(body), capacity=2000, series=1, sensor=False, model="LiFe")
    assert r.phases[0].reason == "default: capacity 1.5x"
    assert r.phases[0].mah_in == pytest.approx(3000, abs=3)


def test_coulomb_counts_add_up_per_phase_and_in_total():
    r = run("LiPo", "train", capacity=1000, series=2, current=1.0)
    total_in = sum(p.mah_in for p in r.phases)
    total_out = sum(p.mah_out for p in r.phases)
    t = r.totals()
    assert t["mah_in"] == pytest.approx(total_in, abs=0.2)
    assert t["mah_out"] == pytest.approx(total_out, abs=0.2)
    assert r.log.mah_in[-1] == pytest.approx(total_in, abs=0.2)


def test_ticking_in_small_steps_gives_the_same_run_as_one_call():
    whole = run("NiMh-dV", capacity=2000, series=4, current=2.0, sensor=False)
    stepped = start("NiMh-dV", capacity=2000, series=4, current=2.0, sensor=False)
    while stepped.interpreter.advance(7):
        pass
    assert np.array_equal(stepped.log.voltage_v, whole.log.voltage_v)
    assert [p.reason for p in stepped.phases] == [p.reason for p in whole.phases]


def test_stop_ends_the_phase_and_the_macro():
    sim = start("NiMh-dV", capacity=2000, series=4, current=2.0)
    sim.interpreter.advance(100)
    sim.interpreter.stop()
    assert sim.interpreter.finished and sim.phases[0].reason == "stopped"
    assert not sim.interpreter.advance(10)


def test_noise_is_seeded_and_reproducible():
    from zuml_studio.sim.interpreter import Measurement
    m = Measurement(noise_v=0.004, lsb_v=0.005, seed=7)
    a = run("NiMh-dV", capacity=2000, series=4, current=2.0, sensor=False, measurement=m)
    b = run("NiMh-dV", capacity=2000, series=4, current=2.0, sensor=False, measurement=m)
    assert np.array_equal(a.log.voltage_v, b.log.voltage_v)
    v = a.log.voltage_v[:100]                       # stored as float32: quantised to its precision
    assert np.allclose(np.round(v / 0.005) * 0.005, v, rtol=0, atol=2e-6)
    assert a.phases[0].reason == "IF(DELTA_PEAK>0.01S) STOP_FAZE"


def test_invalid_records_never_run():
    from zuml_studio.sim.interpreter import StartParams
    from zuml_studio.sim.simulate import prepare
    bad = bytearray(record_of("LiPo"))
    bad[-1] ^= 1
    with pytest.raises(StartError, match="check byte"):
        prepare(bytes(bad), StartParams(capacity_mah=1000, series=1, current_a=1))


def test_a_macro_that_never_ends_stops_at_the_simulation_limit():
    body = "FAZE CONSTANT_I=0.5A END_FAZE"
    r = run(macro("", body), "discharge", capacity=1000, series=1, soc=0.2, tick_s=60.0)
    assert r.phases[0].reason.startswith("limit: simulation stopped after 1000h")


def test_a_200_hour_training_runs_to_its_end():
    # 10 cycles of a 10 Ah pack at 0.1C, no sensor (each charge ends at 1.5x the capacity): ~250 h
    r = run("NiMh", "train", capacity=10000, current=1.0, series=4, repetitions=10, sensor=False, tick_s=10.0)
    assert r.interpreter.end_reason == "end of macro" and r.interpreter.time_s > 200 * 3600
    assert len(r.log) == r.interpreter.time_s / 10.0
