"""Where a recording has no samples, and what a plot may draw of it.

A gap is a step between two samples longer than ``GAP_PERIODS`` of the recording's typical
sample period (the median step): a charger switched off, a cable pulled, LogView paused.
Nothing may be drawn across a gap, at any zoom: a line through it (or a min/max pair of
a downsampled curve that holds samples from both sides) shows values no sample has.

``broken`` puts a NaN row into every gap (a plot drawing with ``connect="finite"`` stops
there); ``envelope`` downsamples to a min and a max per pixel column without ever putting
samples from both sides of a gap, or of a missing value, into one column. No Qt here."""
from __future__ import annotations

import numpy as np

GAP_PERIODS = 5.0
PERIOD_PROBES = 4096          # steps looked at to find the typical period of a long recording


def sample_period(t: np.ndarray) -> float:
    """The median step between samples (of at most PERIOD_PROBES steps spread over the
    recording); 0 with fewer than two samples."""
    n = len(t)
    if n < 2:
        return 0.0
    at = np.unique(np.linspace(0, n - 2, min(n - 1, PERIOD_PROBES)).astype(np.int64))
    steps = np.asarray(t[at + 1], dtype=float) - np.asarray(t[at], dtype=float)
    steps = steps[steps > 0]
    return float(np.median(steps)) if len(steps) else 0.0


def gap_threshold(t: np.ndarray) -> float:
    """The step beyond which two samples are not joined (infinity: no step is a gap)."""
    period = sample_period(t)
    return GAP_PERIODS * period if period > 0 else float("inf")


def gap_after(t: np.ndarray, threshold: float | None = None) -> np.ndarray:
    """Indices k with a gap between sample k and k + 1."""
    threshold = gap_threshold(t) if threshold is None else threshold
    return np.flatnonzero(np.diff(np.asarray(t, dtype=float)) > threshold)


def covered_spans(t: np.ndarray, threshold: float | None = None) -> list[tuple[float, float]]:
    """The time spans the samples cover: (first, last) between gaps."""
    if not len(t):
        return []
    cuts = gap_after(t, threshold)
    starts = np.concatenate(([0], cuts + 1))
    ends = np.concatenate((cuts, [len(t) - 1]))
    return [(float(t[a]), float(t[b])) for a, b in zip(starts, ends)]


def in_gap(t: np.ndarray, seconds: float, threshold: float | None = None) -> bool:
    """Whether a time lies in a gap or outside the recording: no sample speaks for it."""
    n = len(t)
    if not n or seconds < t[0] or seconds > t[-1]:
        return True
    k = int(np.searchsorted(t, seconds))
    if k == 0 or t[k] == seconds:
        return False
    threshold = gap_threshold(t) if threshold is None else threshold
    return float(t[k] - t[k - 1]) > threshold


def outside(t: np.ndarray, times: np.ndarray, threshold: float | None = None) -> np.ndarray:
    """For each of ``times``: whether it lies in a gap of ``t`` or outside it (``in_gap`` for many)."""
    t = np.asarray(t, dtype=float)
    times = np.asarray(times, dtype=float)
    if not len(t):
        return np.ones(len(times), dtype=bool)
    threshold = gap_threshold(t) if threshold is None else threshold
    k = np.clip(np.searchsorted(t, times), 1, max(1, len(t) - 1))
    step = t[k] - t[k - 1] if len(t) > 1 else np.zeros(len(times))
    exact = (t[np.minimum(k, len(t) - 1)] == times) | (t[k - 1] == times)
    return (times < t[0]) | (times > t[-1]) | ((step > threshold) & ~exact)


def broken(t: np.ndarray, *ys: np.ndarray, threshold: float | None = None) -> tuple[np.ndarray, ...]:
    """(t, *ys) with a row inserted in every gap: its time midway, its values NaN."""
    t = np.asarray(t, dtype=float)
    cuts = gap_after(t, threshold)
    if not len(cuts):
        return (t, *(np.asarray(y, dtype=float) for y in ys))
    mid = (t[cuts] + t[cuts + 1]) / 2
    out_t = np.insert(t, cuts + 1, mid)
    return (out_t, *(np.insert(np.asarray(y, dtype=float), cuts + 1, np.nan) for y in ys))


def envelope(t: np.ndarray, y: np.ndarray, x0: float, x1: float, pixels: int,
             threshold: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    """The curve (t, y) between x0 and x1 (and one sample beyond each) as drawn ``pixels``
    columns wide: per column and stretch of data, the first and last time carrying the
    min and max in the order they come (the samples themselves when they are fewer than
    the columns), with a NaN point between stretches split by a gap or a missing value."""
    t = np.asarray(t, dtype=float)
    y = np.asarray(y, dtype=float)
    threshold = gap_threshold(t) if threshold is None else threshold
    i0 = max(0, int(np.searchsorted(t, x0, "left")) - 1)
    i1 = min(len(t), int(np.searchsorted(t, x1, "right")) + 1)
    t, y = t[i0:i1], y[i0:i1]
    if not len(t):
        return t, y
    finite = np.isfinite(y)
    # A stretch ends at a gap, and where a value is missing (the next finite sample starts a new one).
    breaks = np.zeros(len(t), dtype=bool)
    breaks[1:] = (np.diff(t) > threshold) | ~finite[:-1]
    stretch = np.cumsum(breaks)[finite]
    t, y = t[finite], y[finite]
    if not len(t):
        return t, y
    width = max(x1 - x0, 1e-9) / max(1, int(pixels))
    column = np.floor((t - x0) / width).astype(np.int64)
    new_group = np.ones(len(t), dtype=bool)
    new_group[1:] = (np.diff(column) != 0) | (np.diff(stretch) != 0)
    starts = np.flatnonzero(new_group)
    if len(starts) == len(t):            # one sample a group: the samples, broken between stretches
        return _with_breaks(t, y, stretch)
    ends = np.append(starts[1:], len(t)) - 1
    lo = np.minimum.reduceat(y, starts)
    hi = np.maximum.reduceat(y, starts)
    rising = y[ends] >= y[starts]
    gx = np.column_stack((t[starts], t[ends])).ravel()
    gy = np.column_stack((np.where(rising, lo, hi), np.where(rising, hi, lo))).ravel()
    return _with_breaks(gx, gy, np.repeat(stretch[starts], 2))


def _with_breaks(x: np.ndarray, y: np.ndarray, stretch: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """A NaN point between consecutive points of different stretches."""
    cuts = np.flatnonzero(np.diff(stretch) != 0)
    if not len(cuts):
        return x, y
    return np.insert(x, cuts + 1, (x[cuts] + x[cuts + 1]) / 2), np.insert(y, cuts + 1, np.nan)
