"""One session's figures, from a log as the log readers read it: charge in and out, energy, the
capacity reached, the resistance at the log's rest steps (``logs.rest_steps``), the cell deviation at
the end of the charge and the highest temperature."""
from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np

from ..logs.charge import MAX_STEP_S
from ..logs.model import STATES, Columns, Log
from ..logs.rest_steps import resistance_mohm_per_cell
from ..domain.chemistry import load_chemistry


@dataclass(frozen=True)
class SessionFigures:
    duration_s: float
    charge_in_mah: float | None
    charge_out_mah: float | None
    energy_in_wh: float | None
    energy_out_wh: float | None
    capacity_mah: float | None
    # "discharge": a discharge from full to the chemistry's cut-off (the pack's capacity); "not from full: N %":
    # it began at about N % charged; "partial: N %": it stopped with N % of its voltage range (from where it
    # began to the cut-off) covered. The last two are what was taken out, not the pack's capacity.
    capacity_from: str | None
    resistance_mohm_per_cell: float | None
    resistance_from: str | None        # "rest steps" (docs/validation.md) or "charger" (its own Ri readings)
    cell_deviation_mv: float | None
    t_max_c: float | None

    def as_dict(self) -> dict:
        return asdict(self)


def session_figures(log: Log, cells: int, chemistry: str | None = None) -> SessionFigures:
    """``cells``: the pack's cells in series (a log without balance taps does not say); ``chemistry``:
    the pack's, for whether a discharge reached its cut-off (None: not judged, a discharge counts)."""
    a = log.arrays()
    t, v, i = a["t"], a["voltage"], a["current"]
    current = log.meta.get("current_measured", True) and len(t) > 0
    e_in, e_out = _energy_wh(t, v, i) if current else (None, None)
    cap, cap_from = _capacity(log, cells, chemistry) if current else (None, None)
    r, r_from = None, None
    if current:
        r = resistance_mohm_per_cell(t, v, i, cells)
        r_from = "rest steps" if r is not None else None
    if r is None and log.resistance:
        # A charger that measured nothing sends 0: unknown, not 0 mΩ
        cells_mohm = [float(np.mean(c)) for _t, _p, c in log.resistance if c and all(x > 0 for x in c)]
        if cells_mohm:
            r, r_from = float(np.median(cells_mohm)), "charger"
    if r is not None and not r > 0:          # no rest step or reading that measures anything: unknown
        r, r_from = None, None
    temps = a["temp"][np.isfinite(a["temp"])]
    c = log.columns
    return SessionFigures(
        duration_s=float(t[-1] - t[0]) if len(t) else 0.0,
        charge_in_mah=_r(c.mah_in[-1], 1) if current else None,
        charge_out_mah=_r(c.mah_out[-1], 1) if current else None,
        energy_in_wh=_r(e_in, 3), energy_out_wh=_r(e_out, 3),
        capacity_mah=_r(cap, 1), capacity_from=cap_from,
        resistance_mohm_per_cell=_r(r, 1), resistance_from=r_from,
        cell_deviation_mv=_r(_end_of_charge_deviation_mv(log), 1),
        t_max_c=_r(float(temps.max()), 2) if len(temps) else None)


def _r(value: float | None, digits: int) -> float | None:
    return None if value is None else round(float(value), digits)


def _energy_wh(t: np.ndarray, v: np.ndarray, i: np.ndarray) -> tuple[float, float]:
    """V·I over time (trapezoid); a step over ``MAX_STEP_S`` (a gap) or back in time adds nothing, as
    for the charge (``logs.charge``)."""
    if len(t) < 2:
        return 0.0, 0.0
    dt = np.diff(t)
    p = v * i
    mean = (p[1:] + p[:-1]) / 2.0
    ok = (dt > 0) & (dt <= MAX_STEP_S)
    step = np.where(ok, mean * dt, 0.0) / 3600.0
    return float(step[step > 0].sum()), float(abs(step[step < 0].sum()))


def _capacity(log: Log, cells: int, chemistry: str | None) -> tuple[float | None, str | None]:
    """The largest charge taken out in one discharge phase, and whether it is what the pack holds:
    "discharge" when that discharge began full (a charge ran before it in the log, or its first loaded
    voltage says so) and ran to the chemistry's cut-off; "not from full: N %" when it began at about N %
    charged; "partial: N %" when it stopped with N % of its voltage range covered. A discharge that is the
    pack's capacity is preferred to a larger one that is not. A charge is no capacity (it may start part
    full and puts in more than the pack stores): a log with no discharge gives none."""
    c = log.columns
    found = []                                  # (is the capacity, taken, label)
    k, charged = 0, False
    for phase in log.phases():
        start = k
        k = int(np.searchsorted(c.t, phase.end_s, side="right")) if k < len(c) else k
        k = max(k, start)
        if phase.state == "charge" and k > start:
            charged = True
        if phase.state != "discharge" or k <= start:
            continue
        taken = float(c.mah_out[k - 1] - c.mah_out[max(start - 1, 0)])
        window = c.window(start, k)
        began = None if charged else _start_soc(window, cells, chemistry)
        covered = _range_covered(window, cells, chemistry)
        if began is not None and began < STARTED_FULL:
            found.append((False, taken, f"not from full: {began * 100:.0f} %"))
        elif covered is not None and covered < REACHED_CUT_OFF:
            found.append((False, taken, f"partial: {covered * 100:.0f} %"))
        else:
            found.append((True, taken, "discharge"))
    found = [f for f in found if f[1] > 1.0]
    if not found:
        return None, None
    _is, taken, label = max(found, key=lambda f: (f[0], f[1]))
    return taken, label


# A discharge that began at this state of charge or above began full: a NiMH pack's resting voltage
# does not tell 85 % from 100 % (its curve is flat at the top), so the bar is set below it.
STARTED_FULL = 0.8
# The loaded voltage is raised by the current through this many times the chemistry's reference cell's
# resistance before it is read as a resting voltage: an aged or smaller pack's resistance is higher.
RESISTANCE_ALLOWANCE = 3.0


def _start_soc(samples: Columns, cells: int, chemistry: str | None) -> float | None:
    """The state of charge a discharge began at, from its first loaded voltage per cell raised by the
    current through RESISTANCE_ALLOWANCE x the chemistry's cell resistance, read on its resting voltage
    curve; None when the chemistry or the cells are not known."""
    loaded = samples.current < -0.005
    if chemistry is None or cells < 1 or loaded.sum() < 3:
        return None
    chem = load_chemistry(chemistry)
    v_cell = float(np.median(samples.voltage[loaded][:3])) / cells
    amps = float(np.median(-samples.current[loaded][:3]))
    resting = v_cell + amps * chem.r0_ohm * RESISTANCE_ALLOWANCE
    return float(np.interp(resting, chem.ocv_v, chem.ocv_soc))


# A discharge that covered this much of its voltage range (start to cut-off) reached the cut-off: a
# charger ends a discharge at the cut-off voltage under load, within its rounding and the leads' drop.
REACHED_CUT_OFF = 0.9


def _range_covered(samples: Columns, cells: int, chemistry: str | None) -> float | None:
    """How much of the range from its first loaded voltage to the cut-off a discharge covered (1: it
    reached the cut-off); None when the chemistry or the cells are not known."""
    loaded = samples.voltage[samples.current < -0.005]
    if chemistry is None or cells < 1 or len(loaded) < 3:
        return None
    cut_off = load_chemistry(chemistry).discharge_end_v * cells
    top = float(np.median(loaded[:3]))
    if top <= cut_off:
        return 1.0
    return float(min(1.0, max(0.0, (top - float(loaded[-1])) / (top - cut_off))))


def _end_of_charge_deviation_mv(log: Log) -> float | None:
    """max − min cell at the last sample of the last charge phase with every cell read."""
    c = log.columns
    if c.cells.shape[1] < 2:
        return None
    read = np.flatnonzero((c.state == STATES.index("charge")) & (c.cells > 0).all(axis=1))
    if not len(read):
        return None
    cells = c.cells[read[-1]]
    return float(cells.max() - cells.min()) * 1000.0
