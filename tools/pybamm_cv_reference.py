"""The CV tail's reference figures from PyBaMM (issue 35 §1): Chen2020 (LG M50, 5 Ah) from empty, CC at 0.5C, 1C
and 2C to 4.2 V, then CV at 4.2 V to C/50, solved by the DFN (the oracle) and the SPM (for comparison).
Writes tests/data/pybamm_cv_chen2020.json, which tests/sim/test_cv_tail.py holds the lithium model to; the
suite never needs PyBaMM.

PyBaMM is not a dependency of ZUML Studio: run this from a venv of its own,
    python3 -m venv /tmp/pybamm-venv && /tmp/pybamm-venv/bin/pip install pybamm
    /tmp/pybamm-venv/bin/python tools/pybamm_cv_reference.py
"""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pybamm

OUT = Path(__file__).resolve().parents[1] / "tests" / "data" / "pybamm_cv_chen2020.json"
RATES = (0.5, 1.0, 2.0)
V_MAX = 4.2
END_C = 50                  # the CV ends at C/END_C
CURVE_POINTS = 21           # the CV current at this many evenly spaced times of the phase


def figures(model: pybamm.BaseModel, rate: float) -> dict:
    experiment = pybamm.Experiment([(f"Charge at {rate:g}C until {V_MAX} V", f"Hold at {V_MAX} V until C/{END_C}")],
                                   period="5 seconds")
    sim = pybamm.Simulation(model, parameter_values=pybamm.ParameterValues("Chen2020"), experiment=experiment,
                            solver=pybamm.IDAKLUSolver())
    sol = sim.solve(initial_soc=0.0)
    cc, cv = sol.cycles[0].steps
    t_cc = cc["Time [s]"].entries
    t_cv = cv["Time [s]"].entries
    i_cv = -cv["Current [A]"].entries          # PyBaMM: charge is negative
    duration = float(t_cv[-1] - t_cv[0])
    grid = t_cv[0] + np.linspace(0.0, duration, CURVE_POINTS)
    curve = np.interp(grid, t_cv, i_cv)
    charged = sol["Discharge capacity [A.h]"].entries
    return {
        "cc_s": round(float(t_cc[-1] - t_cc[0]), 1),
        "cv_s": round(duration, 1),
        "cv_half_a": round(float(np.interp(t_cv[0] + duration / 2, t_cv, i_cv)), 5),
        "cc_a": round(float(-cc["Current [A]"].entries[-1]), 5),
        "charged_ah": round(float(abs(charged[-1] - charged[0])), 5),
        "cv_current_a": [round(float(x), 5) for x in curve],
    }


def main() -> None:
    out = {"source": f"PyBaMM {pybamm.__version__}, ParameterValues('Chen2020'), from empty (initial_soc 0), "
                     f"CC to {V_MAX} V then CV to C/{END_C}; tools/pybamm_cv_reference.py",
           "capacity_ah": 5.0, "v_max": V_MAX, "end_c": END_C, "rates": list(RATES), "models": {}}
    for name, model in (("DFN", pybamm.lithium_ion.DFN), ("SPM", pybamm.lithium_ion.SPM)):
        out["models"][name] = {f"{rate:g}C": figures(model(), rate) for rate in RATES}
        for rate, f in out["models"][name].items():
            print(f"{name} {rate}: CC {f['cc_s'] / 60:.1f} min, CV {f['cv_s'] / 60:.1f} min, "
                  f"half-way {f['cv_half_a']:.3f} A, {f['charged_ah']:.3f} Ah")
    OUT.write_text(json.dumps(out, indent=1) + "\n")
    print(f"wrote {OUT}")


if __name__ == "__main__":
    main()
