"""The pack's resistance read at a log's rests and the default model made to have it (sim/measured_r.py,
issue 26 decision (a))."""
import numpy as np
import pytest

from zuml_studio.domain.chemistry import load_chemistry
from zuml_studio.sim.measured_r import MeasuredR, measure, model_step, with_measured_r


def stepped(on_a: float, r_ohm: float, cells: int = 4, period: float = 1.0):
    """A charge at on_a that stops at 100 s: the voltage falls by on_a × r_ohm × cells at once."""
    t = np.arange(0.0, 200.0, period)
    i = np.where(t < 100.0, on_a, 0.0)
    v = np.where(t < 100.0, 6.0, 6.0 - on_a * r_ohm * cells)
    return t, v, i


def test_a_step_to_a_rest_reads_the_resistance_per_cell():
    t, v, i = stepped(0.5, 0.184)
    m = measure(t, v, i, 4, "charge", (0.0, 100.0), 0.5)
    assert m.ohm_per_cell == pytest.approx(0.184) and m.delay_s == 1.0 and m.at_s == (99.0,)


def test_a_log_sampled_slower_than_a_second_is_read_at_twice_its_period():
    t, v, i = stepped(1.0, 0.125, period=1.5)
    assert measure(t, v, i, 4, "charge", (0.0, 100.0), 1.0).delay_s == 3.0


def test_steps_of_the_other_direction_or_a_small_tail_current_are_not_read():
    t, v, i = stepped(0.5, 0.184)
    assert measure(t, v, i, 4, "discharge", (0.0, 100.0), 0.5) is None
    # A CV tail's last 0.5 A of a 10 A charge reads its polarisation, not its resistance.
    assert measure(t, v, i, 4, "charge", (0.0, 100.0), 10.0) is None


def test_the_scaled_model_steps_as_the_pack_did():
    chem = load_chemistry("NiMh")
    measured = MeasuredR(0.184, 1.0, (99.0,))
    scaled, scale = with_measured_r(chem, 1100.0, measured)
    assert model_step(scaled, 1100.0, 1.0) == pytest.approx(0.184)
    assert scale == pytest.approx(0.184 / model_step(chem, 1100.0, 1.0))
    assert scaled.r0_ohm / chem.r0_ohm == pytest.approx(scale) and scaled.r1_ohm / chem.r1_ohm == pytest.approx(scale)


def test_the_measurement_round_trips_as_json_values():
    m = MeasuredR(0.2036, 1.0, (15207.023, 47345.173))
    assert MeasuredR.from_dict(m.to_dict()) == MeasuredR(0.2036, 1.0, (15207.0, 47345.2))
