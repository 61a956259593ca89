"""A pack of unequal cells: one `battery.Pack` state per cell (its own capacity, resistance and
state of charge; its own RC, overcharge and thermal state), in series, with the charger's balancer
bleeding chosen cells.

The pack's terminal voltage is the sum of the cells'. The CV solve finds the one series current
that makes that sum the set voltage: each cell's end-of-step voltage is piecewise linear and rising
in its current (`Pack.cv_terms`), so a Newton step on the sum, kept inside the bracket the earlier
steps found (bisection when it leaves it), lands on the solution in one or two steps once it is in
the right OCV segments.

A pack of identical cells never comes here: `build_pack` returns the one-state `Pack` for it (the
firmware's differential test and the speed of an ordinary run depend on that).
"""
from __future__ import annotations

import random
from bisect import bisect_right
from dataclasses import dataclass, replace
from math import inf
from typing import Sequence

from .battery import _COLLAPSE_V_PER_SOC, _SOC_FLOOR, Pack
from ..domain.chemistry import Chemistry
from ..i18n import _

_CV_TOLERANCE_V = 1e-9        # per pack: the interpreter measures to 1 µV
_CV_MAX_STEPS = 80


@dataclass(frozen=True)
class CellSpec:
    """One cell: its capacity, its resistance as a multiple of the pack's cell resistance, its
    start state of charge (None: the run's)."""

    capacity_mah: float
    r_scale: float = 1.0
    soc: float | None = None


def check_cells(cells: Sequence[CellSpec]) -> None:
    """ValueError with one line naming the first bad cell."""
    for k, c in enumerate(cells, 1):
        if not 0.0 < c.capacity_mah < 1e7:
            raise ValueError(_("cell {k}: capacity_mah must be > 0").format(k=k))
        if not 0.05 <= c.r_scale <= 20.0:
            raise ValueError(_("cell {k}: r_scale must be 0.05..20").format(k=k))
        if c.soc is not None and not 0.0 <= c.soc <= 1.0:
            raise ValueError(_("cell {k}: soc must be 0..1 or null").format(k=k))


def spread_cells(capacity_mah: float, series: int, spread: tuple[float, float, float] | None = None,
                 seed: int = 1, soc: float = 0.0) -> list[CellSpec]:
    """Cells drawn reproducibly (`seed`): each cell's capacity and resistance uniformly within ± the
    spread's CAP and R percent of the pack's, its start state of charge within ± SOC percentage
    points of `soc` (no SOC spread: the run's start state)."""
    cap_pct, r_pct, soc_pct = spread or (0.0, 0.0, 0.0)
    rng = random.Random(seed)
    cells = []
    for _k in range(series):
        u_cap, u_r, u_soc = rng.uniform(-1, 1), rng.uniform(-1, 1), rng.uniform(-1, 1)
        cells.append(CellSpec(capacity_mah * (1.0 + u_cap * cap_pct / 100.0), 1.0 + u_r * r_pct / 100.0,
                              min(1.0, max(0.0, soc + u_soc * soc_pct / 100.0)) if soc_pct else None))
    return cells


def weaken(cells: Sequence[CellSpec], pct: float, cell: int | None = None) -> list[CellSpec]:
    """The cells with one (the last unless `cell`, 1-based) holding `pct` % less capacity."""
    out = list(cells)
    k = (cell or len(out)) - 1
    out[k] = replace(out[k], capacity_mah=out[k].capacity_mah * (1.0 - pct / 100.0))
    return out


def uniform(cells: Sequence[CellSpec], capacity_mah: float) -> bool:
    """Every cell the pack's own: the one-state pack models it exactly."""
    return all(c.capacity_mah == capacity_mah and c.r_scale == 1.0 and c.soc is None for c in cells)


def build_pack(chem: Chemistry, capacity_mah: float, series: int, soc: float = 0.0, ambient_c: float = 25.0,
               cells: Sequence[CellSpec] | None = None) -> Pack | CellPack:
    """The one-state `Pack` when the cells are identical (or not given), else a `CellPack`."""
    if cells is None or uniform(cells, capacity_mah):
        return Pack(chem, capacity_mah, series, soc, ambient_c)
    if len(cells) != series:
        raise ValueError(_("{given} cells given for a pack of {series}").format(given=len(cells), series=series))
    return CellPack(chem, capacity_mah, cells, soc, ambient_c)


class CellPack:
    """Cells in series, each a one-cell `Pack`; quacks like `Pack` for the interpreter."""

    per_cell = True

    def __init__(self, chem: Chemistry, capacity_mah: float, cells: Sequence[CellSpec], soc: float = 0.0,
                 ambient_c: float = 25.0) -> None:
        check_cells(cells)
        self.chem = chem
        self.capacity_mah = float(capacity_mah)
        self.series = len(cells)
        self.ambient_c = float(ambient_c)
        # A cell's resistance is the pack's cell resistance x r_scale, whatever its own capacity
        # (the one-cell Pack would scale it by 1/capacity).
        self.cells = [Pack(chem, c.capacity_mah, 1, soc if c.soc is None else c.soc, ambient_c,
                           c.r_scale * c.capacity_mah / capacity_mah) for c in cells]
        self.specs = list(cells)
        self._q = [c.capacity_mah for c in cells]
        self._q_total = sum(self._q)
        self.bleed_a = [0.0] * self.series     # the balancer's current out of each cell, A
        self.current = 0.0
        self._cv_guess = 0.0
        self.cell_voltages = [c.voltage for c in self.cells]
        self.voltage = sum(self.cell_voltages)
        self.cell_voltage = self.voltage / self.series

    @property
    def soc(self) -> float:
        """The charge the cells hold over what they can hold (capacity-weighted)."""
        return sum(c.soc * q for c, q in zip(self.cells, self._q)) / self._q_total

    @property
    def temp_c(self) -> float:
        """The pack's temperature: the mean of the cells' (one sensor on the pack)."""
        return sum(c.temp_c for c in self.cells) / self.series

    def open_circuit_voltage(self) -> float:
        return sum(c.open_circuit_voltage() for c in self.cells)

    def step(self, current_a: float, dt: float) -> float:
        """Advance dt seconds at `current_a` through the pack (+ = charge), each cell less its bleed."""
        volts = self.cell_voltages = [c.step(current_a - b, dt) for c, b in zip(self.cells, self.bleed_a)]
        self.current = current_a
        v = self.voltage = sum(volts)
        self.cell_voltage = v / self.series
        return v

    def set_bleed(self, mask: int, balancer) -> None:
        """Bleed the cells of ``mask`` (bit k-1: cell k) through ``balancer`` (a `BalancerSpec`) from now on."""
        if mask:
            self.bleed_a = [balancer.bleed(v) if mask >> k & 1 else 0.0 for k, v in enumerate(self.cell_voltages)]
        elif any(self.bleed_a):
            self.bleed_a = [0.0] * self.series

    def current_for_voltage(self, v_pack: float, dt: float) -> float:
        """The series current that makes the sum of the cells' voltages v_pack at the end of a step of dt."""
        terms = [(c.cv_terms(dt), c.soc, c._xs, c._ys, c._slopes, b) for c, b in zip(self.cells, self.bleed_a)]
        x = self._cv_guess = _solve(terms, v_pack, self._cv_guess)
        return x

    def current_for_ceiling(self, current_a: float, ceiling_v: float, dt: float) -> float:
        """The lower of ``current_a`` and, for each cell, the series current that puts it at ``ceiling_v`` at
        the end of a step of dt (never below 0): a balancing charger holds its highest cell at the ceiling
        and the current follows (cheali derives the current from the cells' voltages)."""
        for c, b in zip(self.cells, self.bleed_a):
            term = (c.cv_terms(dt), c.soc, c._xs, c._ys, c._slopes, b)
            if _cell_voltage(term, current_a)[0] > ceiling_v:
                current_a = _solve((term,), ceiling_v, current_a)
        return current_a if current_a > 0.0 else 0.0


def _solve(terms, v_target: float, x: float) -> float:
    """The series current at which the cells of ``terms`` sum to ``v_target`` at the end of the step: Newton
    from ``x``, kept inside the bracket found so far (bisection when it leaves it)."""
    lo, hi = -inf, inf
    for _step in range(_CV_MAX_STEPS):
        f, df = -v_target, 0.0
        for term in terms:
            v, dv = _cell_voltage(term, x)
            f += v
            df += dv
        if abs(f) <= _CV_TOLERANCE_V:
            break
        if f < 0.0:
            lo = x
        else:
            hi = x
        nx = x - f / df
        if not lo < nx < hi:
            nx = 0.5 * (lo + hi)
        if hi - lo < 1e-12:
            # A jump (a cell's O2 overvoltage as its current changes sign): no current gives
            # the voltage exactly; the one just below it is held.
            x = lo
            break
        x = nx
    return x


def _cell_voltage(term: tuple, current: float) -> tuple[float, float]:
    """One cell's voltage at the end of the step at series current `current`, and its slope."""
    (rest, r_ohmic, g_charge, extra, vp, r_pol, vp_max, r_dis, g_dis, x0, b_x), s, xs, ys, slopes, bleed = term
    i = current - bleed
    if i > 0.0:
        g = g_charge
        v = rest + extra + r_ohmic * i
        dv = r_ohmic
        pol = vp + i * r_pol
        if pol > vp_max:
            v += vp_max - vp
        else:
            v += i * r_pol
            dv += r_pol
    else:
        g = g_dis
        v = rest + r_dis * i
        dv = r_dis
    gx = g * b_x
    s += g * i
    if s > 1.0:
        # `step` holds a full cell at 1: its bulk no longer rises with the current
        s = 1.0
        g = 0.0
    s += x0 + gx * i      # the surface, where the OCV is read (Pack.step)
    g += gx
    if s < 0.0:
        if s < _SOC_FLOOR:
            return v + ys[0] + _SOC_FLOOR * _COLLAPSE_V_PER_SOC, dv
        return v + ys[0] + s * _COLLAPSE_V_PER_SOC, dv + g * _COLLAPSE_V_PER_SOC
    j = bisect_right(xs, s)
    last = len(xs) - 1
    if j > last:
        j = last
    slope = slopes[j - 1]
    return v + ys[j - 1] + (s - xs[j - 1]) * slope, dv + g * slope
