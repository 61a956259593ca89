"""Fit each cell of a pack whose log has balance taps: its capacity, resistance and start state.

The pack is fitted first (``fit.fit``); the cells share its fitted chemistry (OCV table, slow
polarisation, heating), since a pack's cells are of one type. Each tap is then a one-cell curve driven
by the pack's current at every sample, its voltage compared at every sample of the log's direction
(charging, or discharging for a discharge), and three values move: the cell's capacity, where it started, and one factor on the pack's fitted resistances (R0, R1,
R2, as the pack fit's ``r_scale``). Fitted freely, with its own OCV offset and slope, a tap of a partial
charge trades its OCV against its capacity and start (the reason the pack fit pulls them towards the
table), and the spread between cells would be that trade rather than the cells. Why and what the
recordings give: docs/fit.md, "Cells"."""
from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from .cell_pack import CellSpec
from ..domain.chemistry import Chemistry
from .curve import Curve, CurveError
from .fit import LI, Battery, FitResult, simulate_curve, solver
from .fit_checks import cells_plausible, coverage
from ..i18n import _

# The taps are one per cell where their sum is this close to the pack voltage (median over the
# charge): the leads and connectors between them drop a few per cent at most (406DUO 4S at 4.4 A:
# 0.4 %); one NiMH tap (iCharger 3010B) or taps not wired are no cells.
_TAPS_AGREE = 0.05
_STEP_S = 10.0               # tap curves are decimated as the pack's fit decimates its curve
_SAMPLES = 1500
_MAX_NFEV = 60               # three values per cell: the fits on the recordings take 5-32 evaluations
_CAPACITY_RANGE = 3.0        # a cell holds at most 3x and at least a third of the pack's fitted capacity
_R_SCALE = (0.1, 10.0)
_SOC_MAX = 0.99
_BOUND_LOG = 0.01            # a value within 1 % of a bound is at it (as the pack fit)
# A tap within 5 mV of its highest voltage for 50 points more of the charge than the other taps'
# median was held there by the charger (its balancer bled it, or its current was cut for it): the
# X6 LiPo log's cell 3 sits at 4.205 V from the second second to the end (100 %), the others 24-27 %
# (in a CV tail every cell ends near its top: 18-40 % on the other LiPo logs, 97-98 % on every LiFe cell).
# Such a cell did not take the pack's current, so what the fit says of its capacity is not measured.
_HELD_MV = 5.0
_HELD_MARGIN = 0.5


@dataclass(frozen=True)
class CellFit:
    """One cell: ``r_scale`` multiplies the pack's fitted resistances, ``r_mohm`` is its R0 + R1 at its
    capacity (the step a current change makes within seconds)."""
    capacity_mah: float
    start_soc: float
    r_scale: float
    r_mohm: float
    rmse_v_mv: float
    top_v: float                 # the median of its samples within _HELD_MV of its highest: where it topped out
    held_share: float            # the share of the charge it spent there (0 for a discharge)
    at_bound: tuple[str, ...] = ()
    held: bool = False           # held at v_max by the charger while the others rose (see _HELD_MARGIN)
    coverage: dict | None = None  # fit_checks.coverage: whether its window fixes its capacity

    @property
    def measured(self) -> bool:
        """Whether its capacity is a measurement: it took the pack's current over enough of its range."""
        return not self.held and (self.coverage is None or self.coverage["fixed"])

    def as_dict(self, number: int) -> dict:
        return {"cell": number, "capacity_mah": round(self.capacity_mah, 1), "start_soc": round(self.start_soc, 4),
                "r_scale": round(self.r_scale, 4), "r_mohm": round(self.r_mohm, 2),
                "rmse_v_mv": round(self.rmse_v_mv, 2), "top_v": round(self.top_v, 4),
                "held_pct": round(self.held_share * 100.0, 1), "held": self.held, "at_bound": list(self.at_bound),
                "coverage": self.coverage, "capacity_measured": self.measured}


@dataclass(frozen=True)
class CellsFit:
    """The cells of a pack, cell 1 at its negative end, and the pack's fitted capacity."""
    cells: tuple[CellFit, ...]
    pack_capacity_mah: float

    @property
    def weakest(self) -> int:
        """The cell (1-based) that holds least (fills and empties first), among those that took the pack's
        current (a held cell's capacity is not measured); the lowest of all when every one was held."""
        free = [k for k, c in enumerate(self.cells) if c.measured] or range(len(self.cells))
        return 1 + min(free, key=lambda k: self.cells[k].capacity_mah)

    @property
    def highest_resistance(self) -> int:
        return 1 + max(range(len(self.cells)), key=lambda k: self.cells[k].r_mohm)

    def report(self) -> dict:
        """What ``zuml fit --json`` carries as ``cell_fit``."""
        return {"cells": [c.as_dict(k) for k, c in enumerate(self.cells, start=1)],
                "capacity_mah": _spread([c.capacity_mah for c in self.cells]),
                "r_mohm": _spread([c.r_mohm for c in self.cells]),
                "weakest": self.weakest, "highest_resistance": self.highest_resistance,
                "implausible": cells_plausible([c.capacity_mah for c in self.cells], [c.r_mohm for c in self.cells])}

    def saved(self) -> list[CellSpec]:
        """The cells as a battery file keeps them (``save_battery(..., cells=...)``): the taps' differences
        on the pack's own fit. Capacities are scaled so that their mean is the pack's fitted capacity and
        resistance factors so that theirs is 1: the taps leave out the leads the pack voltage includes, so
        their own level is not the pack's. A held cell's capacity, not measured, is taken as the others'
        mean. The start state is the run's (null): where the cells stood at this log's start is no property
        of the pack."""
        free = [c.capacity_mah for c in self.cells if not c.held] or [c.capacity_mah for c in self.cells]
        caps = np.array([float(np.mean(free)) if c.held else c.capacity_mah for c in self.cells])
        scales = np.array([c.r_scale for c in self.cells])
        return [CellSpec(round(float(cap * self.pack_capacity_mah / caps.mean()), 1), round(float(s / scales.mean()), 4))
                for cap, s in zip(caps, scales)]


def _spread(values: list[float]) -> dict:
    """min, max, mean and (max - min) / mean in per cent."""
    lo, hi, mean = min(values), max(values), sum(values) / len(values)
    return {"min": round(lo, 2), "max": round(hi, 2), "mean": round(mean, 2),
            "spread_pct": round((hi - lo) / mean * 100.0, 2) if mean else 0.0}


def taps_per_cell(curve: Curve, series: int) -> bool:
    """Whether the curve's balance taps are one per cell of a ``series`` pack."""
    if curve.cells_v is None or curve.cells_v.shape[1] != series or series < 2:
        return False
    total = np.sum(curve.cells_v, axis=1)
    ok = np.isfinite(total) & (curve.v > 0)
    if ok.sum() < 10:
        return False
    return abs(float(np.median(total[ok] / curve.v[ok])) - 1.0) <= _TAPS_AGREE


def fit_cells(result: FitResult) -> CellsFit | None:
    """Each cell of the fitted charge or discharge from its balance tap; None where the log has no tap per
    cell."""
    curve, series = result.curve, result.battery.series
    if not taps_per_cell(curve, series):
        return None
    chem, capacity = result.battery.chem, result.battery.capacity_mah
    start_soc = float(result.params.get("start_soc", 0.0))
    charge = curve.direction == "charge"
    cells = [_fit_tap(_tap(curve, k), chem, capacity, start_soc, charge) for k in range(series)]
    shares = [c.held_share for c in cells]
    held = [c.held_share - float(np.median(shares[:k] + shares[k + 1:])) > _HELD_MARGIN for k, c in enumerate(cells)]
    return CellsFit(tuple(replace(c, held=h) for c, h in zip(cells, held)), capacity)


def _tap(curve: Curve, k: int) -> Curve:
    """Tap k as a one-cell curve on the pack's current (samples where it was not read left out)."""
    v = curve.cells_v[:, k]
    ok = np.isfinite(v)
    return Curve(curve.t[ok], v[ok], curve.i[ok], None if curve.temp is None else curve.temp[ok], 0,
                 f"{curve.name} cell {k + 1}", curve.chemistry)


def _scaled(chem: Chemistry, factor: float) -> Chemistry:
    return replace(chem, r0_ohm=chem.r0_ohm * factor, r1_ohm=chem.r1_ohm * factor, r2_ohm=chem.r2_ohm * factor)


def _fit_tap(tap: Curve, chem: Chemistry, pack_capacity: float, start_soc: float, charge: bool) -> CellFit:
    least_squares = solver()

    work = tap.decimated(max(_STEP_S, float(tap.t[-1]) / _SAMPLES))
    by_current = np.zeros(len(work.t), bool)
    compared = work.i > 0 if charge else work.i < 0
    weight = 1000.0 / math.sqrt(max(int(compared.sum()), 1))
    lo = np.array([math.log(pack_capacity / _CAPACITY_RANGE), 0.0, math.log(_R_SCALE[0])])
    hi = np.array([math.log(pack_capacity * _CAPACITY_RANGE), _SOC_MAX, math.log(_R_SCALE[1])])

    def run(x: np.ndarray):
        battery = Battery(_scaled(chem, math.exp(x[2])), math.exp(x[0]), 1)
        return simulate_curve(battery, work, by_current, float(x[1]))

    def residuals(x: np.ndarray) -> np.ndarray:
        return (run(x).v[compared] - work.v[compared]) * weight

    x0 = np.clip([math.log(pack_capacity), start_soc, 0.0], lo + 1e-9, hi - 1e-9)
    try:
        sol = least_squares(residuals, x0, bounds=(lo, hi), diff_step=1e-3, x_scale="jac", max_nfev=_MAX_NFEV)
    except ValueError as exc:      # scipy's words ("Residuals are not finite in the initial point")
        raise CurveError(_("{name}: the cell's fit cannot start: the model gives no finite voltage along its "
                           "tap ({error})").format(name=tap.name, error=exc)) from None
    capacity, soc, factor = math.exp(sol.x[0]), float(sol.x[1]), math.exp(sol.x[2])
    r_mohm = (chem.r0_ohm + chem.r1_ohm) * factor * chem.ref_capacity_ah / (capacity / 1000.0) * 1000.0
    ends = [name for name, value, a, b in (("capacity_mah", sol.x[0], lo[0], hi[0]),
                                            ("r_scale", sol.x[2], lo[2], hi[2]))
            if min(abs(value - a), abs(value - b)) < _BOUND_LOG]
    # Held at a ceiling is a charge's: a discharge's top is its start, and no charger holds a cell there.
    along = tap.v[tap.i > 0 if charge else tap.i < 0]
    top = along[along >= float(along.max()) - _HELD_MV / 1000.0]
    window = float(tap.mah[-1] if charge else tap.delivered_mah[-1])
    cover = coverage(chem, (float(along[0]), float(along[-1])), window, capacity, soc, chem.name in LI)
    return CellFit(capacity, soc, factor, r_mohm, math.sqrt(2.0 * sol.cost), float(np.median(top)),
                   len(top) / len(along) if charge else 0.0, tuple(ends), coverage=cover)
