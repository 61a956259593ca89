"""The pack's resistance measured in a log (issue #26, decision (a)): where the current steps to a rest,
the voltage step per cell and ampere (``logs.rest_steps``, the method of docs/validation.md), and the
default model with its R0 and R1 scaled so that its own step, at the same delay after the current
stops, is the measured one. ``compare`` runs the macro with it, as it takes the start voltage and the
capacity from the log."""
from __future__ import annotations

import math
from dataclasses import dataclass, replace

import numpy as np

from ..logs import Log
from ..logs.rest_steps import RestStep, rest_steps
from ..domain.chemistry import Chemistry, load_chemistry
from .curve import Curve
from .fit import FitResult
from .fit_discharge import fit_curve

_NEAR_S = 600.0          # steps this close after the compared part (the rest that follows it) count as its own
_ROUNDS = 5              # at most this many fits with the scale set from the last one's capacity ...
_SETTLED = 0.01          # ... until the capacity moves less than this share


@dataclass(frozen=True)
class MeasuredR:
    ohm_per_cell: float        # the median of the steps read
    delay_s: float             # after the current stopped
    at_s: tuple[float, ...]    # the log's time of each step read (s on its own clock)

    def to_dict(self) -> dict:
        return {"mohm_per_cell": round(self.ohm_per_cell * 1000.0, 1), "delay_s": self.delay_s,
                "at_s": [round(t, 1) for t in self.at_s]}

    @staticmethod
    def from_dict(d: dict) -> "MeasuredR":
        return MeasuredR(float(d["mohm_per_cell"]) / 1000.0, float(d["delay_s"]), tuple(float(t) for t in d["at_s"]))


def measure(t: np.ndarray, v: np.ndarray, i: np.ndarray, cells: int, direction: str,
            span: tuple[float, float], current_a: float) -> MeasuredR | None:
    """The resistance from the steps of ``direction``'s current (charge: +, discharge: -) of at least half
    ``current_a`` (the curve's own: a step from a CV tail's last few percent reads its polarisation, the
    Pb absorption's 0.98 A 138 mΩ per cell) inside ``span`` (the compared part, on the log's clock) or
    within _NEAR_S after it; else from such steps anywhere in the log; None where it has none. A log
    sampled slower than once a second has its step read at twice its period (the first rest sample may
    straddle the step: the eStation BC6's 1.5 s)."""
    t, v, i = (np.asarray(x, float) for x in (t, v, i))
    ok = np.isfinite(t) & np.isfinite(v) & np.isfinite(i)
    t, v, i = t[ok], v[ok], i[ok]
    if len(t) < 3:
        return None
    period = float(np.median(np.diff(t)))
    delay = 1.0 if period <= 1.0 else 2.0 * period
    sign = 1.0 if direction == "charge" else -1.0
    # A step whose voltage moves against the current is no resistance (the Akkumatik reads its pack
    # lower at rest after a discharge): it is left out.
    steps = [s for s in rest_steps(t, v, i, min_current_a=max(0.05, 0.5 * current_a), delay_s=delay,
                                   max_delay_s=max(5.0, 2.5 * delay))
             if s.current_a * sign > 0 and s.ohm_per_cell(cells) > 0]
    near = [s for s in steps if span[0] <= s.time_s <= span[1] + _NEAR_S]
    use = near or steps
    return _median(use, cells, delay) if use else None


def measure_log(log: Log, cells: int, direction: str, span: tuple[float, float],
                current_a: float) -> MeasuredR | None:
    """``measure`` over the whole log (its rests lie outside the charge or discharge a curve holds)."""
    a = log.arrays()
    return measure(a["t"], a["voltage"], a["current"], cells, direction, span, current_a)


def measure_curve(log: Log | None, curve: Curve, cells: int) -> MeasuredR | None:
    """``measure_log`` around the curve read from ``log`` (None: a curve CSV, no rests to read)."""
    if log is None:
        return None
    return measure_log(log, cells, curve.direction, (curve.start_s, curve.start_s + float(curve.t[-1])),
                       float(np.median(np.abs(curve.i))))


def fit_with_measured_r(curve: Curve, chemistry: str, series: int, measured: MeasuredR) -> tuple[FitResult, float]:
    """The default model (capacity and start fitted) with its step made the measured one, and the scale
    on R0 and R1. The model's resistance scales with the capacity the fit finds, so the scale is set from
    a capacity, then again from the capacity found with it until that settles; begun from the default's
    capacity and from the charge the curve moved (a default far from the pack, the NiCd one on the
    Akkumatik pack, finds twice its capacity, and from there a second answer), the closer fit kept."""
    chem = load_chemistry(chemistry)
    moved = float(curve.mah[-1] if curve.direction == "charge" else curve.delivered_mah[-1])
    begins = (fit_curve(curve, chemistry, series, only_capacity=True).battery.capacity_mah, moved)
    answers = [_settle(curve, chem, series, measured, capacity) for capacity in begins]
    return min(answers, key=lambda a: a[0].figures["rmse_v_per_cell_mv"])


def _settle(curve: Curve, chem: Chemistry, series: int, measured: MeasuredR,
            capacity_mah: float) -> tuple[FitResult, float]:
    for _round in range(_ROUNDS):
        scaled, scale = with_measured_r(chem, capacity_mah, measured)
        result = fit_curve(curve, chem.name, series, only_capacity=True, base=scaled)
        settled = abs(result.battery.capacity_mah / capacity_mah - 1.0) < _SETTLED
        capacity_mah = result.battery.capacity_mah
        if settled:
            break
    return result, scale


def _median(steps: list[RestStep], cells: int, delay: float) -> MeasuredR:
    return MeasuredR(float(np.median([s.ohm_per_cell(cells) for s in steps])), delay,
                     tuple(s.time_s for s in steps))


def model_step(chem: Chemistry, capacity_mah: float, after_s: float) -> float:
    """The model's fall per cell and ampere ``after_s`` after the current stops: R0 and that much of R1,
    at the capacity's scale (R × Ah is constant within a chemistry)."""
    scale = chem.ref_capacity_ah * 1000.0 / capacity_mah
    return scale * (chem.r0_ohm + chem.r1_ohm * (1.0 - math.exp(-after_s / chem.tau1_s)))


def with_measured_r(chem: Chemistry, capacity_mah: float, measured: MeasuredR) -> tuple[Chemistry, float]:
    """The chemistry with R0 and R1 scaled so that its step at the measured delay is the measured one,
    and the scale."""
    scale = measured.ohm_per_cell / model_step(chem, capacity_mah, measured.delay_s)
    return replace(chem, r0_ohm=chem.r0_ohm * scale, r1_ohm=chem.r1_ohm * scale), scale

