"""What a fitted model predicts for the log it was fitted to (issue 35 §4, issue 33 §2): the program the log ran,
its current and its end, written as a macro and run on the simulator with the fitted battery from the fit's own
start state. A model that ends that program far from where the log ended (a false -dV, a dT/dt end the log's
charger never had, a pack full too soon) is not to be trusted for this pack, whatever its RMSE."""
from __future__ import annotations

import math
from dataclasses import replace

import numpy as np

from ..domain.end_reasons import read
from ..domain.units import AS_PER_MAH
from .compare import log_charger, real_end
from .curve import Curve
from .fit import FitResult, cc_current, cv_mask, measured, smooth
from .fit_discharge import discharge_current, end_voltage, hold_mask
from .interpreter import StartError, StartParams
from .simulate import BatterySetup, simulate
from ..i18n import _

TRUST_PCT = 15.0            # a predicted charge this far off the log's: the model is not to be trusted (issue 33)
_COOL_K_PER_W = 0.01        # the heat sink of a charger as big as the log's needed
_BACKUP = 2.0               # the program's own timer: this many times the log's time (a model that never ends)
# A -dV ends a charge within a minute or two of the fall; a charge that ran on for this share of its charge after
# its voltage had fallen as far as it ends was not ended by its -dV (every other nickel log: under 0.2 %).
_DV_LATE_SHARE = 0.05


def drop_first_reached(curve: Curve, chemistry: str, series: int) -> dict | None:
    """Where a nickel charge's own voltage first fell as far below its peak as it ends (1-minute average, the samples
    ``real_end`` reads): ``{"mah", "before_end_s", "drop_mv_per_cell"}``; None for a charge without a -dV end. A
    charger that ended on its -dV stopped there; one that ran on long after (the AkkuMaster C4's 0.2C charge: 52 min)
    ended on something the voltage does not show, which no -dV program states (docs/validation.md)."""
    if real_end(curve, chemistry, series)["kind"] != "dv":
        return None
    use = measured(curve, cv_mask(curve, chemistry))
    t, mah, s = curve.t[use], curve.mah[use], smooth(curve.t[use], curve.v[use])
    top = int(np.argmax(s))
    fall = s[top] - s[top:]
    first = top + int(np.flatnonzero(fall >= fall[-1] - 1e-9)[0])
    return {"mah": round(float(mah[first]), 1), "before_end_s": round(float(t[-1] - t[first]), 1),
            "drop_mv_per_cell": round(float(fall[-1]) / series * 1000.0, 2)}


def dv_ended_it(curve: Curve, chemistry: str, series: int) -> bool:
    """Whether a nickel charge with a -dV stopped where its voltage first fell that far (not long after it)."""
    reached = drop_first_reached(curve, chemistry, series)
    return reached is not None and reached["mah"] >= (1.0 - _DV_LATE_SHARE) * float(curve.mah[-1])


def own_program(result: FitResult) -> tuple[str, StartParams] | None:
    """The macro of the program the fitted log ran (its current, its end) and its start values; None where the
    log's end is not one a macro states (a charge that just stops: the log ends, not the program; a nickel charge
    whose charger ran on long after its -dV, to a timer or counter the log does not state)."""
    curve, chemistry, series = result.curve, result.chemistry, result.battery.series
    end = real_end(curve, chemistry, series)
    backup = f"      IF(tf>{math.ceil(_BACKUP * float(curve.t[-1]) / 60.0)}m) STOP_FAZE\n"
    sensor = curve.temp is not None
    if curve.direction == "discharge":
        # To the log's end voltage at its current; where the log's charger then held that voltage and stepped its
        # current down (the Akkumatik NiCd's last 10 %), the program holds it too, until the log's last current.
        hold = hold_mask(curve)
        if hold.any():
            at = np.flatnonzero(hold)
            hold_v, stop = float(np.median(curve.v[at])), float(-curve.i[at[-1]])
            phases = (f"    FAZE\n      CONSTANT_I=INPUT\n      IF(V<{hold_v:.2f}V) STOP_FAZE\n{backup}    END_FAZE\n"
                      f"    FAZE\n      CONSTANT_V={hold_v:.2f}V\n      IF(I<{stop:.3f}A) STOP_FAZE\n{backup}    END_FAZE\n")
        else:
            phases = (f"    FAZE\n      CONSTANT_I=INPUT\n      IF(V<{end_voltage(curve):.2f}V) STOP_FAZE\n{backup}"
                      "    END_FAZE\n")
        body = "  DISCHARGE_SECTION\n" + phases + "  END_SECTION\n"
        params = StartParams("discharge", 1, round(result.battery.capacity_mah), round(discharge_current(curve), 3),
                             None, series, sensor)
    else:
        cv = cv_mask(curve, chemistry)
        current = round(cc_current(curve, cv), 3)
        if end["kind"] == "dv" and not dv_ended_it(curve, chemistry, series):
            return None
        if end["kind"] == "dv":
            # The pack's drop below its peak to the nearest hundredth of a volt (what the byte code keeps), at least one.
            drop = max(0.01, round(float(end["values"]["drop"]) * series / 1000.0, 2))
            phases = f"    FAZE\n      CONSTANT_I=INPUT\n      IF(DELTA_PEAK>{drop:.2f}V) STOP_FAZE\n{backup}    END_FAZE\n"
        elif end["kind"] == "cv":
            hold, stop = float(end["values"]["v"]), float(end["values"]["a"])
            phases = (f"    FAZE\n      CONSTANT_I=INPUT\n      IF(V>{hold:.2f}V) STOP_FAZE\n{backup}    END_FAZE\n"
                      f"    FAZE\n      CONSTANT_V={hold:.2f}V\n      IF(I<{stop:.3f}A) STOP_FAZE\n{backup}    END_FAZE\n")
        else:
            return None
        body = "  CHARGE_SECTION\n" + phases + "  END_SECTION\n"
        params = StartParams("charge", 1, round(result.battery.capacity_mah), current, None, series, sensor)
    return f"MACRO own\n  AKK_TYPE={chemistry}\n{body}END_MACRO\n", params


def predict_own(result: FitResult, sensor: bool | None = None) -> dict | None:
    """The fitted model on its log's own program: ``{"real_mah", "model_mah", "charge_error_pct", "real_s",
    "model_s", "time_error_pct", "trusted", "why", "ended_by"}`` (``why``: the model's end, English as the phase-end
    reasons are; ``ended_by``: "own_end", "backup" (the program's timer at twice the log's time: the model never got
    to the log's end) or "charger" (a limit of its own)); None where the log's end is no program's (``own_program``).
    ``sensor``: run with a temperature sensor or without (default: as the log had one)."""
    from ..lang.compiler import compile_source     # the compiler only where a prediction is asked for

    made = own_program(result)
    if made is None:
        return None
    text, params = made
    if sensor is not None:
        params = replace(params, sensor=sensor)
    compiled = compile_source(text)
    if not compiled.ok:
        return None
    curve = result.curve
    soc = float(result.params.get("start_soc", 0.0 if curve.direction == "charge" else 1.0))
    # The log's charger: its current and power, and a heat sink that never throttles it (the B6's, at the 135 W of
    # the 10 h lead-acid discharge, paused it for hours: a prediction of the charger's heat, not the pack's).
    charger = replace(log_charger(curve, "imax_b6"), heatsink_r_k_per_w=_COOL_K_PER_W)
    setup = BatterySetup(result.chemistry, soc, curve.ambient_c, charger, chem=result.battery.chem)
    try:
        sim = simulate(compiled.record, params, setup)
    except StartError:
        return None
    it = sim.interpreter
    discharge = curve.direction == "discharge"
    real_mah = float(curve.delivered_mah[-1] if discharge else curve.mah[-1])
    model_mah = (it.q_out if discharge else it.q_in) / AS_PER_MAH
    real_s, model_s = float(curve.t[-1] - curve.t[0]), float(it.time_s)
    charge_off = (model_mah / real_mah - 1.0) * 100.0 if real_mah else 0.0
    time_off = (model_s / real_s - 1.0) * 100.0 if real_s else 0.0
    last = it.phases[-1] if it.phases else None
    why = (last.reason if last else "") or it.end_reason
    # What ended it: the log's own end, the program's backup timer (the model never got there), or a limit of
    # the charger's own (its dT/dt, capacity or temperature end: "default: ...").
    ended_by = "backup" if why.startswith("IF(tf>") else "charger" if read(why).code.charger_default else "own_end"
    return {"real_mah": round(real_mah, 1), "model_mah": round(model_mah, 1), "charge_error_pct": round(charge_off, 1),
            "real_s": round(real_s, 1), "model_s": round(model_s, 1), "time_error_pct": round(time_off, 1),
            "trusted": bool(abs(charge_off) <= TRUST_PCT), "why": why, "ended_by": ended_by}


def trust_words(prediction: dict | None) -> str | None:
    """Why the model is not to be trusted for this pack, in the user's language (None: it may be)."""
    if prediction is None or prediction["trusted"]:
        return None
    how = {"own_end": _("it ends there after {minutes} min: {why}"),
           "backup": _("it never reaches the log's own end: the program's timer stops it after {minutes} min"),
           "charger": _("the charger's own limit ends it after {minutes} min: {why}")}[prediction.get("ended_by", "own_end")]
    return _("⚠ do not trust this model for this pack: on the program its own log ran it predicts {model} mAh where "
             "the log has {real} mAh ({off}; more than ±{limit} off); {how}").format(
        model=f"{prediction['model_mah']:.0f}", real=f"{prediction['real_mah']:.0f}",
        off=f"{prediction['charge_error_pct']:+.0f} %", limit=f"{TRUST_PCT:g} %",
        how=how.format(minutes=f"{prediction['model_s'] / 60:.0f}", why=prediction["why"]))


def prediction_line(prediction: dict) -> str:
    """The prediction next to the log's figure, in the user's language."""
    return _("On its own log's program: {model} mAh predicted, {real} mAh logged ({off}); end after {m_min} min "
             "predicted, {r_min} min logged").format(
        model=f"{prediction['model_mah']:.0f}", real=f"{prediction['real_mah']:.0f}",
        off=f"{prediction['charge_error_pct']:+.1f} %", m_min=f"{prediction['model_s'] / 60:.0f}",
        r_min=f"{prediction['real_s'] / 60:.0f}")
