"""Record sets (DataExplorer's word: one charge, pause, discharge… of a session), one rule for the
``.osd`` reader and the CSV exports that hold ``### RECORDSET`` blocks.

Where a set lies on the session's time line: at its start time stamp relative to the first set's,
but never before the previous set's end plus one time step. Which way it goes: its name says
(…Entladen…/…discharg… a discharge, …Laden…/…charg… a charge, …Pause… a pause, …Idle… idle, as
``zuml log export --dataexplorer`` names them); a set whose name
says neither, logged with a current that is never negative, is a discharge when its voltage falls
under load (a falling voltage under load is never a charge: an export with positive discharge
current), else the current's sign decides."""
from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from .model import STATES, SampleBuilder, states_from_current

# Currents within this of zero are not load (as model.state_from_current).
LOAD_A = 0.005
# A set whose voltage under load ends this much (relative) below where it began is discharging.
FALL = 0.02


def direction_of(name: str) -> str:
    """"discharge", "charge", "pause", "idle", or "" when the set's name does not say."""
    lower = name.lower()
    if "entlad" in lower or "discharg" in lower:
        return "discharge"
    if "lad" in lower or "charg" in lower:
        return "charge"
    if "pause" in lower:
        return "pause"
    return "idle" if "idle" in lower else ""


def direction_by_voltage(volts: Sequence[float], amps: Sequence[float] | None) -> str:
    """"discharge" for a set logged with a current never below zero whose voltage under load falls
    (its last tenth's median more than ``FALL`` below its first tenth's), else ""."""
    if amps is None:
        return ""
    i = np.asarray(amps, float)
    v = np.asarray(volts, float)
    if len(i) != len(v) or (i < -LOAD_A).any():
        return ""
    loaded = v[i > LOAD_A]
    if len(loaded) < 10:
        return ""
    tenth = max(len(loaded) // 10, 1)
    first, last = float(np.median(loaded[:tenth])), float(np.median(loaded[-tenth:]))
    return "discharge" if first > 0 and last < first * (1.0 - FALL) else ""


def offset_s(end_s: float | None, step_s: float, start_ms: float, first_start_ms: float | None) -> float:
    """Where a set whose own time starts at 0 begins on the session's time line."""
    offset = 0.0 if end_s is None else end_s + step_s
    if start_ms > 0 and first_start_ms is not None and end_s is not None:
        offset = max(offset, (start_ms - first_start_ms) / 1000.0)
    return offset


def add_set(builder: SampleBuilder, name: str, t: Sequence[float], volts: Sequence[float],
            amps: Sequence[float] | None, mah: Sequence[float] | None = None, *,
            temp: Sequence[float] | None = None, heatsink: Sequence[float] | None = None,
            cells: Sequence[Sequence[float]] | np.ndarray | None = ()) -> str:
    """One set's samples (columns, ``cells`` one per cell or samples × cells; None: not logged) in its direction (current and charge signed by
    it; a pause holds the charge counter). Returns the direction used ("" : the current's sign)."""
    direction = direction_of(name) or direction_by_voltage(volts, amps)
    held = builder.last("counter")
    t = np.asarray(t, float)
    n = len(t)
    i = np.zeros(n) if amps is None else np.array(amps, float)
    q = None if mah is None else np.array(mah, float)
    if direction == "discharge":
        np.negative(np.abs(i, out=i), out=i)
        if q is not None:
            np.negative(np.abs(q, out=q), out=q)
    elif direction == "charge":
        np.abs(i, out=i)
        if q is not None:
            np.abs(q, out=q)
    elif q is not None:
        q = np.where(i < -LOAD_A, -np.abs(q), q)        # a counter that counts up in either direction
    if direction == "pause" and q is not None:
        q = np.full(n, 0.0 if held is None else held)
    state = np.full(n, STATES.index(direction), np.int8) if direction else states_from_current(i)
    builder.add_columns(t, np.asarray(volts, float), i, state,
                        temp=None if temp is None else np.asarray(temp, float),
                        heatsink=None if heatsink is None else np.asarray(heatsink, float),
                        cells=cells if isinstance(cells, np.ndarray) or cells is None else
                        np.column_stack([np.asarray(c, float) for c in cells]) if len(cells) else None,
                        counter=q)
    return direction
