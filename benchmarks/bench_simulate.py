"""Simulated seconds per wall second for the reference runs, at a 1 s tick, and the memory
the sample log takes per tick (issue 16).

Targets: at least 150 000x real time, so the GUI can re-simulate on every edit; at most
30 bytes of sample log per tick, so a 200 h training (10 cycles of a 10 Ah pack at 0.1C)
fits in memory comfortably. Issue 26: each run on both engines (`simulate(engine=...)`: the C engine and
the Python interpreter, the reference); a 12S pack of unequal cells on the C engine at most 3x the one-cell
pack's cost per tick in the Python interpreter, and the one-cell LiIon CC-CV to C/50 at least as fast as
PyBaMM's SPM re-solve of the same charge (benchmarks/bench_pybamm.py, from a venv of its own).
Run: python benchmarks/bench_simulate.py
"""
from __future__ import annotations

import statistics
import time
import tracemalloc

from zuml_studio.data import standard_macros_dir
from zuml_studio.lang.compiler import compile_source
from zuml_studio.sim.interpreter import StartParams
from zuml_studio.sim.simulate import BatterySetup, simulate

MACROS = standard_macros_dir()
RUNS = {
    "NiMH 2000 mAh x4, 1C, -dV (NiMh-dV)": ("NiMh-dV", StartParams("charge", 1, 2000, 2.0, None, 4, False)),
    "LiPo 2000 mAh x3, 1C CC-CV (LiPo seed)": ("LiPo", StartParams("charge", 1, 2000, 2.0, None, 3, True)),
    "LiIon 5000 mAh, 1C CC-CV to C/50": ("LiIon-CCCV", StartParams("charge", 1, 5000, 5.0, None, 1, True)),
}
# A training that outlasts any cap of a few days: NiMH 10 Ah x4, 10 cycles at 1 A (0.1C), no sensor
# (each charge ends at 1.5x the capacity).
LONG = ("NiMh", StartParams("train", 10, 10000, 1.0, None, 4, False))


# Issue 26: a 12S pack of unequal cells (with the B6's balancer) against the one-cell pack, per tick.
CELLS = ("LiPo", StartParams("charge", 1, 2000, 2.0, None, 12, True), BatterySetup(cell_spread=(3.0, 10.0, 2.0)))


ENGINES = ("python", "c")


def _per_tick(record: bytes, params: StartParams, setup: BatterySetup = BatterySetup(), engine: str = "auto") -> float:
    walls = []
    for _ in range(5):
        t0 = time.perf_counter()
        result = simulate(record, params, setup, engine=engine)
        walls.append(time.perf_counter() - t0)
    return statistics.median(walls) / len(result.log)


def cells_against_one() -> None:
    name, params, setup = CELLS
    record = compile_source((MACROS / f"{name}.zuml").read_text()).record
    one = {engine: _per_tick(record, StartParams("charge", 1, 2000, 2.0, None, 1, True), engine=engine)
           for engine in ENGINES}
    for engine in ENGINES:
        twelve = _per_tick(record, params, setup, engine)
        print(f"LiPo 2000 mAh 1C CC-CV [{engine}]: one cell {one[engine] * 1e6:.2f} us/tick, 12S with spread "
              f"3,10,2 % and the balancer {twelve * 1e6:.2f} us/tick = {twelve / one['python']:.2f}x the one cell "
              f"in Python (target <= 3x)")


def main() -> None:
    cells_against_one()
    for label, (name, params) in RUNS.items():
        record = compile_source((MACROS / f"{name}.zuml").read_text()).record
        for engine in ENGINES:
            walls = []
            for _ in range(7):
                t0 = time.perf_counter()
                result = simulate(record, params, engine=engine)
                walls.append(time.perf_counter() - t0)
            wall = statistics.median(walls)
            simulated = result.interpreter.time_s
            print(f"{label} [{engine}]: {simulated / 3600:.2f} h simulated in {wall * 1000:.1f} ms = "
                  f"{simulated / wall:,.0f}x real time, {wall / len(result.log) * 1e6:.2f} us/tick "
                  f"(target >= 150,000x)")
    name, params = LONG
    record = compile_source((MACROS / f"{name}.zuml").read_text()).record
    for engine in ENGINES:
        _long(record, params, engine)


def _long(record: bytes, params: StartParams, engine: str) -> None:
    t0 = time.perf_counter()
    result = simulate(record, params, engine=engine)
    wall = time.perf_counter() - t0
    tracemalloc.start()
    again = simulate(record, params, engine=engine)
    held = tracemalloc.get_traced_memory()[0]
    tracemalloc.stop()
    ticks = len(again.log)
    own = again.log.nbytes() if hasattr(again.log, "nbytes") else held
    print(f"NiMH 10 Ah x4, training x10 at 0.1C [{engine}]: {result.interpreter.time_s / 3600:.1f} h simulated "
          f"({result.interpreter.end_reason}) in {wall:.2f} s = {result.interpreter.time_s / wall:,.0f}x real time; "
          f"the run holds {held / 1e6:.1f} MB = {held / ticks:.1f} bytes per tick, its sample log "
          f"{own / ticks:.1f} (target <= 30)")


if __name__ == "__main__":
    main()
