"""Charge in and out, in one place for every format: the current integrated over time where the
log has a current, else the difference of the charger's own counter (which need not start at zero:
an Akkumatik discharge's counter starts at 1 867 mAh); where a log has both they are compared
(``disagreement``) and a difference over ``AGREE`` is said."""
from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ..streams.charge_counter import ChargeCounter

SECONDS_PER_HOUR = 3600.0
# A gap longer than this is not integrated over: the log was interrupted, the charger
# was not necessarily still pushing current.
MAX_STEP_S = 60.0
# The counter and the integrated current agree when they differ by at most this (relative).
AGREE = 0.03
# Totals below this are not compared (a counter's 1 mAh steps are a large part of them).
COMPARE_FROM_MAH = 20.0
# Samples worked at a time over a long log.
_BLOCK = 1 << 16


def integrate_current(times_s: Sequence[float] | np.ndarray,
                      currents_a: Sequence[float] | np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Cumulative mAh in (current > 0) and out (current < 0), trapezoidal per step.

    A step whose halves have opposite signs is split at the zero crossing; a step back in
    time or longer than ``MAX_STEP_S`` adds nothing. Worked in blocks so a long log's temporaries stay small."""
    t = np.asarray(times_s, float)
    i = np.asarray(currents_a, float)
    n = len(t)
    ins, outs = np.zeros(n), np.zeros(n)
    q_in = q_out = 0.0
    for lo in range(0, max(n - 1, 0), _BLOCK):
        hi = min(lo + _BLOCK, n - 1)
        dt = t[lo + 1:hi + 1] - t[lo:hi]
        a, b = i[lo:hi], i[lo + 1:hi + 1]
        same = (a >= 0.0) == (b >= 0.0)
        area = (a + b) * 0.5 * dt
        with np.errstate(invalid="ignore", divide="ignore"):
            cross = np.where(same, 0.0, dt * np.abs(a) / (np.abs(a) + np.abs(b)))
        a1, a2 = a * cross * 0.5, b * (dt - cross) * 0.5
        pos = np.where(same, np.maximum(area, 0.0), np.maximum(a1, 0.0) + np.maximum(a2, 0.0))
        neg = np.where(same, np.maximum(-area, 0.0), -np.minimum(a1, 0.0) - np.minimum(a2, 0.0))
        ok = (dt > 0.0) & (dt <= MAX_STEP_S)
        step_in = np.cumsum(np.where(ok, pos, 0.0) * (1000.0 / SECONDS_PER_HOUR)) + q_in
        step_out = np.cumsum(np.where(ok, neg, 0.0) * (1000.0 / SECONDS_PER_HOUR)) + q_out
        ins[lo + 1:hi + 1], outs[lo + 1:hi + 1] = step_in, step_out
        q_in, q_out = float(step_in[-1]), float(step_out[-1])
    return ins, outs


def charge_from_counter(counter_mah: Sequence[float]) -> tuple[list[float], list[float]]:
    """Cumulative mAh in and out from a charger's signed, per-phase capacity counter
    (``streams.charge_counter``: the live drivers count the same way), counted from its first value:
    a log that begins with the counter at 1 867 mAh has moved no charge yet."""
    counter = ChargeCounter()
    ins: list[float] = []
    outs: list[float] = []
    for c in counter_mah:
        q_in, q_out = counter.add(c)
        ins.append(q_in)
        outs.append(q_out)
    if ins:
        in0, out0 = ins[0], outs[0]
        ins = [q - in0 for q in ins]
        outs = [q - out0 for q in outs]
    return ins, outs


def counter_totals(counter_mah: Sequence[float] | np.ndarray) -> tuple[float, float]:
    """``charge_from_counter``'s last (in, out) without its lists (a long log's counter)."""
    counter = ChargeCounter()
    values = np.asarray(counter_mah, float)
    if not len(values):
        return 0.0, 0.0
    first = None
    for lo in range(0, len(values), _BLOCK):
        for c in values[lo:lo + _BLOCK].tolist():
            totals = counter.add(c)
            if first is None:
                first = totals
    return counter.totals[0] - first[0], counter.totals[1] - first[1]


def disagreement(integrated: tuple[float, float], counted: tuple[float, float]) -> dict | None:
    """The totals (in, out) of the integrated current and of the counter, and the larger relative
    difference of the two, when it is over ``AGREE``; None when they agree."""
    worst = 0.0
    for a, b in zip(integrated, counted):
        top = max(abs(a), abs(b))
        if top >= COMPARE_FROM_MAH:
            worst = max(worst, abs(a - b) / top)
    if worst <= AGREE:
        return None
    return {"in_integrated_mah": round(integrated[0], 1), "out_integrated_mah": round(integrated[1], 1),
            "in_counter_mah": round(counted[0], 1), "out_counter_mah": round(counted[1], 1),
            "difference": round(worst, 4)}
