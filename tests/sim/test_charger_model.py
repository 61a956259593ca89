"""iMAX B6 power-stage limits and heat sink (chargers.md §1b; heat sink calibrated, see imax_b6.toml)."""
from __future__ import annotations

import pytest

from zuml_studio.sim.charger_model import Charger, load_charger


@pytest.fixture
def b6() -> Charger:
    return Charger(load_charger(), ambient_c=25.0)


def test_imax_b6_limits():
    lim = load_charger("imax_b6")
    assert (lim.max_charge_a, lim.max_charge_w, lim.max_discharge_a, lim.max_discharge_w, lim.max_v) == (5, 50, 1, 5, 27)
    assert 0 < lim.min_charge_a < lim.max_charge_a


def test_unknown_charger_is_a_key_error():
    with pytest.raises(KeyError, match="imax_b6"):
        load_charger("no_such_charger")


@pytest.mark.parametrize(
    "requested, pack_v, expected",
    [
        (2.0, 12.0, 2.0),            # within both limits
        (8.0, 5.0, 5.0),             # current limit
        (8.0, 16.8, 50.0 / 16.8),    # power limit
        (-0.3, 4.0, -0.3),
        (-3.0, 3.0, -1.0),           # discharge current limit
        (-3.0, 12.0, -5.0 / 12.0),   # discharge power limit
        (0.0, 12.0, 0.0),
        (3.0, 0.0, 3.0),             # no power limit on a dead-short reading
    ],
)
def test_limit_current(b6, requested, pack_v, expected):
    assert b6.limit_current(requested, pack_v) == pytest.approx(expected)


def test_limited_current_respects_a_and_w_in_both_directions(b6):
    for v in (1.0, 4.2, 8.4, 12.0, 16.8, 25.2):
        for req in (-20.0, -1.5, -0.5, 0.5, 4.0, 20.0):
            i = b6.limit_current(req, v)
            assert abs(i) <= abs(req) and i * req >= 0
            if i > 0:
                assert i <= 5.0 + 1e-12 and i * v <= 50.0 + 1e-9
            else:
                assert -i <= 1.0 + 1e-12 and -i * v <= 5.0 + 1e-9


def test_heatsink_5w_discharge_then_cools_to_ambient(b6):
    for _ in range(3600):
        t = b6.step(-0.5, 10.0, 1.0)
    assert 55.0 <= t <= 65.0
    for _ in range(2 * 3600):
        t = b6.step(0.0, 10.0, 1.0)
    assert t == pytest.approx(25.0, abs=0.5)


def test_heatsink_50w_charge(b6):
    for _ in range(3600):
        t = b6.step(4.0, 12.5, 1.0)
    assert 45.0 <= t <= 55.0


def test_heatsink_rises_monotonically_and_independent_of_dt():
    fine, coarse = Charger(load_charger()), Charger(load_charger())
    last = fine.heatsink_c
    for _ in range(600):
        now = fine.step(-1.0, 5.0, 1.0)
        assert now >= last
        last = now
    coarse.step(-1.0, 5.0, 600.0)
    assert coarse.heatsink_c == pytest.approx(fine.heatsink_c, rel=1e-9)


def test_minus_dv_hold_off_is_a_charger_parameter_from_the_thesis():
    """Issue 11.8: seed 001 ignores the first 5-10 minutes of a -dV charge; the model says how long."""
    lim = load_charger("imax_b6")
    assert (lim.dpeak_window_s, lim.dpeak_holdoff_s) == (30.0, 300.0)


@pytest.mark.parametrize("holdoff", [300.0, 900.0])
def test_the_interpreter_ignores_a_minus_dv_during_the_chargers_hold_off(holdoff):
    from dataclasses import replace

    from simhelp import record_of
    from zuml_studio.sim.interpreter import StartParams
    from zuml_studio.sim.simulate import BatterySetup, prepare
    # A full pack charged at 1C peaks at once: the -dV fires as soon as the hold-off allows.
    r = prepare(record_of("NiMh-dV"), StartParams("charge", 1, 2000, 2.0, None, 4, False), BatterySetup(soc=1.0))
    r.interpreter.charger.limits = replace(r.interpreter.charger.limits, dpeak_holdoff_s=holdoff)
    r.interpreter.run()
    (phase,) = r.phases
    assert phase.reason == "IF(DELTA_PEAK>0.01S) STOP_FAZE"
    assert holdoff < phase.end_s <= holdoff + 600


def test_a_charger_file_without_its_minus_dv_numbers_is_refused(monkeypatch):
    import zuml_studio.sim.charger_model as cm
    from zuml_studio.data import DataFileError
    parsed = cm.data.read_toml("chargers/imax_b6.toml")
    del parsed["delta_peak"]
    monkeypatch.setattr(cm.data, "read_toml", lambda relative: parsed)
    with pytest.raises(DataFileError, match="imax_b6.toml: missing key 'delta_peak'"):
        cm.load_charger("imax_b6")
