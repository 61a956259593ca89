"""Charge in and out, in one place for every format: the current integrated over time where the
log has a current, else the difference of the charger's own counter (which need not start at zero:
an Akkumatik discharge's counter starts at 1 867 mAh); where a log has both they are compared
(``disagreement``) and a difference over ``AGREE`` is said."""
from __future__ import annotations

from collections.abc import Sequence

from ..device.charge_counter import ChargeCounter

SECONDS_PER_HOUR = 3600.0
# A gap longer than this is not integrated over: the log was interrupted, the charger
# was not necessarily still pushing current.
MAX_STEP_S = 60.0
# The counter and the integrated current agree when they differ by at most this (relative).
AGREE = 0.03
# Totals below this are not compared (a counter's 1 mAh steps are a large part of them).
COMPARE_FROM_MAH = 20.0


def integrate_current(times_s: Sequence[float], currents_a: Sequence[float]) -> tuple[list[float], list[float]]:
    """Cumulative mAh in (current > 0) and out (current < 0), trapezoidal per step.

    A step whose halves have opposite signs is split at the zero crossing; a step back in
    time or longer than ``MAX_STEP_S`` adds nothing."""
    q_in = q_out = 0.0
    ins: list[float] = []
    outs: list[float] = []
    prev_t = prev_i = None
    for t, i in zip(times_s, currents_a):
        if prev_t is not None:
            dt = t - prev_t
            if 0.0 < dt <= MAX_STEP_S:
                if (prev_i >= 0.0) == (i >= 0.0):
                    area = (prev_i + i) * 0.5 * dt
                    pos, neg = (area, 0.0) if area >= 0 else (0.0, -area)
                else:
                    cross = dt * abs(prev_i) / (abs(prev_i) + abs(i))
                    a1, a2 = prev_i * cross * 0.5, i * (dt - cross) * 0.5
                    pos, neg = max(a1, 0.0) + max(a2, 0.0), -min(a1, 0.0) - min(a2, 0.0)
                q_in += pos * 1000.0 / SECONDS_PER_HOUR
                q_out += neg * 1000.0 / SECONDS_PER_HOUR
        ins.append(q_in)
        outs.append(q_out)
        prev_t, prev_i = t, i
    return ins, outs


def charge_from_counter(counter_mah: Sequence[float]) -> tuple[list[float], list[float]]:
    """Cumulative mAh in and out from a charger's signed, per-phase capacity counter
    (``device.charge_counter``: the live drivers count the same way), counted from its first value:
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
