"""Micro-benchmark: microseconds per Pack.step and per Pack.current_for_voltage, per chemistry;
then a 12S pack of unequal cells (CellPack) against a one-cell pack.

Run from the repository root:  python benchmarks/bench_battery.py
Budget: a 2-hour charge at dt = 1 s (7200 steps) well under 30 ms, i.e. about 3 us per step.
Issue 26's target: a 12S pack with spread costs at most 3x a one-cell pack (step + CV solve).
"""
from __future__ import annotations

import pathlib
import sys
import timeit

sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1]))

from zuml_studio.sim.battery import Pack  # noqa: E402
from zuml_studio.sim.cell_pack import CellPack, spread_cells  # noqa: E402
from zuml_studio.domain.chemistry import chemistry_names, load_chemistry  # noqa: E402

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


def cv_tick(make) -> float:
    """Seconds per CV tick (solve, then step at the solved current) on a fresh pack from `make`."""
    pack = make()
    target = pack.open_circuit_voltage() * 1.02
    solve, step = pack.current_for_voltage, pack.step

    def ticks() -> None:
        for _ in range(STEPS):
            step(solve(target, 1.0), 1.0)

    return min(timeit.repeat(ticks, number=1, repeat=5)) / STEPS


def cells_against_one() -> None:
    chem = load_chemistry("LiPo")
    one = cv_tick(lambda: Pack(chem, 2000, 1, soc=0.3))
    twelve = cv_tick(lambda: CellPack(chem, 2000, spread_cells(2000, 12, (5.0, 10.0, 2.0), seed=1, soc=0.3), 0.3))
    print(f"LiPo CV tick: one cell {one * 1e6:.2f} us, 12S with spread {twelve * 1e6:.2f} us = "
          f"{twelve / one:.1f}x (target <= 3x)")


def main() -> None:
    print(f"{'chemistry':10s} {'step us':>8s} {'cv us':>8s} {'7200 steps ms':>14s}")
    for name in chemistry_names():
        t_step, t_cv = bench(name)
        print(f"{name:10s} {t_step * 1e6:8.2f} {t_cv * 1e6:8.2f} {t_step * STEPS * 1e3:14.1f}")
    cells_against_one()


if __name__ == "__main__":
    main()
