"""Min/max envelopes of the live plot's columns at every zoom level, kept up to date as
samples arrive, so that any view of a session, a million samples or more, is drawn from
about two points per pixel without scanning the samples in view on every frame.

Level k (k >= 1) holds, for each bin of ``FANOUT ** k`` consecutive samples, the first
sample's time and every column's minimum and maximum (NaN-aware: a bin whose values are
all NaN, a temperature without a sensor, stays NaN). Level k+1 is folded from level k,
so taking in new samples costs O(new) amortised. A view is served from the coarsest level
that still gives at least one bin per pixel: the same picture as peak downsampling the
raw samples, at the cost of the pixels instead of the samples.

Only levels from ``FIRST_KEPT`` up are kept (bins of 64 samples and more): the levels below
would cost a third of the samples' own memory again, and a view that needs one of them has
at most ``FANOUT ** FIRST_KEPT`` samples per pixel, few enough to fold on the fly.

No Qt here (unit-tested on its own).
"""
from __future__ import annotations

from typing import Mapping, Sequence

import numpy as np

from .growing_buffer import GrowingBuffer

FANOUT = 4
FIRST_KEPT = 3


def _fold(op: np.ufunc, values: np.ndarray, size: int = FANOUT) -> np.ndarray:
    """``op`` over each run of ``size`` values (their count a multiple of it): strided
    element-wise passes for a short run (a reduce along a short axis costs a call per run,
    ten times slower), a reduce along the axis for a long one."""
    if size > FANOUT:
        return op.reduce(np.asarray(values).reshape(-1, size), axis=1)
    out = values[0::size]
    for i in range(1, size):
        out = op(out, values[i::size])
    return out


class _Level:
    """The complete bins of one level: their first time and each column's min and max."""

    def __init__(self, columns: Sequence[str], dtypes: Mapping[str, np.dtype]):
        names = ["t"] + [f"{c}.min" for c in columns] + [f"{c}.max" for c in columns]
        self.rows = GrowingBuffer(names, 4096, dtype={**{f"{c}.min": dtypes[c] for c in columns},
                                                     **{f"{c}.max": dtypes[c] for c in columns}})

    def __len__(self) -> int:
        return len(self.rows)


class Envelope:
    """The envelopes of ``columns`` over the clock ``clock`` of one growing table."""

    def __init__(self, columns: Sequence[str], clock: str = "t"):
        self.columns = tuple(columns)
        self.clock = clock
        self.levels: list[_Level] = []
        self._n = 0
        self._raw: Mapping[str, np.ndarray] = {}

    def __len__(self) -> int:
        """Samples taken in."""
        return self._n

    def clear(self) -> None:
        self.levels.clear()
        self._n = 0
        self._raw = {}

    def update(self, n: int, cols: Mapping[str, np.ndarray]) -> None:
        """Take in the table's first ``n`` rows (``cols``: arrays or ``Column`` views of at least
        ``n`` rows, never changed afterwards, as ``GrowingBuffer.snapshot`` gives them). Fewer
        rows than before means the table was cleared and refilled: start again."""
        if n < self._n:
            self.clear()
        self._raw = cols
        self._n = n
        source_len = n
        source = {self.clock: cols[self.clock], **{f"{c}.min": cols[c] for c in self.columns},
                  **{f"{c}.max": cols[c] for c in self.columns}}
        k = 0
        size = FANOUT ** FIRST_KEPT             # the kept level 0 folds that many samples a bin
        while source_len >= size:
            if k == len(self.levels):
                self.levels.append(_Level(self.columns, {c: cols[c].dtype for c in self.columns}))
            level = self.levels[k]
            done, complete = len(level), source_len // size
            if complete > done:
                a, b = done * size, complete * size
                new = {"t": source[self.clock if k == 0 else "t"][a:b:size]}
                for c in self.columns:
                    new[f"{c}.min"] = _fold(np.fmin, source[f"{c}.min"][a:b], size)
                    new[f"{c}.max"] = _fold(np.fmax, source[f"{c}.max"][a:b], size)
                level.rows.extend(new)
            source_len, source = level.rows.snapshot()
            size = FANOUT
            k += 1

    def view(self, x0: float, x1: float, bins: int) -> tuple[int, np.ndarray, dict[str, np.ndarray]]:
        """What to draw of the clock range [x0, x1] at ``bins`` bins across (the plot's width
        in pixels): ``(level, x, {column: y})``. Level 0: the raw samples in range, when
        there are no more than two per bin; else min/max pairs of the coarsest level with at
        least ``bins`` bins in range. One sample or bin beyond each edge is included, so the
        lines run to the edges of the view."""
        n = self._n
        if not n:
            return 0, np.zeros(0), {c: np.zeros(0) for c in self.columns}
        t = self._raw[self.clock]
        i0 = max(0, int(t.searchsorted(x0, "left")) - 1)
        i1 = min(n, int(t.searchsorted(x1, "right")) + 1)
        count = i1 - i0
        bins = max(1, int(bins))
        if count <= 2 * bins:
            return 0, np.asarray(t[i0:i1]), {c: np.asarray(self._raw[c][i0:i1]) for c in self.columns}
        k = min(FIRST_KEPT - 1 + len(self.levels), max(1, int(np.log(count / bins) / np.log(FANOUT))))
        size = FANOUT ** k
        j0 = i0 // size
        if k < FIRST_KEPT:                  # not kept: fold the samples in view now
            a = j0 * size
            complete = a + (i1 - a) // size * size
            times = np.asarray(t[a:complete:size])
            lows = {c: _fold(np.fmin, self._raw[c][a:complete], size) for c in self.columns}
            highs = {c: _fold(np.fmax, self._raw[c][a:complete], size) for c in self.columns}
            tail = complete
        else:
            _, rows = self.levels[k - FIRST_KEPT].rows.snapshot()
            kept = len(rows["t"])
            j1 = min(kept, -(-i1 // size))
            times = np.asarray(rows["t"][j0:j1])
            lows = {c: np.asarray(rows[f"{c}.min"][j0:j1]) for c in self.columns}
            highs = {c: np.asarray(rows[f"{c}.max"][j0:j1]) for c in self.columns}
            tail = kept * size
        if i1 > tail:               # the newest samples, not yet a complete bin: one bin of their own
            start = max(tail, i0)
            times = np.append(times, t[start])
            for c in self.columns:
                raw = self._raw[c][start:i1]
                lows[c] = np.append(lows[c], np.fmin.reduce(raw))
                highs[c] = np.append(highs[c], np.fmax.reduce(raw))
        x = np.repeat(times, 2)
        ys = {c: np.column_stack((lows[c], highs[c])).ravel() for c in self.columns}
        return k, x, ys
