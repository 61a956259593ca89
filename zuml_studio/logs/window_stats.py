"""What a log says between two times (the log viewer's two cursors, and the span between them):
the values at each cursor and their differences, and per curve the minimum, maximum and mean of
the samples between, the charge in and out, the energy, the time.

* At a cursor: the nearest sample, unless the cursor is in a gap (``gaps.in_gap``): no values.
* Δ mAh is the net charge (in − out, the log's totals) at B minus at A.
* Min, max and mean are of the samples from A to B (the mean of the samples, not time-weighted).
* Charge in/out: the log's totals at the last sample up to B minus those at the first from A.
* Energy in/out: V·I integrated over consecutive samples in the span (trapezoid, charge current
  positive: in), no step across a gap adds anything.
* The cell deviation is the highest cell minus the lowest, per sample, in mV (2 cells or more).
No Qt here."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..domain.units import SECONDS_PER_HOUR
from . import gaps
from .model import Log

CURVES = ("voltage", "current", "temp", "heatsink")


@dataclass(frozen=True)
class Stat:
    min: float
    max: float
    mean: float


@dataclass(frozen=True)
class Reading:
    """The nearest sample to a cursor (None: the cursor is in a gap or outside the log)."""
    t: float
    voltage: float
    current: float | None
    net_mah: float


@dataclass(frozen=True)
class Between:
    a: Reading | None
    b: Reading | None
    start_s: float
    end_s: float
    samples: int
    curves: dict[str, Stat]            # "voltage", "current", "temp", "heatsink", "cell 1"…, "deviation"
    charge_in_mah: float | None
    charge_out_mah: float | None
    energy_in_wh: float | None
    energy_out_wh: float | None

    @property
    def time_s(self) -> float:
        return self.end_s - self.start_s

    def delta(self, name: str) -> float | None:
        """B − A of "t", "voltage", "current" or "net_mah" (None if a cursor has no sample)."""
        if self.a is None or self.b is None:
            return None
        x, y = getattr(self.a, name), getattr(self.b, name)
        return None if x is None or y is None else y - x


# Samples worked at a time.
_BLOCK = 1 << 16


def deviation_mv(cells: np.ndarray) -> np.ndarray:
    """Highest minus lowest cell per sample, in mV; NaN where fewer than two cells read."""
    cells = np.asarray(cells, dtype=float)
    if cells.ndim != 2 or cells.shape[1] < 2:
        return np.full(len(cells), np.nan)
    out = np.empty(len(cells))
    for lo in range(0, len(cells), _BLOCK):         # a block at a time: a long log's cells are not copied whole
        part = cells[lo:lo + _BLOCK]
        finite = np.isfinite(part)
        high = np.where(finite, part, -np.inf).max(axis=1)
        low = np.where(finite, part, np.inf).min(axis=1)
        with np.errstate(invalid="ignore"):
            out[lo:lo + _BLOCK] = np.where(finite.sum(axis=1) >= 2, (high - low) * 1000.0, np.nan)
    return out


def _reading(log: Log, data: dict, seconds: float, gap_s: float) -> Reading | None:
    t = data["t"]
    if gaps.in_gap(t, seconds, gap_s):
        return None
    k = int(np.argmin(np.abs(t - seconds)))
    c = log.columns
    current = float(data["current"][k]) if log.meta.get("current_measured", True) else None
    return Reading(float(t[k]), float(data["voltage"][k]), current, float(c.mah_in[k] - c.mah_out[k]))


def _stat(values: np.ndarray) -> Stat | None:
    values = values[np.isfinite(values)]
    if not len(values):
        return None
    return Stat(float(values.min()), float(values.max()), float(values.mean()))


def between(log: Log, a_s: float, b_s: float) -> Between:
    """The readings at A and B and the statistics of the samples between them (either order)."""
    data = log.arrays()
    t = data["t"]
    gap_s = gaps.gap_threshold(t)
    start, end = sorted((float(a_s), float(b_s)))
    inside = np.flatnonzero((t >= start) & (t <= end))
    curves: dict[str, Stat] = {}
    columns = {name: data[name] for name in CURVES}
    if not log.meta.get("current_measured", True):
        del columns["current"]
    for k in range(data["cells"].shape[1]):
        columns[f"cell {k + 1}"] = data["cells"][:, k]
    if data["cells"].shape[1] >= 2:
        columns["deviation"] = deviation_mv(data["cells"])
    for name, column in columns.items():
        stat = _stat(np.asarray(column)[inside])
        if stat is not None:
            curves[name] = stat
    q_in = q_out = e_in = e_out = None
    if len(inside):
        c, first, last = log.columns, inside[0], inside[-1]
        q_in, q_out = float(c.mah_in[last] - c.mah_in[first]), float(c.mah_out[last] - c.mah_out[first])
        if "current" in columns:
            e_in, e_out = _energy(t[inside], data["voltage"][inside], data["current"][inside], gap_s)
    return Between(_reading(log, data, a_s, gap_s), _reading(log, data, b_s, gap_s), start, end, len(inside),
                   curves, q_in, q_out, e_in, e_out)


def _energy(t: np.ndarray, v: np.ndarray, i: np.ndarray, gap_s: float) -> tuple[float, float]:
    """(in, out) Wh over consecutive samples, trapezoid of V·I, nothing across a gap."""
    if len(t) < 2:
        return 0.0, 0.0
    p = v * i
    dt = np.diff(t)
    step = np.where(dt <= gap_s, dt, 0.0)
    pos = (np.maximum(p[:-1], 0) + np.maximum(p[1:], 0)) / 2 * step
    neg = (np.maximum(-p[:-1], 0) + np.maximum(-p[1:], 0)) / 2 * step
    return float(np.nansum(pos) / SECONDS_PER_HOUR), float(np.nansum(neg) / SECONDS_PER_HOUR)

