"""The live plot's min/max envelopes, without Qt: taken in piece by piece, they give the same
extremes as the raw samples in every view, and about two points per pixel."""
import numpy as np
from hypothesis import given, strategies as st

from zuml_studio.ui.plots.envelope import FANOUT, FIRST_KEPT, Envelope
from zuml_studio.ui.plots.growing_buffer import GrowingBuffer


def table(n: int, seed: int = 1) -> GrowingBuffer:
    rng = np.random.default_rng(seed)
    buf = GrowingBuffer(("t", "v", "temp"), dtype={"v": np.float32, "temp": np.float32})
    temp = rng.normal(30, 2, n)
    temp[(np.arange(n) // 50) % 3 == 0] = np.nan          # a sensor that comes and goes
    buf.extend({"t": np.arange(n, dtype=float) * 0.5, "v": rng.normal(5.6, 0.1, n), "temp": temp})
    return buf


def extremes(y: np.ndarray) -> tuple[float, float]:
    return float(np.nanmin(y)), float(np.nanmax(y))


def test_a_few_samples_are_drawn_as_they_are():
    buf = table(100)
    env = Envelope(("v", "temp"))
    env.update(*buf.snapshot())
    level, x, ys = env.view(10.0, 20.0, bins=800)
    assert level == 0
    assert x.tolist() == (np.arange(19, 42) * 0.5).tolist()      # one sample beyond each edge
    assert ys["v"].tolist() == buf.column("v")[19:42].tolist()


def test_a_million_samples_in_view_give_about_two_points_per_pixel_and_the_true_extremes():
    buf = table(1_000_000)
    env = Envelope(("v", "temp"))
    env.update(*buf.snapshot())
    t = buf.column("t")
    level, x, ys = env.view(t[0], t[-1], bins=840)
    assert level >= 1
    assert 2 * 840 <= len(x) <= 2 * 840 * FANOUT + 4
    assert (np.diff(x) >= 0).all()
    for name in ("v", "temp"):
        assert extremes(ys[name]) == extremes(buf.column(name))


def test_only_the_coarse_levels_are_kept_and_every_level_serves_a_view():
    buf = table(300_000)
    env = Envelope(("v", "temp"))
    env.update(*buf.snapshot())
    kept = sum(len(level) for level in env.levels)
    assert len(env.levels[0]) == 300_000 // FANOUT ** FIRST_KEPT and kept < 300_000 / 40
    t = buf.column("t")
    levels = set()
    for span in (100, 1_000, 3_000, 10_000, 30_000, 150_000):
        level, x, ys = env.view(t[1000], t[1000 + span - 1], bins=100)
        levels.add(level)
        for name in ("v", "temp"):
            raw = np.asarray(buf.column(name))[999:1000 + span + 1]
            lo, hi = extremes(ys[name])
            assert lo <= np.nanmin(raw) and hi >= np.nanmax(raw)
    assert {0, 1, 2, FIRST_KEPT} <= levels


def test_no_finite_value_in_a_bin_stays_nan():
    buf = GrowingBuffer(("t", "temp"))
    buf.extend({"t": np.arange(4096.0), "temp": np.full(4096, np.nan)})
    env = Envelope(("temp",))
    env.update(*buf.snapshot())
    _, x, ys = env.view(0.0, 4095.0, bins=10)
    assert len(x) and np.isnan(ys["temp"]).all()


def test_a_cleared_table_starts_again():
    buf = table(5000)
    env = Envelope(("v", "temp"))
    env.update(*buf.snapshot())
    buf.clear()
    buf.extend({"t": np.arange(10.0), "v": np.full(10, 1.0), "temp": np.full(10, 2.0)})
    env.update(*buf.snapshot())
    assert len(env) == 10
    _, x, ys = env.view(0.0, 9.0, bins=100)
    assert x.tolist() == list(range(10)) and set(ys["v"].tolist()) == {1.0}


@given(chunks=st.lists(st.integers(1, 700), min_size=1, max_size=12),
       window=st.tuples(st.floats(0, 1), st.floats(0, 1)), bins=st.integers(1, 300))
def test_taken_in_piece_by_piece_every_view_has_the_raw_extremes(chunks, window, bins):
    total = sum(chunks)
    full = table(total, seed=total)
    buf = GrowingBuffer(("t", "v", "temp"), dtype={"v": np.float32, "temp": np.float32})
    env = Envelope(("v", "temp"))
    done = 0
    for size in chunks:
        buf.extend({name: full.column(name)[done:done + size] for name in ("t", "v", "temp")})
        done += size
        env.update(*buf.snapshot())
    t = full.column("t")
    a, b = sorted(window)
    x0, x1 = t[0] + a * (t[-1] - t[0]), t[0] + b * (t[-1] - t[0])
    level, x, ys = env.view(x0, x1, bins)
    # the samples in view, plus one beyond each edge
    i0 = max(0, int(np.searchsorted(t, x0, "left")) - 1)
    i1 = min(total, int(np.searchsorted(t, x1, "right")) + 1)
    assert len(x) and x[0] <= t[i0] and x[-1] <= t[i1 - 1]
    for name in ("v", "temp"):
        raw = full.column(name)[i0:i1]
        if np.isnan(raw).all():
            continue
        lo, hi = extremes(ys[name])
        want_lo, want_hi = extremes(raw)
        # a bin may reach a little beyond the view's samples (it starts at a bin boundary), never miss one
        assert lo <= want_lo and hi >= want_hi
        if level == 0:
            assert (lo, hi) == (want_lo, want_hi)
    if level:
        assert len(x) >= bins
