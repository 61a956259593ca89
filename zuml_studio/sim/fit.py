"""Fit a chemistry's battery model (``battery.Pack``) to a measured charge.

The model is driven by the log's own current; where the charger held the voltage (the CV part
of a Li or Pb charge) it is driven by the log's voltage and its current is compared instead.
``scipy.optimize.least_squares`` moves the parameters; scipy is imported only when a fit runs,
so starting the application does not pay for it. What is fitted per chemistry family, the stages
and the weights: docs/fit.md; how well it does on real recordings: docs/validation.md."""
from __future__ import annotations

import math
import os
from dataclasses import dataclass, fields, replace

import numpy as np

from . import engine
from .battery import Pack
from .cell_pack import CellPack, CellSpec, build_pack
from ..domain.chemistry import Chemistry, load_chemistry
from .curve import Curve, CurveError, require_charge
from .fit_checks import HEAT_PARAMS, coverage, heat_check
from ..i18n import _

NI = ("NiCd", "NiMh")
LI = ("LiPo", "LiIon", "LiFe")
# A voltage hold starts where the log's voltage comes within this fraction of its maximum and
# the current has fallen below this fraction of the constant current before it.
_CV_V_FRACTION = 0.995
_CV_I_FRACTION = 0.92
_CV_HOLD_FRACTION = 0.99     # ... and while it stays this close to the voltage held (a lower CC step after the
                             # hold is CC again)
_SMOOTH_S = 60.0            # the peak and -dV are read from a 1-minute moving average (as chargers filter)
_CC_MIN_S = 60.0            # a CC phase shorter than this before the hold is none (the CV figure is then "–")
_PAUSE_FRACTION = 0.5      # CC samples below this fraction of the CC current are measurement pauses
_FIT_SAMPLES = 400           # ... or coarser, so that a long charge has at most about this many samples (a fit
                             # of a 2 h NiMH charge in about a second: benchmarks/bench_fit.py)
_FIT_STEP_S = 10.0          # curves are decimated to this before a fit: seconds per fit, not minutes
_TEMP_WEIGHT = 1.0           # 1 °C of temperature error weighs as 1 mV per cell
_RISE_WEIGHT = 3.0           # 1 °C of error in the temperature rise weighs as 3 mV per cell
_TAIL_WEIGHT = 3.0           # the fall after the peak weighs 3x the rest of the voltage
_TAPS_AGREE = 0.25           # taps further off the pack voltage are not one per cell (a NiMH log's one tap)
_NFEV_PER_PARAM = 15         # evaluations per fitted parameter and start: keeps a fit to seconds
# A charge's median voltage per cell lies within 5 % of the chemistry's charging_v in every real log
# with its right cell count (docs/validation.md); one cell too many or too few on up to 8 cells is 12 %+.
SERIES_TOLERANCE = 0.12
# A discharge's median voltage per cell lies within 11 % of the chemistry's nominal_v on every recorded
# discharge with its right cell count (docs/validation.md; the NiCd pack at 1 A reads 1.07 V, -11 %); one
# cell off on up to 5 cells is 17 % or more (a 6S LiFe or Pb pack read as 7S, 13-14 %, passes).
DISCHARGE_SERIES_TOLERANCE = 0.15
_BOUND_LOG = 0.01            # a log-fitted value within 1 % of a bound is at it
_BOUND_LINEAR = 0.005        # ... a linear one within 0.5 % of its range


@dataclass(frozen=True)
class Param:
    """One fitted quantity: ``log`` ones are fitted as their logarithm (they only make sense > 0)."""
    name: str
    lo: float
    hi: float
    log: bool = False


# Fitted for every chemistry: the battery (capacity, where it started), its resistance and OCV.
COMMON_PARAMS = (Param("capacity_mah", 0.0, 0.0, True), Param("start_soc", 0.0, 0.95),
           Param("r_scale", 0.1, 10.0, True), Param("ocv_offset_v", -0.15, 0.15), Param("ocv_scale", 0.3, 3.0, True))
# Lithium's solid-state diffusion (Chemistry.diffusion_tau_s): from none (1 s) to a particle slower than any cell's
DIFFUSION = Param("diffusion_tau_s", 1.0, 20000.0, True)
# Lead's absorption tail: the charge acceptance (w0) and the gassing voltage its refused share raises (dv_o2_v).
# With polarisation capped at pol_max_v alone the UB121000's absorption current fell to 3 % of CC in twice the
# log's time (2.6 A where the log had 1.0 A at its end); its fitted gassing voltage is 0.44 V, past Ni's 0.3 bound.
GASSING = (Param("w0", 0.005, 0.3, True), Param("dv_o2_v", 0.0, 0.6))
_NI_R_START = 8.0     # a Ni charge that misses ... is fitted again from this many times the default's resistance
_NI_DONE_MV = 20.0    # ... the limit (its cost as an RMSE in mV per cell)
_FAMILY = {
    "ni": (Param("w0", 0.005, 0.3, True), Param("dv_o2_v", 0.0, 0.3), Param("k_t_v_per_k", 0.0, 0.03),
           Param("ha_w_per_k", 0.005, 0.5, True), Param("cth_j_per_k", 5.0, 300.0, True),
           Param("dip_v_per_charge", 0.0, 5.0), Param("dip_tau_s", 60.0, 36000.0, True)),
    "li": (Param("r2_ohm", 1e-4, 2.0, True), Param("tau2_s", 60.0, 36000.0, True), DIFFUSION),
    "pb": (Param("k_charge_ohm", 1e-5, 0.1, True), Param("pol_tau_s", 30.0, 20000.0, True),
           Param("pol_max_v", 0.01, 0.6, True), *GASSING),
}


def family(chemistry: str) -> str:
    return "ni" if chemistry in NI else "li" if chemistry in LI else "pb"


@dataclass(frozen=True)
class Battery:
    """A chemistry with (possibly fitted) parameters, a capacity and a cell count: what ``Pack`` is built from;
    ``cells`` where they are unequal (a weak cell a discharge fit found)."""
    chem: Chemistry
    capacity_mah: float
    series: int
    cells: tuple[CellSpec, ...] | None = None

    def pack(self, soc: float, ambient_c: float) -> Pack | CellPack:
        return build_pack(self.chem, self.capacity_mah, self.series, soc, ambient_c, self.cells)


@dataclass
class Run:
    """The model driven along a curve: its voltage, current and temperature at the curve's samples."""
    v: np.ndarray
    i: np.ndarray
    temp: np.ndarray


@dataclass
class FitResult:
    battery: Battery
    chemistry: str
    params: dict
    figures: dict
    run: Run
    curve: Curve
    cv: np.ndarray
    nfev: int = 0


def cv_mask(curve: Curve, chemistry: str) -> np.ndarray:
    """Samples where the charger held the voltage (never for NiCd/NiMH, which charge at constant current)."""
    n = len(curve.t)
    if chemistry in NI:
        return np.zeros(n, bool)
    vmax = float(curve.v.max())
    reached = np.flatnonzero(curve.v >= _CV_V_FRACTION * vmax)
    mask = np.zeros(n, bool)
    if not len(reached):
        return mask
    first = reached[0]
    i_cc = float(np.median(curve.i[:first + 1]))
    falling = curve.i[first:] < _CV_I_FRACTION * i_cc
    # The voltage held is the hold's own median, not the log's maximum: a charger that overshoots as it turns to
    # CV (the 308DUO's 2S LiFe, 7.29 V, then held at 7.20 V) would else end its hold 1.2 % under that peak.
    held_v = float(np.median(curve.v[first:][falling])) if falling.any() else vmax
    mask[first:] = falling & (curve.v[first:] >= _CV_HOLD_FRACTION * held_v)
    return mask


def has_cc_phase(curve: Curve, cv: np.ndarray) -> bool:
    """Whether the charge ran at constant current for at least _CC_MIN_S before its voltage hold: a full pack topped
    up (the X6 LiFe, held at 3.60 V/cell from its 12th second) has no CC current to measure the CV current against."""
    if not cv.any():
        return True
    first = int(np.flatnonzero(cv)[0])
    on = np.flatnonzero(curve.i[:first] > 0.0)
    return bool(len(on)) and float(curve.t[first] - curve.t[on[0]]) >= _CC_MIN_S


def cc_current(curve: Curve, cv: np.ndarray) -> float:
    """The constant current before the voltage hold (the whole charge's median where there is none)."""
    cc = curve.i[~cv] if (~cv).any() else curve.i
    return float(np.median(cc[cc > 0])) if (cc > 0).any() else 1.0


def measured(curve: Curve, cv: np.ndarray) -> np.ndarray:
    """Samples whose voltage is compared: charging at constant current, not the CV part and not a
    charger's measurement pause (current off for a moment: the eStation BC6 pauses every minute, and
    a 10 s sample held at 0 A would make the model relax far more than the cell did)."""
    return ~cv & charging(curve.i, cc_current(curve, cv))


def charging(current: np.ndarray, i_cc: float) -> np.ndarray:
    """Samples at the charge current, not in a measurement pause."""
    return current >= _PAUSE_FRACTION * i_cc


def simulate_curve(battery: Battery, curve: Curve, cv: np.ndarray, start_soc: float,
                   pack: Pack | CellPack | None = None) -> Run:
    """Drive the model with the log's current (its voltage where ``cv``: a charge's CV, a discharge's hold at its
    end voltage); sample k is held over (t[k-1], t[k]].
    ``pack``: the model to drive (left in its end state for the caller), else a new one from ``battery``."""
    pack = pack or battery.pack(start_soc, curve.ambient_c)
    n = len(curve.t)
    if engine.drivable(pack):
        # The same steps in C (bit for bit, tests/sim/test_drive.py): a fit runs this hundreds of times.
        return Run(*engine.drive(pack, track(curve, cv)))
    v = np.empty(n)
    i = np.empty(n)
    temp = np.empty(n)
    v[0], i[0], temp[0] = pack.step(float(curve.i[0]), 1e-3), curve.i[0], pack.temp_c
    t, vl, il = curve.t.tolist(), curve.v.tolist(), curve.i.tolist()
    cvl = cv.tolist()
    step, for_v = pack.step, pack.current_for_voltage
    for k in range(1, n):
        dt = t[k] - t[k - 1]
        # Held at a voltage, the model's current keeps the log's direction (a discharge's hold never charges).
        cur = (max(0.0, for_v(vl[k], dt)) if il[k] >= 0.0 else min(0.0, for_v(vl[k], dt))) if cvl[k] else il[k]
        v[k] = step(cur, dt)
        i[k] = cur
        temp[k] = pack.temp_c
    return Run(v, i, temp)


_tracks: list = [None]      # the last curve driven, its hold mask and its track: a fit drives one curve many times


def track(curve: Curve, cv: np.ndarray) -> engine.Track:
    """The curve as `simulate_curve` steps it in C: its first sample over 1 ms (as the model's first voltage),
    where ``cv`` held by the log's voltage (never the first)."""
    key = np.asarray(cv, bool).tobytes()
    last = _tracks[0]
    if last is not None and last[0] is curve and last[1] == key:
        return last[2]
    n = len(curve.t)
    dt = np.empty(n)
    dt[0] = 1e-3
    dt[1:] = np.diff(curve.t)
    held = np.asarray(cv, bool).copy()
    held[0] = False
    made = engine.Track(dt, curve.i, curve.v, held)
    _tracks[0] = (curve, key, made)
    return made


def smooth(t: np.ndarray, y: np.ndarray, window_s: float = _SMOOTH_S) -> np.ndarray:
    return smoothed(y, smooth_window(t, window_s))


def smooth_window(t: np.ndarray, window_s: float = _SMOOTH_S) -> int:
    """The moving average's width in samples of ``t`` (its median step)."""
    dt = float(np.median(np.diff(t))) if len(t) > 1 else 1.0
    return max(1, int(round(window_s / max(dt, 1e-3))))


def smoothed(y: np.ndarray, w: int) -> np.ndarray:
    """``y``'s moving average over ``w`` samples, its ends held."""
    if w <= 1 or len(y) < w:
        return y.copy()
    kernel = np.ones(w) / w
    padded = np.concatenate((np.full(w // 2, y[0]), y, np.full(w - 1 - w // 2, y[-1])))
    return np.convolve(padded, kernel, mode="valid")


def peak(t: np.ndarray, v: np.ndarray, mah: np.ndarray, series: int) -> tuple[float, float]:
    """(mAh at the smoothed voltage's maximum, its fall from there to the end in mV per cell)."""
    s = smooth(t, v)
    k = int(np.argmax(s))
    return float(mah[k]), float((s[k] - s[-1]) / series * 1000.0)


def figures(curve: Curve, run: Run, cv: np.ndarray, series: int, chemistry: str) -> dict:
    """The figures ``zuml fit --json`` prints (None where the log has no such part); ``window_s``
    is the span of the charge they are taken over (s from its start)."""
    cc = measured(curve, cv)
    err_v = (run.v[cc] - curve.v[cc]) / series * 1000.0
    out: dict = {"direction": "charge",
                 "rmse_v_per_cell_mv": round(float(np.sqrt(np.mean(err_v ** 2))), 2) if cc.any() else None,
                 "rmse_i_cv_pct": None, "peak": None, "temp_rise": None}
    if cv.any() and not has_cc_phase(curve, cv):
        out["no_cc_phase"] = True         # unknown, not a share of a current the charger never held
    elif cv.any():
        err_i = (run.i[cv] - curve.i[cv]) / cc_current(curve, cv) * 100.0
        out["rmse_i_cv_pct"] = round(float(np.sqrt(np.mean(err_i ** 2))), 2)
    if chemistry in NI:
        t, mah = curve.t[cc], curve.mah[cc]
        real_mah, real_dv = peak(t, curve.v[cc], mah, series)
        model_mah, model_dv = peak(t, run.v[cc], mah, series)
        out["peak"] = {"real_mah": round(real_mah, 1), "model_mah": round(model_mah, 1),
                       "real_dv_mv_per_cell": round(real_dv, 2), "model_dv_mv_per_cell": round(model_dv, 2)}
    span = [round(float(curve.t[0]), 1), round(float(curve.t[-1]), 1)]
    out["window_s"] = span
    if curve.temp is not None:
        out["temp_rise"] = {"real_c": temp_rise(curve.temp), "model_c": temp_rise(run.temp),
                            "real_window_s": span, "model_window_s": span}
    out["rmse_temp_c"] = rmse_temp(curve, run)
    return out


def quality(report: dict, curve: Curve, held: np.ndarray) -> dict:
    """The fit's quality per quantity it was fitted to, each RMSE with its unit and the window it is taken over
    (s from the curve's start): what every fitted figure is to be read with (issue 35 §4). ``held``: the samples
    where the current is compared (a charge's CV, a discharge's hold)."""
    span = report["window_s"]
    out = {"voltage": {"rmse": report["rmse_v_per_cell_mv"], "unit": "mV/cell", "window_s": span}}
    if report["rmse_i_cv_pct"] is not None or report.get("no_cc_phase"):
        at = np.flatnonzero(held)
        out["held_current"] = {"rmse": report["rmse_i_cv_pct"], "unit": "% of the constant current",
                               "window_s": [round(float(curve.t[at[0]]), 1), round(float(curve.t[at[-1]]), 1)]}
        if report.get("no_cc_phase"):
            out["held_current"]["note"] = "no CC phase"
    if report["rmse_temp_c"] is not None:
        out["temperature"] = {"rmse": report["rmse_temp_c"], "unit": "°C", "window_s": span}
    return out


def temp_rise(temp: np.ndarray) -> float:
    """The highest temperature over the first one (°C)."""
    return round(float(np.max(temp) - temp[0]), 2)


def rmse_temp(curve: Curve, run: Run) -> float | None:
    """The temperature's RMSE over the window (°C), None where the log has no probe: the fit's quality per
    quantity next to its figures (issue 35 §4)."""
    if curve.temp is None:
        return None
    return round(float(np.sqrt(np.mean((run.temp - curve.temp) ** 2))), 2)


def check_series(curve: Curve, chem: Chemistry, series: int) -> None:
    """Refuse at once a cell count the charge cannot have (its median voltage per cell more than
    SERIES_TOLERANCE off the chemistry's voltage under charge): a fit with it runs for minutes and
    ends at its bounds."""
    per_cell = float(np.median(curve.v)) / series
    typical = typical_v(chem, curve)
    off = per_cell / typical - 1.0
    if abs(off) > (SERIES_TOLERANCE if curve.direction == "charge" else DISCHARGE_SERIES_TOLERANCE):
        guess = guess_series(curve, chem.name)
        text = (_("{series} cells do not fit this charge: its median voltage {v} V is {per_cell} V per "
                  "cell, {off} from {chemistry}'s {charging} V under charge; it looks like {guess} cells "
                  "(--cells {guess})") if curve.direction == "charge" else
                _("{series} cells do not fit this discharge: its median voltage {v} V is {per_cell} V per "
                  "cell, {off} from {chemistry}'s nominal {charging} V; it looks like {guess} cells "
                  "(--cells {guess})"))
        raise CurveError(text.format(series=series, v=f"{float(np.median(curve.v)):.2f}", per_cell=f"{per_cell:.3f}",
                                     off=f"{off * 100:+.0f} %", chemistry=chem.name, charging=f"{typical:g}",
                                     guess=guess))


def typical_v(chem: Chemistry, curve: Curve) -> float:
    """A cell's typical voltage along the curve: under charge, or its nominal voltage on a discharge."""
    return chem.charging_v if curve.direction == "charge" else chem.nominal_v


# What a fit ending at a bound says something is wrong with: the pack's size, resistance and OCV. The
# start state, and a family's own terms at an end of their range (no slow pair, no dip), are answers.
_TELLING_BOUNDS = ("capacity_mah", "r_scale", "ocv_offset_v", "ocv_scale")


def at_bounds(params: list[Param], values: dict) -> list[dict]:
    """The pack's size, resistance or OCV values that ended at a bound of their range (_TELLING_BOUNDS):
    {"name", "value", "bound": "lower" | "upper"}."""
    out = []
    for p in (p for p in params if p.name in _TELLING_BOUNDS):
        v = values[p.name]
        for bound, edge in (("lower", p.lo), ("upper", p.hi)):
            near = (abs(math.log(v) - math.log(edge)) < _BOUND_LOG if p.log
                    else abs(v - edge) < _BOUND_LINEAR * (p.hi - p.lo))
            if near:
                out.append({"name": p.name, "value": round(v, 6), "bound": bound})
    return out


_CHEM_FIELDS = frozenset(f.name for f in fields(Chemistry))    # once: dataclasses.fields costs per call


def fitted_chemistry(chem: Chemistry, values: dict) -> Chemistry:
    """The chemistry with fitted values: R scaled, OCV shifted and stretched about its mean, family keys replaced."""
    mean = sum(chem.ocv_v) / len(chem.ocv_v)
    scale, offset, r = values.get("ocv_scale", 1.0), values.get("ocv_offset_v", 0.0), values.get("r_scale", 1.0)
    ocv = tuple(mean + offset + scale * (x - mean) for x in chem.ocv_v)
    own = {k: v for k, v in values.items() if k in _CHEM_FIELDS}
    own.setdefault("r2_ohm", chem.r2_ohm * r)    # a fitted slow pair is its own value, else scaled with R
    return replace(chem, ocv_v=ocv, r0_ohm=chem.r0_ohm * r, r1_ohm=chem.r1_ohm * r, **own)


class Residuals:
    """A charge's residuals for a model's run along ``curve``, each part weighted so its sum of squares is its
    mean square in the units of the issue's limits; what does not depend on the run is computed once (a fit
    calls this hundreds of times). ``peak_real``: the log's peak figures (NiCd/NiMH), else None."""

    def __init__(self, curve: Curve, cv: np.ndarray, series: int, peak_real) -> None:
        self.curve, self.cv, self.series, self.peak_real = curve, cv, series, peak_real
        self.cc = measured(curve, cv)
        self.i_cc = cc_current(curve, cv)
        self.t_cc, self.mah_cc = curve.t[self.cc], curve.mah[self.cc]
        self.window = smooth_window(self.t_cc)

    def __call__(self, run: Run, end_terms: bool) -> np.ndarray:
        curve, cv, cc, series = self.curve, self.cv, self.cc, self.series
        peak_real = self.peak_real if end_terms else None
        parts = []
        if cc.any():
            parts.append((run.v[cc] - curve.v[cc]) / series * 1000.0 / math.sqrt(cc.sum()))
        if cv.any():
            # 10 % of the CC current weighs as much as 15 mV per cell (the two Li limits).
            parts.append((run.i[cv] - curve.i[cv]) / self.i_cc * 150.0 / math.sqrt(cv.sum()))
        if curve.temp is not None:
            parts.append((run.temp - curve.temp) * _TEMP_WEIGHT / math.sqrt(len(curve.t)))
        if curve.temp is not None and peak_real is not None:
            # NiCd/NiMH's rise itself (an issue figure): it comes in the last minutes, which weigh little
            # among all the samples.
            rise = (float(run.temp.max() - run.temp[0]) - float(curve.temp.max() - curve.temp[0])) * _RISE_WEIGHT
            parts.append(np.array([rise]))
        if peak_real is not None:
            model_s = smoothed(run.v[cc], self.window)
            k = int(np.argmax(model_s))
            model_mah, model_dv = float(self.mah_cc[k]), float((model_s[k] - model_s[-1]) / series * 1000.0)
            parts.append(np.array([(model_mah - peak_real[0]) / max(peak_real[0], 1.0) * 400.0,
                                   (model_dv - peak_real[1]) * 12.0]))
            # The fall after the real peak, point by point: unlike the peak figures it changes smoothly
            # with the parameters, so the optimiser finds a dip even from a model that has none.
            k, real_tail = peak_real[2], peak_real[3]
            tail = (model_s[k:] - model_s[k]) - real_tail
            parts.append(tail / series * 1000.0 * _TAIL_WEIGHT / math.sqrt(len(tail)))
        return np.concatenate(parts)


def ocv_prior(values: dict) -> np.ndarray:
    """Soft pulls towards the chemistry's OCV: capacity and an OCV stretch trade off against each
    other on a partial charge, and the table shape is the better-known of the two."""
    return np.array([math.log(values.get("ocv_scale", 1.0)) * 10.0, values.get("ocv_offset_v", 0.0) * 100.0])


def fit_samples(curve: Curve) -> Curve:
    """The curve a fit runs the model on (a charge's or a discharge's): decimated to at most about
    ``_FIT_SAMPLES`` samples, none closer than ``_FIT_STEP_S``."""
    return curve.decimated(max(_FIT_STEP_S, float(curve.t[-1]) / _FIT_SAMPLES))


def fit(curve: Curve, chemistry: str, series: int, *, only_capacity: bool = False,
        base: Chemistry | None = None, max_nfev: int | None = None) -> FitResult:
    """Fit the model of `chemistry` (or `base`) to the charge; ``only_capacity`` keeps the chemistry's
    defaults and fits the capacity and start state only (how a user without a log would fare)."""
    require_charge(curve)
    chem = base or load_chemistry(chemistry)
    chemistry = chem.name
    check_series(curve, chem, series)
    work = fit_samples(curve)
    cv = cv_mask(work, chemistry)
    mah = float(work.mah[-1])
    params = list(COMMON_PARAMS[:2] if only_capacity else COMMON_PARAMS + _FAMILY[family(chemistry)])
    if curve.temp is None:
        # Without a probe nothing fixes the heat terms: fitted to the voltage alone they took any value (the
        # eStation NiMH pack's heat loss at its bound, 20 °C of warming at 1 A, a charge its macro then ended
        # by dT/dt after 35 min). The chemistry's own are kept.
        params = [p for p in params if p.name not in HEAT_PARAMS]
    params[0] = Param("capacity_mah", max(mah * 0.5, 1.0), mah * 20.0, True)
    start = {"capacity_mah": min(max(mah * 1.05, params[0].lo * 1.01), params[0].hi * 0.99),
             "start_soc": 0.05, "r_scale": 1.0, "ocv_offset_v": 0.0, "ocv_scale": 1.0}
    for p in params[5:]:
        start[p.name] = min(max(getattr(chem, p.name), p.lo * 1.001 if p.lo > 0 else p.lo), p.hi * 0.999)
    if chemistry in LI:
        # A Li charge may start anywhere: begin where the default OCV meets the first voltage.
        start["start_soc"] = soc_at_ocv(chem, float(work.v[0]) / series)
    real_peak = None
    if chemistry in NI:
        use = measured(work, cv)
        real_s = smooth(work.t[use], work.v[use])
        k_peak = int(np.argmax(real_s))
        real_peak = (*peak(work.t[use], work.v[use], work.mah[use], series), k_peak,
                     real_s[k_peak:] - real_s[k_peak])

    parts = Residuals(work, cv, series, real_peak)

    def solve(free: list[Param], begin: dict, end_terms: bool):
        def residuals(values: dict) -> np.ndarray:
            battery = Battery(fitted_chemistry(chem, values), values["capacity_mah"], series)
            run = simulate_curve(battery, work, cv, values.get("start_soc", 0.0))
            return np.concatenate((parts(run, end_terms), ocv_prior(values)))
        return solve_params(free, begin, residuals, max_nfev, lambda exc: start_error(curve, chemistry, exc))

    # The capacity and start state first, with the chemistry's defaults: that is the default
    # model's answer, and every later stage starts from there.
    # A Li charge may start anywhere and the LFP OCV is flat: try several start states. A Ni
    # charge has two answers, a pack filled within the log (peak and dip) and a larger one that
    # never fills: try capacities on both sides.
    if chemistry in LI:
        # A charge from s to full puts in (1 - s) of the capacity: begin each start state there.
        begins = [{**start, "start_soc": soc, "capacity_mah": min(mah / (1.0 - soc), params[0].hi * 0.99)}
                  for soc in (start["start_soc"], 0.1, 0.5, 0.8, 0.95)]
    elif chemistry in NI:
        begins = [{**start, "capacity_mah": mah * f} for f in (0.85, 1.05, 1.3)]
    else:
        begins = [start]
    tries = [solve(params[:2], begin, True) for begin in begins]
    values = min(tries, key=lambda c: c[1])[0]
    nfev = sum(c[2] for c in tries)
    if chemistry in NI and not only_capacity:
        # Then the shape of the charge (OCV, resistance, the end-of-charge climb) from the voltage
        # alone, then everything with the peak, the dip and the temperature. Fitting all at once
        # stalls where the model has no peak (the peak terms are flat there).
        shape = [p for p in params if p.name not in HEAT_PARAMS]
        # The second start: a strong overcharge dip and (where the heat terms are fitted) almost no voltage per kelvin.
        other = {"dip_v_per_charge": 0.5, **({"k_t_v_per_k": 0.001} if len(shape) < len(params) else {})}
        best = None
        for r_scale in (1.0, _NI_R_START):
            first, _, n1 = solve(shape, {**values, "r_scale": r_scale}, False)
            candidates = [solve(params, first, True), solve(params, {**first, **other}, True)]
            nfev += n1 + sum(c[2] for c in candidates)
            best = min(candidates + ([best] if best else []), key=lambda c: c[1])
            # A fit within the limit is done; one that misses it begins again from _NI_R_START
            # times the resistance (the Akkumatik NiCd pack with its leads reads 10x a cell's own: from
            # the default's the fit stops in a shallower minimum).
            if 2.0 * best[1] <= _NI_DONE_MV ** 2:
                break
        values = best[0]
    elif not only_capacity:
        values, _, n1 = solve(params, values, True)
        nfev += n1
    values = {p.name: values[p.name] for p in params}
    battery = Battery(fitted_chemistry(chem, values), values["capacity_mah"], series)
    full_cv = cv_mask(curve, chemistry)
    run = simulate_curve(battery, curve, full_cv, values.get("start_soc", 0.0))
    report = figures(curve, run, full_cv, series, chemistry)
    report["at_bound"] = at_bounds(params, values)
    report["cells"], report["cells_guessed"] = series, guess_series(curve, chemistry)
    use = np.flatnonzero(charging(curve.i, cc_current(curve, full_cv)))
    report["coverage"] = coverage(chem, (float(curve.v[use[0]]) / series, float(curve.v[use[-1]]) / series),
                                  float(curve.mah[-1]), values["capacity_mah"], values["start_soc"], chemistry in LI)
    report["heat"] = heat_check(report["temp_rise"], "ha_w_per_k" in values)
    report["quality"] = quality(report, curve, full_cv)
    return FitResult(battery, chemistry, {k: round(v, 6) for k, v in values.items()}, report, run, curve, full_cv,
                     nfev)


def solve_params(free: list[Param], begin: dict, residuals, max_nfev: int | None,
                 cannot_start) -> tuple[dict, float, int]:
    """Move the ``free`` parameters from ``begin`` (the others held) to the least squares of
    ``residuals(values)``: (values, cost, evaluations). ``cannot_start(exc)`` is the error raised where
    the model gives no finite residual at the start."""
    least_squares = solver()

    def to_x(values: dict) -> np.ndarray:
        return np.array([math.log(values[p.name]) if p.log else values[p.name] for p in free])

    def values_of(x: np.ndarray) -> dict:
        return {**begin, **{p.name: (math.exp(v) if p.log else float(v)) for p, v in zip(free, x)}}

    lo = np.array([math.log(p.lo) if p.log else p.lo for p in free])
    hi = np.array([math.log(p.hi) if p.log else p.hi for p in free])
    x0 = np.clip(to_x(begin), lo + 1e-9, hi - 1e-9)
    try:
        sol = least_squares(lambda x: residuals(values_of(x)), x0, bounds=(lo, hi), diff_step=1e-3, x_scale="jac",
                            max_nfev=max_nfev or _NFEV_PER_PARAM * len(free))
    except ValueError as exc:      # scipy's words ("Residuals are not finite in the initial point")
        raise cannot_start(exc) from None
    return values_of(sol.x), sol.cost, int(sol.nfev)


def solver():
    """scipy's ``least_squares``, imported on a fit's first use (scipy costs start-up time), its OpenBLAS on one
    thread unless the user set it: a fit's SVDs are of a few columns, and threads fighting for a loaded machine's
    cores made one fit 18 s instead of 2 (benchmarks/bench_fit.py)."""
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
    from scipy.optimize import least_squares
    return least_squares


def start_error(curve: Curve, chemistry: str, exc: ValueError) -> CurveError:
    """The error of a fit whose model cannot run from its start values (a charge's or a discharge's)."""
    return CurveError(_("{name}: the fit cannot start: the {chemistry} model gives no finite voltage along this "
                        "curve from its start values ({error})").format(
            name=curve.name or "curve", chemistry=chemistry, error=exc))


def soc_at_ocv(chem: Chemistry, v_cell: float) -> float:
    """Where the OCV table reaches v_cell (clamped to 0 .. 0.95)."""
    return float(min(0.95, max(0.0, np.interp(v_cell, chem.ocv_v, chem.ocv_soc))))


def guess_series(curve: Curve, chemistry: str) -> int:
    """The cell count: the log's balance taps where they fit its pack voltage, else the charge's median
    voltage over the chemistry's typical voltage under charge. The median, not the highest voltage: a
    NiMH peak lies anywhere from 1.47 to 1.65 V per cell (docs/validation.md), so the top of a 4-cell
    pack with leads reads like 5 cells, while the median stays within 5 % of ``charging_v``."""
    per_cell = float(np.median(curve.v)) / typical_v(load_chemistry(chemistry), curve)
    if curve.cells and abs(per_cell / curve.cells - 1.0) < _TAPS_AGREE:
        return curve.cells
    return max(1, int(round(per_cell)))
