"""-dV detection on window averages with a hold-off, as cheali-charger does it (chargers.md §1c)."""
from __future__ import annotations

import random

import pytest

from zuml_studio.sim.battery import Pack
from zuml_studio.domain.chemistry import load_chemistry
from zuml_studio.sim.delta_peak import DeltaPeakDetector


def feed(det: DeltaPeakDetector, samples, dt: float = 1.0) -> list[float]:
    return [det.update(k * dt, v) for k, v in enumerate(samples, start=1)]


def test_drop_is_measured_against_the_held_window_peak():
    det = DeltaPeakDetector(window_s=30, holdoff_s=0)
    rise = [5.0 + 0.001 * k for k in range(300)]
    fall = [rise[-1] - 0.0005 * k for k in range(1, 301)]
    samples = rise + fall
    drops = feed(det, samples)
    assert max(drops[:300]) == 0.0
    window_means = [sum(samples[k:k + 30]) / 30 for k in range(0, 600, 30)]
    assert det.peak_v == pytest.approx(max(window_means))
    assert drops[-1] == pytest.approx(max(window_means) - window_means[-1])
    assert det.drop_v == drops[-1] and all(d >= 0 for d in drops)


def test_drop_only_changes_at_window_ends():
    det = DeltaPeakDetector(window_s=30, holdoff_s=0)
    drops = feed(det, [5.0] * 30 + [4.9] * 59)
    assert drops[:59] == [0.0] * 59 and drops[59] == pytest.approx(0.1)
    assert set(drops[59:88]) == {drops[59]}


def test_holdoff_lets_the_peak_follow_the_voltage():
    det = DeltaPeakDetector(window_s=30, holdoff_s=180)
    falling = [5.0 - 0.001 * k for k in range(180)]      # e.g. a pack settling just after connection
    assert feed(det, falling) == [0.0] * 180
    assert det.peak_v == pytest.approx(sum(falling[-30:]) / 30)
    det.update(181, falling[-1] - 0.05)
    for t in range(182, 211):
        drop = det.update(t, falling[-1] - 0.05)
    assert drop == pytest.approx(det.peak_v - (falling[-1] - 0.05))


def test_window_average_hides_noise():
    rnd = random.Random(1)
    det = DeltaPeakDetector(window_s=30, holdoff_s=0)
    drops = feed(det, [5.6 + rnd.gauss(0, 0.004) for _ in range(3600)])
    assert max(drops) < 0.008          # single samples dip 3 sigma = 12 mV, the averages far less


def test_reset_forgets_the_peak():
    det = DeltaPeakDetector(window_s=10, holdoff_s=0)
    feed(det, [6.0] * 20 + [5.0] * 20)
    assert det.drop_v > 0
    det.reset()
    assert (det.peak_v, det.drop_v) == (0.0, 0.0)
    assert feed(det, [5.0] * 20)[-1] == 0.0


def test_sparse_samples_close_a_window_each():
    det = DeltaPeakDetector(window_s=30, holdoff_s=0)
    assert det.update(0.0, 5.0) == 0.0
    det.update(100.0, 5.0)
    assert det.peak_v == 5.0
    assert det.update(200.0, 4.9) == pytest.approx(0.1)


def test_fires_on_a_noisy_nimh_charge_like_a_charger():
    """4 x NiMH 2000 mAh at 1C with 2 mV ADC noise and 5 mV quantisation still stops at 1.0-1.15 C."""
    rnd = random.Random(7)
    pack = Pack(load_chemistry("NiMh"), 2000, 4)
    det = DeltaPeakDetector()
    for k in range(1, int(1.3 * 3600)):
        v = pack.step(2.0, 1.0)
        measured = round((v + rnd.gauss(0.0, 0.002)) / 0.005) * 0.005
        if det.update(float(k), measured) >= 4 * 0.005:
            break
    assert 1.0 <= k * 2.0 / 3600 / 2.0 <= 1.15
