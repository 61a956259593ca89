"""A simulated run whose sample log carries per-cell columns (the contract of issue 26: ``cell1_v`` …
``cellN_v`` in volts, cell k from the pack's negative end, and ``balance_mask`` with bit k-1 set while
cell k bleeds), made from a real run of the pack: until the simulator writes them itself, and so
that the plot's tests do not depend on its cell model."""
from __future__ import annotations

import numpy as np

import helpers
from zuml_studio.sim.interpreter import StartParams
from zuml_studio.sim.simulate import simulate

WEAK_CELL = 3


class CellLog:
    """The run's log, with ``cells`` cell columns: equal shares of the pack's voltage, cell
    ``WEAK_CELL`` rising 5 % faster over the run; the balancer bleeds it over the last quarter."""

    def __init__(self, log, cells: int, balancer: bool = True):
        self.log, self.cells, self.balancer = log, cells, balancer
        self.per_cell = True

    def __len__(self) -> int:
        return len(self.log)

    def arrays(self, start: int = 0, stop: int | None = None) -> dict[str, np.ndarray]:
        out = self.log.arrays(start, stop)
        share = out["voltage_v"] / self.cells
        ramp = np.linspace(0.0, 1.0, len(share)) if len(share) else share
        for k in range(1, self.cells + 1):
            out[f"cell{k}_v"] = share * (1.05 ** ramp if k == WEAK_CELL else 1.0 - 0.01 * ramp / self.cells)
        if self.balancer:
            out["balance_mask"] = np.where(ramp >= 0.75, 1 << (WEAK_CELL - 1), 0).astype(np.int64)
        return out

    def column(self, name: str) -> np.ndarray:
        return self.arrays()[name]


def lipo_run(cells: int, balancer: bool = True):
    """A LiPo charge of ``cells`` in series whose log has the cells' columns (none for ``cells`` = 0)."""
    result = simulate(helpers.compiled("LiPo"), StartParams(task="charge", capacity_mah=2000, current_a=2.0,
                                                            series=max(cells, 2)))
    if cells:
        result.interpreter.log = CellLog(result.interpreter.log, cells, balancer)
    return result
