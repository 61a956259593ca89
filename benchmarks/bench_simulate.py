"""Simulated seconds per wall second for the issue's two reference runs, at a 1 s tick.

Target: at least 100 000x real time (a 2-hour charge in under 72 ms), so the GUI can
re-simulate on every edit. Run: python benchmarks/bench_simulate.py
"""
from __future__ import annotations

import statistics
import time

from zuml_studio.data import standard_macros_dir
from zuml_studio.lang.compiler import compile_source
from zuml_studio.sim.interpreter import StartParams
from zuml_studio.sim.simulate import simulate

MACROS = standard_macros_dir()
RUNS = {
    "NiMH 2000 mAh x4, 1C, -dV (NiMh-dV)": ("NiMh-dV", StartParams("charge", 1, 2000, 2.0, None, 4, False)),
    "LiPo 2000 mAh x3, 1C CC-CV (LiPo seed)": ("LiPo", StartParams("charge", 1, 2000, 2.0, None, 3, True)),
    "LiIon 5000 mAh, 1C CC-CV to C/50": ("LiIon-CCCV", StartParams("charge", 1, 5000, 5.0, None, 1, True)),
}


def main() -> None:
    for label, (name, params) in RUNS.items():
        record = compile_source((MACROS / f"{name}.zuml").read_text()).record
        walls = []
        for _ in range(7):
            t0 = time.perf_counter()
            result = simulate(record, params)
            walls.append(time.perf_counter() - t0)
        wall = statistics.median(walls)
        simulated = result.interpreter.time_s
        print(f"{label}: {simulated / 3600:.2f} h simulated in {wall * 1000:.1f} ms = "
              f"{simulated / wall:,.0f}x real time, {wall / len(result.log) * 1e6:.1f} us/tick "
              f"(target >= 100,000x)")


if __name__ == "__main__":
    main()
