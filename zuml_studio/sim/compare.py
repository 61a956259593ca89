"""Run a macro from a real log's start conditions and set the two side by side: the same
figures as a fit, plus when and why each charge ended."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .curve import Curve
from .fit import NI, Run, cc_current, cv_mask, figures, soc_at_ocv
from .chemistry import load_chemistry
from .interpreter import StartParams
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
    first, and their flat OCV says little); Li and Pb from where the OCV meets the first voltage."""
    ambient = curve.ambient_c
    if chemistry in NI:
        return 0.0, ambient
    return soc_at_ocv(load_chemistry(chemistry), float(curve.v[0]) / series), ambient


def real_end(curve: Curve, chemistry: str, series: int) -> dict:
    """When the logged charge ended and the state change that shows why."""
    t, v, i = float(curve.t[-1]), float(curve.v[-1]), float(curve.i[-1])
    end = {"time_s": round(t, 1), "mah": round(float(curve.mah[-1]), 1), "v": round(v, 3), "a": round(i, 3)}
    cv = cv_mask(curve, chemistry)
    if chemistry in NI:
        drop = (float(curve.v.max()) - v) / series * 1000.0
        end["why"] = f"voltage {drop:.1f} mV per cell below its peak (-dV)" if drop > 0.5 else "log ends"
    elif cv.any():
        end["why"] = f"current tapered to {i:.3g} A ({100 * i / cc_current(curve, cv):.0f} % of CC) at {v:.3f} V"
    else:
        end["why"] = "log ends during constant current"
    return end


def compare(curve: Curve, record: bytes, chemistry: str | None, series: int, capacity_mah: float,
            battery: str | None = None, charger: str = "imax_b6") -> Comparison:
    if battery:
        from .batteries import load_battery
        chem_name = load_battery(battery).chem.name
    else:
        chem_name = load_chemistry(chemistry).name if chemistry else model_chemistry(record, BatterySetup())
    soc, ambient = start_setup(curve, chem_name, series)
    cv = cv_mask(curve, chem_name)
    params = StartParams("charge", 1, round(capacity_mah), round(cc_current(curve, cv), 2), None, series)
    sim = simulate(record, params, BatterySetup(chem_name, soc, ambient, charger, battery))
    a = sim.log.arrays()
    m_t, m_v, m_i, m_temp = a["time_s"], a["voltage_v"], np.clip(a["current_a"], 0.0, None), a["temp_c"]
    over = curve.t <= (m_t[-1] if len(m_t) else 0.0)
    if over.sum() < 10:
        raise ValueError(_("the simulation ended within the log's first samples: nothing to compare"))
    part = Curve(curve.t[over], curve.v[over], curve.i[over], None if curve.temp is None else curve.temp[over],
                 curve.cells, curve.name)
    run = Run(np.interp(part.t, m_t, m_v), np.interp(part.t, m_t, m_i), np.interp(part.t, m_t, m_temp))
    part_cv = cv[over]
    report = figures(part, run, part_cv, series, sim.chemistry)
    last = sim.phases[-1] if sim.phases else None
    report["ends"] = {
        "real": real_end(curve, sim.chemistry, series),
        "model": {"time_s": round(float(m_t[-1]), 1) if len(m_t) else 0.0,
                  "mah": round(sim.interpreter.q_in / 3.6, 1),
                  "why": (last.reason if last else "") or sim.interpreter.end_reason},
    }
    return Comparison(sim, part.t, run, part_cv, report)
