"""Micro-benchmark: microseconds per Pack.step and per Pack.current_for_voltage, per chemistry.

Run from the repository root:  python benchmarks/bench_battery.py
Budget: a 2-hour charge at dt = 1 s (7200 steps) well under 30 ms, i.e. about 3 us per step.
"""
from __future__ import annotations

import pathlib
import sys
import timeit

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1]))

from zuml_studio.sim.battery import Pack  # noqa: E402
from zuml_studio.sim.chemistry import chemistry_names, load_chemistry  # noqa: E402

STEPS = 7200


def bench(name: str) -> tuple[float, float]:
    chem = load_chemistry(name)
    pack = Pack(chem, 2000, 4, soc=0.3)
    step = pack.step

    def charge() -> None:
        for _ in range(STEPS):
            step(1.0, 1.0)

    t_step = min(timeit.repeat(charge, number=1, repeat=5)) / STEPS
    cv_pack = Pack(chem, 2000, 4, soc=0.3)
    solve = cv_pack.current_for_voltage
    target = cv_pack.open_circuit_voltage() + 0.2

    def cv() -> None:
        for _ in range(STEPS):
            solve(target, 1.0)

    t_cv = min(timeit.repeat(cv, number=1, repeat=5)) / STEPS
    return t_step, t_cv


def main() -> None:
    print(f"{'chemistry':10s} {'step us':>8s} {'cv us':>8s} {'7200 steps ms':>14s}")
    for name in chemistry_names():
        t_step, t_cv = bench(name)
        print(f"{name:10s} {t_step * 1e6:8.2f} {t_cv * 1e6:8.2f} {t_step * STEPS * 1e3:14.1f}")


if __name__ == "__main__":
    main()
