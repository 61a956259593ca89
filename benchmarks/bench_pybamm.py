"""PyBaMM's single-particle model (SPM) with the IDAKLU solver on the charge bench_simulate.py times for
the LiIon-CCCV macro: a 5 Ah cell (Chen2020, the LG M50, 5 Ah) from empty, 1C CC to 4.2 V, then CV to C/50.
Issue 26 compares its re-solve (a second solve of the built simulation) with ZUML Studio's one-cell run.

PyBaMM is not a dependency of ZUML Studio: run this from a venv of its own,
    python3 -m venv /tmp/pybamm-venv && /tmp/pybamm-venv/bin/pip install pybamm
    /tmp/pybamm-venv/bin/python benchmarks/bench_pybamm.py
"""
from __future__ import annotations

import statistics
import time

import pybamm

EXPERIMENT = [("Charge at 1C until 4.2 V", "Hold at 4.2 V until C/50")]


def main() -> None:
    model = pybamm.lithium_ion.SPM()
    parameters = pybamm.ParameterValues("Chen2020")
    experiment = pybamm.Experiment(EXPERIMENT)
    t0 = time.perf_counter()
    sim = pybamm.Simulation(model, parameter_values=parameters, experiment=experiment,
                            solver=pybamm.IDAKLUSolver())
    solution = sim.solve(initial_soc=0.0)
    one_shot = time.perf_counter() - t0
    walls = []
    for _ in range(7):
        t0 = time.perf_counter()
        solution = sim.solve(initial_soc=0.0)
        walls.append(time.perf_counter() - t0)
    hours = solution["Time [h]"].entries[-1]
    charged = solution["Discharge capacity [A.h]"].entries
    print(f"PyBaMM {pybamm.__version__} SPM + IDAKLU, 5 Ah (Chen2020) 1C CC-CV to C/50: {hours:.2f} h, "
          f"{abs(charged[-1] - charged[0]):.2f} Ah in; one-shot (build + solve) {one_shot * 1000:.0f} ms, "
          f"re-solve {statistics.median(walls) * 1000:.1f} ms (median of 7)")


if __name__ == "__main__":
    main()
