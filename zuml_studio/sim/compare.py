"""Run a macro from a real log's start conditions and set the two side by side: the same
figures as a fit, plus when and why each charge (or discharge) ended."""
from __future__ import annotations

from dataclasses import dataclass, replace

import numpy as np

from .charger_model import ChargerLimits, load_charger
from .curve import Curve, require_charge, require_discharge
from .fit import (NI, Run, cc_current, charging, cv_mask, figures, has_cc_phase, measured, peak, soc_at_ocv,
                  temp_rise)
from .fit_discharge import discharge_current, discharge_figures, end_voltage
from .fit_report import real_end_why
from ..domain.chemistry import load_chemistry
from .interpreter import StartParams
from .measured_r import MeasuredR, with_measured_r
from .simulate import BatterySetup, SimResult, model_chemistry, simulate
from ..i18n import _


@dataclass
class Comparison:
    sim: SimResult
    t: np.ndarray        # the log's time base over which both ran
    run: Run             # the simulation resampled onto it
    cv: np.ndarray
    report: dict


def start_setup(curve: Curve, chemistry: str, series: int) -> tuple[float, float]:
    """(start SOC, ambient °C) from the log: Ni charges start empty (a charger discharges them
    first, and their flat OCV says little) and Ni discharges full (a capacity test follows a charge);
    Li and Pb from where the OCV meets the first voltage (a discharge's first is read before the load)."""
    ambient = curve.ambient_c
    if chemistry in NI:
        return (0.0 if curve.direction == "charge" else 1.0), ambient
    return soc_at_ocv(load_chemistry(chemistry), float(curve.v[0]) / series), ambient


def real_end(curve: Curve, chemistry: str, series: int) -> dict:
    """When the logged charge ended and the state change that shows why: ``why`` in English (the
    report is a contract), ``kind`` and ``values`` to say it in the user's language."""
    t, v, i = float(curve.t[-1]), float(curve.v[-1]), float(curve.i[-1])
    if curve.direction == "discharge":
        end_v = end_voltage(curve)
        end = {"time_s": round(t, 1), "mah": round(float(curve.delivered_mah[-1]), 1), "v": round(end_v, 3),
               "a": round(i, 3)}
        kind, values = "cutoff", {"v": f"{end_v:.3f}", "per_cell": f"{end_v / series:.3f}"}
        return {**end, "why": real_end_why(kind, values, translate=False), "kind": kind, "values": values}
    end = {"time_s": round(t, 1), "mah": round(float(curve.mah[-1]), 1), "v": round(v, 3), "a": round(i, 3)}
    cv = cv_mask(curve, chemistry)
    if chemistry in NI:
        use = measured(curve, cv)
        drop = peak(curve.t[use], curve.v[use], curve.mah[use], series)[1]     # as the figures read it
        kind, values = ("dv", {"drop": f"{drop:.1f}"}) if drop > 0.5 else ("log_ends", {})
    elif cv.any():
        # A charge that started at its held voltage has no CC current to state the end's share of: "–".
        share = f"{100 * i / cc_current(curve, cv):.0f} %" if has_cc_phase(curve, cv) else "–"
        kind, values = "cv", {"a": f"{i:.3g}", "share": share, "v": f"{v:.3f}"}
    else:
        kind, values = "cc", {}
    return {**end, "why": real_end_why(kind, values, translate=False), "kind": kind, "values": values}


def _model_peak(sim: SimResult, series: int, i_cc: float) -> tuple[float, float]:
    """The simulation's own peak (mAh) and -dV (mV per cell) over its whole charge: a model that
    runs on past the log's end peaks where the log no longer is."""
    a = sim.log.arrays()
    use = charging(a["current_a"], i_cc)
    if use.sum() < 2:
        return 0.0, 0.0
    return peak(a["time_s"][use], a["voltage_v"][use], a["mah_in"][use], series)


def log_charger(curve: Curve, base: str) -> ChargerLimits:
    """``base``'s power stage with its charge limits raised to what the log's charger delivered: a
    log from a 1 kW iCharger is not to be held to a B6's 50 W (the simulation would charge at a
    third of the log's current and say nothing about the macro)."""
    limits = load_charger(base)
    margin = 1.02
    out = np.clip(-curve.i, 0.0, None)
    return replace(limits, max_charge_a=max(limits.max_charge_a, float(curve.i.max()) * margin),
                   max_charge_w=max(limits.max_charge_w, float((curve.v * curve.i).max()) * margin),
                   max_discharge_a=max(limits.max_discharge_a, float(out.max()) * margin),
                   max_discharge_w=max(limits.max_discharge_w, float((curve.v * out).max()) * margin),
                   max_v=max(limits.max_v, float(curve.v.max()) * margin))


def _chemistry(record: bytes, chemistry: str | None, battery: str | None) -> str:
    if battery:
        from .batteries import load_battery
        return load_battery(battery).chem.name
    return load_chemistry(chemistry).name if chemistry else model_chemistry(record, BatterySetup())


def _resampled(curve: Curve, sim: SimResult) -> tuple[Curve, Run, np.ndarray]:
    """The part of the log the simulation covers, the simulation on its samples, and its own temperature."""
    a = sim.log.arrays()
    m_t, m_v, m_i, m_temp = a["time_s"], a["voltage_v"], a["current_a"], a["temp_c"]
    over = curve.t <= (m_t[-1] if len(m_t) else 0.0)
    if over.sum() < 10:
        raise ValueError(_("the simulation ended within the log's first samples: nothing to compare"))
    part = Curve(curve.t[over], curve.v[over], curve.i[over], None if curve.temp is None else curve.temp[over],
                 curve.cells, curve.name)
    return part, Run(np.interp(part.t, m_t, m_v), np.interp(part.t, m_t, m_i), np.interp(part.t, m_t, m_temp)), m_temp


def _simulate(record: bytes, params: StartParams, setup: BatterySetup,
              measured_r: MeasuredR | None) -> tuple[SimResult, dict | None]:
    """The macro on the model; with ``measured_r`` (and no named battery) the default model's R0 and R1
    scaled so that its step is the log's: then also what the report says of it."""
    if measured_r is None or setup.battery:
        return simulate(record, params, setup), None
    chem, scale = with_measured_r(load_chemistry(setup.chemistry), params.capacity_mah, measured_r)
    return simulate(record, params, replace(setup, chem=chem)), {**measured_r.to_dict(), "r_scale": round(scale, 3)}


def _model_end(sim: SimResult, mah: float) -> dict:
    a = sim.log.arrays()
    last = sim.phases[-1] if sim.phases else None
    return {"time_s": round(float(a["time_s"][-1]), 1) if len(a["time_s"]) else 0.0, "mah": round(mah, 1),
            "why": (last.reason if last else "") or sim.interpreter.end_reason}


def _compare_discharge(curve: Curve, record: bytes, chemistry: str | None, series: int, capacity_mah: float | None,
                       battery: str | None, charger: str, measured_r: MeasuredR | None) -> Comparison:
    """The macro started as a discharge at the log's current; the capacity it delivers is what the
    simulation took out until the macro's own end (its cutoff, not the log's)."""
    require_discharge(curve)
    chem_name = _chemistry(record, chemistry, battery)
    soc, ambient = start_setup(curve, chem_name, series)
    if capacity_mah is None:
        # What the log's discharge implies: it emptied the pack from where it started.
        capacity_mah = float(curve.delivered_mah[-1]) / max(soc, 0.05)
    params = StartParams("discharge", 1, round(capacity_mah), round(discharge_current(curve), 2), None, series)
    sim, said = _simulate(record, params, BatterySetup(chem_name, soc, ambient, log_charger(curve, charger), battery),
                          measured_r)
    part, run, m_temp = _resampled(curve, sim)
    delivered = sim.interpreter.q_out / 3.6
    report = discharge_figures(part, run, series, delivered)
    report["capacity"]["real_mah"] = round(float(curve.delivered_mah[-1]), 1)     # each over its whole run
    if report["temp_rise"] is not None:
        report["temp_rise"] = {"real_c": temp_rise(curve.temp), "model_c": temp_rise(m_temp),
                               "real_window_s": [round(float(curve.t[0]), 1), round(float(curve.t[-1]), 1)],
                               "model_window_s": [0.0, round(float(sim.log.arrays()["time_s"][-1]), 1)]}
    report["ends"] = {"real": real_end(curve, sim.chemistry, series), "model": _model_end(sim, delivered)}
    report["resistance"] = said
    return Comparison(sim, part.t, run, np.zeros(len(part.t), bool), report)


def compare(curve: Curve, record: bytes, chemistry: str | None, series: int, capacity_mah: float | None,
            battery: str | None = None, charger: str = "imax_b6",
            measured_r: MeasuredR | None = None) -> Comparison:
    """The macro's charge against the log's charge, or its discharge against the log's discharge (the
    curve's direction says which task the macro is started with). ``measured_r``: the pack's resistance
    read in the log (``measured_r``), which the default model then takes (report key ``resistance``)."""
    if curve.direction == "discharge":
        return _compare_discharge(curve, record, chemistry, series, capacity_mah, battery, charger, measured_r)
    require_charge(curve)
    chem_name = _chemistry(record, chemistry, battery)
    soc, ambient = start_setup(curve, chem_name, series)
    if capacity_mah is None:
        # What the log's charge implies: it filled the pack from where it started.
        capacity_mah = float(curve.mah[-1]) / (1.0 - soc)
    cv = cv_mask(curve, chem_name)
    params = StartParams("charge", 1, round(capacity_mah), round(cc_current(curve, cv), 2), None, series)
    sim, said = _simulate(record, params, BatterySetup(chem_name, soc, ambient, log_charger(curve, charger), battery),
                          measured_r)
    part, run, m_temp = _resampled(curve, sim)
    run.i = np.clip(run.i, 0.0, None)
    m_t = sim.log.arrays()["time_s"]
    part_cv = cv[:len(part.t)]
    report = figures(part, run, part_cv, series, sim.chemistry)
    if report["peak"] is not None:
        # Each peak over its own whole charge; the RMSE above is over the time both ran.
        use = measured(curve, cv)
        real_mah, real_dv = peak(curve.t[use], curve.v[use], curve.mah[use], series)
        model_mah, model_dv = _model_peak(sim, series, cc_current(curve, cv))
        report["peak"] = {"real_mah": round(real_mah, 1), "model_mah": round(model_mah, 1),
                          "real_dv_mv_per_cell": round(real_dv, 2), "model_dv_mv_per_cell": round(model_dv, 2)}
    if report["temp_rise"] is not None:
        # As the fit states it: the log's rise over its whole charge, the model's over its own run
        # (the model may stop before the log's warm end, or run past it).
        report["temp_rise"] = {"real_c": temp_rise(curve.temp), "model_c": temp_rise(m_temp),
                               "real_window_s": [round(float(curve.t[0]), 1), round(float(curve.t[-1]), 1)],
                               "model_window_s": [0.0, round(float(m_t[-1]), 1)]}
    report["ends"] = {"real": real_end(curve, sim.chemistry, series),
                      "model": _model_end(sim, sim.interpreter.q_in / 3.6)}
    report["resistance"] = said
    return Comparison(sim, part.t, run, part_cv, report)
