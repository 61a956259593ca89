"""The rest-step resistance (docs/validation.md's method), on made-up steps whose answer is known."""
import numpy as np
import pytest

from zuml_studio.logs.rest_steps import resistance_mohm_per_cell, rest_steps


def _log(period: float, drop_v: float = 0.4, current: float = 2.0):
    """2 A for 60 s, then a rest of 60 s: the voltage falls by ``drop_v`` at once, then 1 mV/s."""
    t = np.arange(0.0, 120.0 + period / 2, period)
    i = np.where(t < 60.0, current, 0.0)
    v = np.where(t < 60.0, 8.4, 8.4 - drop_v - 0.001 * (t - 60.0))
    return t, v, i


def test_one_second_after_the_step():
    steps = rest_steps(*_log(1.0))
    assert len(steps) == 1
    (s,) = steps
    assert (s.time_s, s.current_a, s.delay_s) == (59.0, 2.0, 1.0)
    assert s.ohm_per_cell(2) * 1000 == pytest.approx((0.4 + 0.0) / 2.0 / 2 * 1000, abs=0.01)


def test_a_slow_log_reads_its_second_rest_sample_and_a_coarse_one_none():
    t, v, i = _log(1.5)
    # 1.5 s samples: the second rest sample, 3 s after the last one on
    assert resistance_mohm_per_cell(t, v, i, 2) == pytest.approx((0.4 + 0.0015) / 2.0 / 2 * 1000, abs=0.01)
    assert resistance_mohm_per_cell(*_log(10.0), 2) is None                 # 20 s later is polarisation


def test_a_discharge_step_and_small_currents():
    t, v, i = _log(1.0, drop_v=-0.3, current=-1.5)                           # the voltage rises after a discharge
    assert rest_steps(t, v, i)[0].ohm_per_cell(1) == pytest.approx(0.2, abs=1e-6)
    assert rest_steps(*_log(1.0, current=0.02)) == []                        # below 50 mA: no step
