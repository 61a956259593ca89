"""Fit a chemistry's battery model to a measured discharge (a capacity test), and the figures of one.

The model is driven by the log's current (negative); the voltage is compared while the current flows,
and the delivered capacity is the model's charge taken out until its voltage reaches the log's end
voltage (where the charger stopped), driven on at the log's last current where the log ends first.
What is fitted: the capacity, the start state, the resistance, the OCV offset and slope and the
discharge knee (``k_discharge_ohm``), the slow RC pair, and the heat terms for NiCd/NiMH with a
temperature channel (docs/fit.md). The limits are the issue's (docs/validation.md)."""
from __future__ import annotations

import math

import numpy as np

from . import engine
from .cell_pack import CellSpec
from ..domain.chemistry import Chemistry, load_chemistry
from .curve import Curve, require_discharge
from .fit_checks import coverage, delivered_check, heat_check
from .fit import (COMMON_PARAMS, DIFFUSION, LI, NI, Battery, FitResult, Param, Run, at_bounds, check_series, fit,
                  fit_samples, fitted_chemistry, guess_series, ocv_prior, quality, rmse_temp, simulate_curve, soc_at_ocv,
                  solve_params,
                  start_error, temp_rise)

_PAUSE_FRACTION = 0.5        # samples below this share of the discharge current are pauses, not compared
_CAPACITY_WEIGHT = 7.0       # 1 % of delivered capacity weighs as 7 mV per cell (3 % is about a voltage limit)
_TEMP_WEIGHT = 1.0           # 1 °C of temperature error weighs as 1 mV per cell, as on a charge
_RUN_ON = 3.0                # the model is driven past the log's end for at most this many times its charge
_RUN_ON_STEP_S = 10.0       # at least this, or the curve's own step
# A charger that ends a discharge by holding its end voltage steps the current down (the Akkumatik 2S Li-ion
# log: 1.5 A to 0.35 A at 3.33 V/cell over its last minutes; the Akkumatik NiCd one 1.0 to 0.2 A at 3.40-3.45 V
# over its last 9 minutes, 10 % of its charge): samples within _HOLD_V of the lowest voltage
# under current, at less than _HOLD_I of the current before, are driven by the log's voltage as a charge's CV.
_HOLD_V = 0.02
_HOLD_I = 0.92
_HOLD_WEIGHT = 150.0         # 10 % of the discharge current weighs as 15 mV per cell (as a charge's CV)
_KNEE = Param("k_discharge_ohm", 1e-5, 0.1, True)
# The slow RC pair for every family: from rest into a discharge a pack's voltage falls for minutes
# (the Akkumatik NiCd pack 90 mV/cell over its first four minutes after a charge), more than R0 and R1 do.
_SLOW = (Param("r2_ohm", 1e-4, 2.0, True), Param("tau2_s", 60.0, 36000.0, True))
_HEAT = (Param("k_t_v_per_k", 0.0, 0.03), Param("ha_w_per_k", 0.005, 0.5, True), Param("cth_j_per_k", 5.0, 300.0, True))
_R_STARTS = (0.1, 1.0, 4.0)  # the full fit begins from the default's resistance, a tenth and 4x it
_START_SOC = Param("start_soc", 0.05, 1.0)    # a discharge mostly starts full
# One cell emptying before the others shows on the pack's voltage as a step: a fall of at least
# _STEP_SHARE of a cell's voltage within _STEP_WINDOW_S, the discharge going on for _STEP_AFTER_S after it
# (the AkkuMaster NiMH pack falls 4.42 -> 3.43 V, one of its four cells, within two minutes 13 minutes
# before its end). Where a pack shows one, the fit tries one more parameter, the weakest cell's capacity
# over the others' (the others equal), and keeps it only where it brings the RMSE below _WEAK_GAIN of the
# equal cells' and by _WEAK_GAIN_MV at least.
_STEP_WINDOW_S = 120.0
_STEP_SHARE = 0.5
_STEP_AFTER_S = 180.0
_WEAK = Param("weak_share", 0.2, 0.99)
_WEAK_GAIN = 0.8
_WEAK_GAIN_MV = 3.0


def fit_curve(curve: Curve, chemistry: str, series: int, **kw) -> FitResult:
    """``fit`` for a charge, ``fit_discharge`` for a discharge: each direction on its own."""
    return (fit_discharge if curve.direction == "discharge" else fit)(curve, chemistry, series, **kw)


def discharge_current(curve: Curve) -> float:
    """The discharge current (A, positive): the median where current flows out."""
    out = -curve.i[curve.i < 0]
    return float(np.median(out)) if len(out) else 1.0


def discharging(curve: Curve) -> np.ndarray:
    """Samples at the discharge current, not in a pause, and not the first: a charger logs the voltage it
    read before the load (the Akkumatik log holds the charged pack's 6.196 V for 3 s at -1 A)."""
    use = -curve.i >= _PAUSE_FRACTION * discharge_current(curve)
    use[0] = False
    return use


def end_voltage(curve: Curve) -> float:
    """Where the logged discharge stopped: its last voltage under current."""
    use = np.flatnonzero(discharging(curve))
    return float(curve.v[use[-1]]) if len(use) else float(curve.v[-1])


def hold_mask(curve: Curve) -> np.ndarray:
    """Samples where the charger held the discharge's end voltage and stepped its current down (see _HOLD_V)."""
    out = -curve.i
    mask = np.zeros(len(curve.t), bool)
    flowing = out > 0.0
    if not flowing.any():
        return mask
    v_min = float(curve.v[flowing].min())
    reached = np.flatnonzero(flowing & (curve.v <= v_min * (1.0 + _HOLD_V)))
    first = int(reached[0])
    before = out[:first + 1][flowing[:first + 1]]
    mask[first:] = flowing[first:] & (out[first:] < _HOLD_I * float(np.median(before))) & \
        (curve.v[first:] <= v_min * (1.0 + _HOLD_V))
    return mask


def model_delivered(battery: Battery, curve: Curve, start_soc: float, end_v: float,
                    hold: np.ndarray | None = None) -> tuple[Run, float]:
    """The model along the curve and the mAh it delivers until its voltage first reaches ``end_v``
    (interpolated between samples); where it is still above at the log's end it is driven on at the
    log's last discharge current (up to _RUN_ON times the log's charge). Where the log ``hold``s its end
    voltage the model is held there too and delivers what its own current takes out over the log's window
    (cut where it reaches ``end_v`` before the hold: a model that empties early is not a fit)."""
    return Delivery(curve, end_v, hold)(battery, start_soc)


class Delivery:
    """`model_delivered` along one curve, what does not depend on the model computed once (a fit runs it
    hundreds of times)."""

    def __init__(self, curve: Curve, end_v: float, hold: np.ndarray | None = None) -> None:
        self.curve, self.end_v = curve, end_v
        self.hold = hold = np.zeros(len(curve.t), bool) if hold is None else hold
        self.mah = curve.delivered_mah
        use = discharging(curve) & ~hold
        if hold.any():
            use[int(np.argmax(hold)):] = False
        self.use = use
        self.i_end = -discharge_current(curve)
        # The run-on in steps of the curve's own (a decimated curve's are coarser): in 10 s steps a 10 h lead-acid
        # discharge driven on for hours cost 24 s a fit.
        self.step_s = max(_RUN_ON_STEP_S, float(np.median(np.diff(curve.t)))) if len(curve.t) > 1 else _RUN_ON_STEP_S
        self.step_mah = -self.i_end * self.step_s / 3.6
        taken = float(self.mah[-1])
        limit = taken + _RUN_ON * max(taken, 1.0)
        # The run-on's running sums, as a loop adding step_mah to the log's charge makes them (cumsum adds in
        # order): where each step starts, and the sum that ends the run-on.
        count = int((limit - taken) / self.step_mah) + 2 if self.step_mah > 0 else 0
        sums = np.cumsum(np.concatenate(([taken], np.full(count, self.step_mah))))
        n = int(np.argmax(sums >= limit)) if (sums >= limit).any() else len(sums)
        self.marks, self.run_on_end = sums[:n], float(sums[n]) if n < len(sums) else taken
        self._run_on_track = None

    def __call__(self, battery: Battery, start_soc: float) -> tuple[Run, float]:
        curve, end_v, hold, mah = self.curve, self.end_v, self.hold, self.mah
        pack = battery.pack(start_soc, curve.ambient_c)
        run = simulate_curve(battery, curve, hold, start_soc, pack=pack)
        below = np.flatnonzero(self.use & (run.v <= end_v))
        if hold.any() and not len(below):
            return run, float(Curve(curve.t, run.v, run.i, None, 0).delivered_mah[-1])
        if len(below):
            k = int(below[0])
            if k == 0:
                return run, 0.0
            v0, v1 = run.v[k - 1], run.v[k]
            share = (v0 - end_v) / (v0 - v1) if v0 > v1 else 1.0
            return run, float(mah[k - 1] + (mah[k] - mah[k - 1]) * min(1.0, max(0.0, share)))
        return run, self._run_on(pack, float(run.v[-1]))

    def _run_on(self, pack, v_before: float) -> float:
        """The model driven on at the log's discharge current from its end until it reaches ``end_v``."""
        end_v, step_mah, marks = self.end_v, self.step_mah, self.marks
        if not len(marks):
            return self.run_on_end
        if engine.drivable(pack):
            if self._run_on_track is None:
                n = len(marks)
                self._run_on_track = engine.Track(np.full(n, self.step_s), np.full(n, self.i_end), np.zeros(n),
                                                  np.zeros(n, bool))
            v = engine.drive(pack, self._run_on_track, end_v)[0]
        else:
            v = []
            for _ in marks:
                v.append(pack.step(self.i_end, self.step_s))
                if v[-1] <= end_v:
                    break
        if v[-1] > end_v:
            return self.run_on_end
        before = v[-2] if len(v) > 1 else v_before
        share = (before - end_v) / (before - v[-1]) if before > v[-1] else 1.0
        return float(marks[len(v) - 1]) + step_mah * share


def cell_step(curve: Curve, series: int) -> float | None:
    """The delivered mAh where the pack's voltage steps down by a cell's (the middle of the steepest such
    fall), None where it shows no such step."""
    use = discharging(curve)
    t, v, mah = curve.t[use], curve.v[use], curve.delivered_mah[use]
    if series < 2 or len(t) < 3:
        return None
    later = np.searchsorted(t, t + _STEP_WINDOW_S)
    ok = (later < len(t)) & (t >= t[0] + _STEP_WINDOW_S)
    ok &= t[np.minimum(later, len(t) - 1)] <= t[-1] - _STEP_AFTER_S
    at = np.flatnonzero(ok)
    if not len(at):
        return None
    drop = v[at] - v[later[at]]
    k = int(np.argmax(drop))
    if drop[k] < _STEP_SHARE * float(np.median(v)) / series:
        return None
    return float(0.5 * (mah[at[k]] + mah[later[at[k]]]))


def _battery(chem: Chemistry, values: dict, series: int) -> Battery:
    """The fitted battery; with ``weak_share`` its last cell holds that share of the others' capacity."""
    q = values["capacity_mah"]
    share = values.get("weak_share")
    cells = None if share is None else (CellSpec(q),) * (series - 1) + (CellSpec(q * share),)
    return Battery(fitted_chemistry(chem, values), q, series, cells)


def discharge_figures(curve: Curve, run: Run, series: int, model_mah: float) -> dict:
    """The figures ``zuml fit --json`` prints for a discharge (the keys of a charge's, and ``capacity``)."""
    hold = hold_mask(curve)
    use = discharging(curve) & ~hold
    err_v = (run.v[use] - curve.v[use]) / series * 1000.0
    span = [round(float(curve.t[0]), 1), round(float(curve.t[-1]), 1)]
    out: dict = {"direction": "discharge",
                 "rmse_v_per_cell_mv": round(float(np.sqrt(np.mean(err_v ** 2))), 2) if use.any() else None,
                 "rmse_i_cv_pct": None, "peak": None, "temp_rise": None, "window_s": span,
                 "capacity": {"real_mah": round(float(curve.delivered_mah[-1]), 1), "model_mah": round(model_mah, 1)}}
    if hold.any():
        err_i = (run.i[hold] - curve.i[hold]) / discharge_current(curve) * 100.0
        out["rmse_i_cv_pct"] = round(float(np.sqrt(np.mean(err_i ** 2))), 2)
    out["capacity"].update(delivered_check(float(curve.delivered_mah[-1]), model_mah))
    out["rmse_temp_c"] = rmse_temp(curve, run)
    if curve.temp is not None:
        out["temp_rise"] = {"real_c": temp_rise(curve.temp), "model_c": temp_rise(run.temp),
                            "real_window_s": span, "model_window_s": span}
    return out


class Residuals:
    """A discharge's residuals for a model's run and the charge it delivered, each part weighted so its sum of
    squares is its mean square in mV per cell; what does not depend on the run is computed once."""

    def __init__(self, curve: Curve, series: int, real_mah: float, hold: np.ndarray) -> None:
        self.curve, self.series, self.real_mah, self.hold = curve, series, real_mah, hold
        self.use = discharging(curve) & ~hold
        self.i_dis = discharge_current(curve)

    def __call__(self, run: Run, model_mah: float) -> np.ndarray:
        curve, hold, use, real_mah = self.curve, self.hold, self.use, self.real_mah
        parts = [(run.i[hold] - curve.i[hold]) / self.i_dis * _HOLD_WEIGHT / math.sqrt(max(int(hold.sum()), 1)),
                 (run.v[use] - curve.v[use]) / self.series * 1000.0 / math.sqrt(max(int(use.sum()), 1)),
                 np.array([(model_mah - real_mah) / max(real_mah, 1.0) * 100.0 * _CAPACITY_WEIGHT])]
        if curve.temp is not None:
            parts.append((run.temp - curve.temp) * _TEMP_WEIGHT / math.sqrt(len(curve.t)))
        return np.concatenate(parts)


def _params(chem: Chemistry, curve: Curve, only_capacity: bool, mah: float) -> list[Param]:
    capacity = Param("capacity_mah", max(mah * 0.5, 1.0), mah * 20.0, True)
    if only_capacity:
        return [capacity, _START_SOC]
    heat = _HEAT if chem.name in NI and curve.temp is not None else ()
    diffusion = (DIFFUSION,) if chem.name in LI else ()
    return [capacity, _START_SOC, *COMMON_PARAMS[2:], _KNEE, *_SLOW, *diffusion, *heat]


def fit_discharge(curve: Curve, chemistry: str, series: int, *, only_capacity: bool = False,
                  base: Chemistry | None = None, max_nfev: int | None = None) -> FitResult:
    """Fit the model of `chemistry` (or `base`) to the discharge; ``only_capacity`` keeps the chemistry's
    defaults and fits the capacity and start state only (how a user without a log would fare)."""
    require_discharge(curve)
    chem = base or load_chemistry(chemistry)
    chemistry = chem.name
    check_series(curve, chem, series)
    work = fit_samples(curve)
    real_mah, end_v = float(curve.delivered_mah[-1]), end_voltage(curve)
    params = _params(chem, curve, only_capacity, real_mah)
    start = {"capacity_mah": real_mah, "start_soc": 1.0, "r_scale": 1.0, "ocv_offset_v": 0.0, "ocv_scale": 1.0}
    for p in params[5:]:
        start[p.name] = min(max(getattr(chem, p.name), p.lo * 1.001 if p.lo > 0 else p.lo), p.hi * 0.999)

    hold = hold_mask(work)
    delivery, parts = Delivery(work, end_v, hold), Residuals(work, series, real_mah, hold)

    def residuals(values: dict) -> np.ndarray:
        run, model_mah = delivery(_battery(chem, values, series), values["start_soc"])
        return np.concatenate((parts(run, model_mah), ocv_prior(values)))

    def solve(free: list[Param], begin: dict) -> tuple[dict, float, int]:
        return solve_params(free, begin, residuals, max_nfev, lambda exc: start_error(curve, chemistry, exc))

    # Where it started: full (a capacity test follows a charge), or where the OCV meets the first voltage
    # plus what the current's drop hides; each begun with the capacity that empties it at the log's end.
    socs = {1.0, 0.85}
    if chemistry not in NI:
        socs.add(round(min(1.0, max(0.3, soc_at_ocv(chem, float(curve.v[0]) / series) + 0.1)), 3))
    begins = [{**start, "start_soc": soc, "capacity_mah": real_mah / soc} for soc in sorted(socs)]
    tries = [solve(params[:2], begin) for begin in begins]
    values = min(tries, key=lambda c: c[1])[0]
    nfev = sum(c[2] for c in tries)
    if not only_capacity:
        # A pack's resistance may lie far from the default's either way (the NiCd default's, tuned on the
        # Akkumatik charge, is twice what that pack's discharge fits): from the default's alone the fit
        # can stop in a shallower minimum.
        tries = [solve(params, {**values, "r_scale": r}) for r in _R_STARTS]
        values = min(tries, key=lambda c: c[1])[0]
        nfev += sum(c[2] for c in tries)
    values = {p.name: values[p.name] for p in params}
    battery = _battery(chem, values, series)
    run, model_mah = model_delivered(battery, curve, values["start_soc"], end_v, hold_mask(curve))
    report = discharge_figures(curve, run, series, model_mah)
    report["weak_cell"] = None
    step_mah = None if only_capacity else cell_step(work, series)
    if step_mah is not None:
        # Begun where the weak cell, as full as the others, empties at the step.
        share = step_mah / (values["capacity_mah"] * values["start_soc"])
        weak, _cost, n = solve([*params, _WEAK], {**values, "weak_share": min(0.95, max(0.3, share))})
        nfev += n
        weak_battery = _battery(chem, weak, series)
        weak_run, weak_mah = model_delivered(weak_battery, curve, weak["start_soc"], end_v, hold_mask(curve))
        weak_report = discharge_figures(curve, weak_run, series, weak_mah)
        before, after = report["rmse_v_per_cell_mv"], weak_report["rmse_v_per_cell_mv"]
        if after <= _WEAK_GAIN * before and before - after >= _WEAK_GAIN_MV:
            values = {p.name: weak[p.name] for p in params}
            battery, run, report = weak_battery, weak_run, weak_report
            report["weak_cell"] = {"capacity_share": round(weak["weak_share"], 4),
                                   "capacity_mah": round(weak["capacity_mah"] * weak["weak_share"], 1),
                                   "others_mah": round(weak["capacity_mah"], 1), "at_mah": round(step_mah, 1),
                                   "rmse_equal_cells_mv": before}
    report["at_bound"] = at_bounds(params, values)
    report["cells"], report["cells_guessed"] = series, guess_series(curve, chemistry)
    use = np.flatnonzero(discharging(curve))
    report["coverage"] = coverage(chem, (float(curve.v[use[0]]) / series, float(curve.v[use[-1]]) / series), real_mah,
                                  values["capacity_mah"], values["start_soc"], chemistry in LI)
    report["heat"] = heat_check(report["temp_rise"], any(p.name == "ha_w_per_k" for p in params))
    report["quality"] = quality(report, curve, hold_mask(curve))
    return FitResult(battery, chemistry, {k: round(v, 6) for k, v in values.items()}, report, run, curve,
                     hold_mask(curve), nfev)

