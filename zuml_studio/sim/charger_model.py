"""Power-stage limits, heat-sink temperature and balancer of a B6-class charger.

Numbers come from the package's ``resources/chargers/<name>.toml``. The heat sink is one
first-order thermal node: charging loses (1 - efficiency) of the output power
in the converter, discharging burns all of V * |I| in the load transistor.

The balancer (``[balancer]``, optional) watches each cell of a lithium pack during a charge:
it bleeds every cell more than ``spread_v`` above the lowest (through a load resistor on the
tap, ``bleed_r_ohm``: V_cell / R, or a regulated ``bleed_a``); the charge current is held so that no
cell passes its chemistry's ``ceiling_v``, and the charge ends when a cell is there and the current has
fallen to a tenth of the phase's own. With ``window_s`` it bleeds as the B6's firmware does
(docs/firmware.md, Balancer): windows of at most ``window_s`` of up to ``max_bleeders`` cells, the
highest first, each decided after ``settle_s`` with the loads off, once a cell reaches ``from_v`` or a
CV phase holds its voltage; a cell leaves its window early once it is presumed down to the lowest cell
that does not bleed (its reading plus what its own bleed took off it).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from math import exp

from .. import data
from ..data import DataFileError
from ..domain.end_reasons import EndCode, EndReason
from ..i18n import _


@dataclass(frozen=True)
class ChargerLimits:
    """What the power stage can do; currents in A (magnitudes), powers in W, pack voltage in V."""

    name: str
    max_charge_a: float
    max_charge_w: float
    max_discharge_a: float
    max_discharge_w: float
    max_v: float
    min_charge_a: float
    min_discharge_a: float
    charge_efficiency: float
    heatsink_r_k_per_w: float
    heatsink_c_j_per_k: float
    dpeak_window_s: float          # -dV: voltage averaged over windows this long
    dpeak_holdoff_s: float         # -dV: ignored this long after a phase starts (seed 001: 5-10 min)
    balancer: BalancerSpec | None = None    # None: the charger has no balancer


@dataclass(frozen=True)
class BalancerSpec:
    """How the charger balances a lithium pack's cells while it charges them."""

    bleed_r_ohm: float | None      # load resistor on each tap: the bleed is V_cell / R ...
    bleed_a: float | None          # ... or a regulated current (exactly one of the two)
    during: str                    # "charge": every charge phase; "cv": only phases that hold a voltage
    spread_v: float                # a cell bleeds while it is more than this above the lowest cell
    ceiling_v: dict[str, float]    # per chemistry: no cell is charged past this voltage
    window_s: float = 0.0          # a window's longest bleed (0: the cells of ``mask`` bleed every tick)
    settle_s: float = 0.0          # the loads off this long before a window's decision
    spread_off_v: float = 0.0      # a cell that bled in the last window bleeds again from this above the lowest
    max_bleeders: int = 0          # at most this many cells bleed at once
    from_v: dict[str, float] = field(default_factory=dict)   # per chemistry: no window while every cell is below


    def bleed(self, cell_v: float) -> float:
        """The current a bleeding cell at ``cell_v`` gives to its load, A."""
        return self.bleed_a if self.bleed_a is not None else max(0.0, cell_v) / self.bleed_r_ohm

    def mask(self, cell_voltages, bleeding: int = 0) -> int:
        """The cells to bleed now (bit k-1: cell k), from the cells' last readings: a cell starts when it
        is more than ``spread_v`` above the lowest and, once bleeding, goes on while it is above the
        lowest at all (as cheali bleeds every cell above the lowest once the spread passes its
        tolerance; without that its own bleed, lowering its reading, would switch it off and on)."""
        low = min(cell_voltages)
        start = low + self.spread_v
        mask = 0
        for k, v in enumerate(cell_voltages):
            if v > start or (bleeding >> k & 1 and v > low):
                mask |= 1 << k
        return mask

    def window(self, w: BalanceWindow, cell_voltages, dt: float, holding: bool, chemistry: str) -> int:
        """The cells that bleed over the next tick of ``dt`` s, ``w`` carrying the windows from tick to tick
        (without ``window_s``: ``mask``'s); ``holding``: the phase holds its voltage (then the windows run
        below ``from_v`` too). firmware/host/model/charger.c's zm_balance_window, operation for operation."""
        v = cell_voltages
        if not self.window_s > 0.0:
            w.mask = self.mask(v, w.mask)
            return w.mask
        if max(v) < self.from_v.get(chemistry, 0.0) and not holding:
            w.mask = w.bled = 0
            w.t = 0.0
            return 0
        w.t += dt
        if not w.mask:
            if w.t >= self.settle_s:
                w.before = list(v)
                w.mask = self._bleeders(v, w.bled)
                w.first = True
                w.t = 0.0
            return w.mask
        ref = -1
        for k, x in enumerate(v):
            if not w.mask >> k & 1 and (ref < 0 or x < v[ref]):
                ref = k
        keep = w.mask
        if w.first:
            # what each bleed took off its cell, against the lowest cell that does not bleed (the charge moves
            # them all as the loads go on)
            w.drop = [(w.before[k] - w.before[ref]) - (x - v[ref]) if w.mask >> k & 1 else 0.0
                      for k, x in enumerate(v)]
            w.first = False
        else:
            low = v[ref]
            for k, x in enumerate(v):
                if keep >> k & 1 and x + w.drop[k] <= low:
                    keep &= ~(1 << k)
        if w.t >= self.window_s or not keep:
            w.bled = w.mask
            keep = 0
            w.t = 0.0
        w.mask = keep
        return keep

    def _bleeders(self, v, bled: int) -> int:
        """The cells to bleed at a window's start, the highest first: more than ``spread_v`` above the lowest
        (``spread_off_v`` for one that bled in the last window), at most ``max_bleeders``; a tie goes to the
        first cell."""
        low = min(v)
        mask = 0
        for _pick in range(self.max_bleeders):
            best, at = 0.0, -1
            for k, x in enumerate(v):
                over = x - low
                if not mask >> k & 1 and over > best and (over > self.spread_v or
                                                          (bled >> k & 1 and over > self.spread_off_v)):
                    best, at = over, k
            if at < 0:
                break
            mask |= 1 << at
        return mask

    def ceiling_reason(self, chemistry: str, cell_voltages, current_a: float, own_a: float,
                       bleed_a=None) -> EndReason | None:
        """The end reason of a charge held at the ceiling: a cell read (to 1 mV) at the chemistry's ceiling
        and the charge the cells keep (``current_a`` less the mean of the cells' bleeds, ``bleed_a``), which the
        charger lowers to hold that cell there, fallen to a tenth of ``own_a``: a constant-current phase's own
        current (cheali: a cell at Vc and I <= minIc = Ic / 10), 0 for a phase that holds a voltage (its own
        current condition ends it as the hold lowers the current; this, once the bleeds take it all), < 0
        when the phase asks for no current now (a pause); else None."""
        ceiling = self.ceiling_v.get(chemistry)
        top = max(cell_voltages)
        at = cell_voltages.index(top)
        net = current_a - (sum(bleed_a) / len(bleed_a) if bleed_a else 0.0)
        if ceiling is None or own_a < 0.0 or net * 10.0 > own_a or round(top, 3) < ceiling:
            return None
        return EndReason(EndCode.CEILING, cell=at + 1, volts=ceiling)


@dataclass
class BalanceWindow:
    """A balancer's windows from tick to tick (zm_window_t), new at each phase's start."""

    mask: int = 0                  # the cells bleeding now (bit k-1: cell k)
    bled: int = 0                  # the cells that bled in the last window
    first: bool = False            # the window's first tick: its drops not measured yet
    t: float = 0.0                 # seconds in the window, or with the loads off
    before: list = field(default_factory=list)
    drop: list = field(default_factory=list)


def load_charger(name: str = "imax_b6") -> ChargerLimits:
    """Load ``resources/chargers/<name>.toml``; KeyError names the chargers there are."""
    known = data.names("chargers")
    if name not in known:
        raise KeyError(_("no charger {name!r}; known chargers: {known}").format(name=name, known=', '.join(known)))
    relative = f"chargers/{name}.toml"
    try:
        return _from_toml(data.read_toml(relative))
    except KeyError as exc:
        raise DataFileError(_("data file {location}: missing key {exc}").format(
                location=data.location(relative), exc=exc)) from None
    except (TypeError, ValueError) as exc:
        raise DataFileError(_("data file {location}: {exc}").format(
                location=data.location(relative), exc=exc)) from None


def _from_toml(parsed: dict) -> ChargerLimits:
    lim, hs, dpeak = parsed["limits"], parsed["heatsink"], parsed["delta_peak"]
    limits = ChargerLimits(
        name=str(parsed["name"]),
        max_charge_a=float(lim["max_charge_a"]),
        max_charge_w=float(lim["max_charge_w"]),
        max_discharge_a=float(lim["max_discharge_a"]),
        max_discharge_w=float(lim["max_discharge_w"]),
        max_v=float(lim["max_v"]),
        min_charge_a=float(lim["min_charge_a"]),
        min_discharge_a=float(lim["min_discharge_a"]),
        charge_efficiency=float(hs["charge_efficiency"]),
        heatsink_r_k_per_w=float(hs["r_k_per_w"]),
        heatsink_c_j_per_k=float(hs["c_j_per_k"]),
        dpeak_window_s=float(dpeak["window_s"]),
        dpeak_holdoff_s=float(dpeak["holdoff_s"]),
        balancer=_balancer(parsed["balancer"]) if "balancer" in parsed else None,
    )
    if not 0.0 < limits.charge_efficiency <= 1.0 or limits.heatsink_r_k_per_w <= 0 or limits.heatsink_c_j_per_k <= 0:
        raise ValueError(_("efficiency must be in (0, 1], heat-sink R and C > 0"))
    if limits.dpeak_window_s <= 0 or limits.dpeak_holdoff_s < 0:
        raise ValueError(_("-dV window must be > 0 s and its hold-off >= 0 s"))
    return limits


def _balancer(bal: dict) -> BalancerSpec:
    r, amps = bal.get("bleed_r_ohm"), bal.get("bleed_a")
    spec = BalancerSpec(None if r is None else float(r), None if amps is None else float(amps), str(bal["during"]),
                        float(bal["spread_v"]), {str(k): float(v) for k, v in bal["ceiling_v"].items()},
                        float(bal.get("window_s", 0.0)), float(bal.get("settle_s", 0.0)),
                        float(bal.get("spread_off_v", 0.0)), int(bal.get("max_bleeders", 0)),
                        {str(k): float(v) for k, v in bal.get("from_v", {}).items()})
    if (r is None) == (amps is None) or (spec.bleed_r_ohm or spec.bleed_a or 0.0) <= 0.0:
        raise ValueError(_("balancer: give bleed_r_ohm or bleed_a (one of them, > 0)"))
    if spec.during not in ("charge", "cv") or spec.spread_v < 0.0:
        raise ValueError(_("balancer: during must be \"charge\" or \"cv\", spread_v >= 0"))
    if spec.window_s and (spec.window_s < 0.0 or spec.settle_s < 0.0 or spec.max_bleeders < 1):
        raise ValueError(_("balancer: window_s and settle_s >= 0 s, max_bleeders >= 1"))
    if not all(0.0 < v < 10.0 for v in spec.ceiling_v.values()):
        raise ValueError(_("balancer: each ceiling_v must be 0..10 V"))
    return spec


class Charger:
    """Clamps requested currents to the power stage and tracks the heat-sink temperature."""

    def __init__(self, limits: ChargerLimits, ambient_c: float = 25.0) -> None:
        self.limits = limits
        self.ambient_c = float(ambient_c)
        self.heatsink_c = float(ambient_c)
        self._loss_per_w = 1.0 - limits.charge_efficiency
        self._r = limits.heatsink_r_k_per_w
        self._tau = limits.heatsink_r_k_per_w * limits.heatsink_c_j_per_k
        self._dt = -1.0
        self._a = 0.0

    def limit_current(self, requested_a: float, pack_v: float) -> float:
        """Clamp a charge (+) current to max A and max W (P = V*I), a discharge (-) current likewise."""
        lim = self.limits
        if requested_a > 0.0:
            i = min(requested_a, lim.max_charge_a)
            if pack_v > 0.0:
                i = min(i, lim.max_charge_w / pack_v)
            return i
        if requested_a < 0.0:
            i = min(-requested_a, lim.max_discharge_a)
            if pack_v > 0.0:
                i = min(i, lim.max_discharge_w / pack_v)
            return -i
        return 0.0

    def clip_reason(self, requested_a: float, pack_v: float) -> str:
        """Which limit ``limit_current`` applies to this request ("5 W discharge limit")."""
        lim = self.limits
        charging = requested_a > 0.0
        amps, watts = (lim.max_charge_a, lim.max_charge_w) if charging else (lim.max_discharge_a, lim.max_discharge_w)
        if pack_v > 0.0 and watts / pack_v < amps:
            text = _("{watts} W charge limit") if charging else _("{watts} W discharge limit")
            return text.format(watts=f"{watts:g}")
        text = _("{amps} A charge limit") if charging else _("{amps} A discharge limit")
        return text.format(amps=f"{amps:g}")

    def step(self, current_a: float, pack_v: float, dt: float) -> float:
        """Advance the heat sink dt seconds; returns heatsink_c."""
        if dt != self._dt:
            self._dt = dt
            self._a = exp(-dt / self._tau)
        power = abs(current_a * pack_v)
        loss = power * self._loss_per_w if current_a > 0.0 else power
        t_final = self.ambient_c + loss * self._r
        # Exact first-order response for a loss held constant over the step.
        self.heatsink_c = t_final + (self.heatsink_c - t_final) * self._a
        return self.heatsink_c
