"""A finished (or cancelled) simulation made ready to draw, off the GUI thread: the sample
log's columns as float64 arrays and their min/max envelopes at every zoom level, so that the
GUI thread draws any view of a run, a day of ticks or more, from about two points per pixel
without scanning the samples (``ChargePlot``). No Qt here.

A pack of several cells (the log has ``cell1_v`` … ``cellN_v``, and ``balance_mask`` where a
balancer ran: bit k-1 set while cell k bleeds) gets the columns its cell curves draw: each cell
and, where it bleeds, its voltage again (NaN elsewhere) up to ``MAX_EACH`` cells; beyond that the
lowest and the highest cell, and the highest again while any cell bleeds."""
from __future__ import annotations

import re
from dataclasses import dataclass, field
from typing import Mapping

import numpy as np

from .envelope import Envelope

CLOCK = "time_s"
CURVES = {"voltage": "voltage_v", "current": "current_a", "temp": "temp_c", "heatsink": "heatsink_c"}
MASK = "balance_mask"
MAX_EACH = 8                    # cells drawn one by one; more are drawn as their lowest and highest
LOWEST, HIGHEST, BLEEDING = "cells_min", "cells_max", "cells_bleed"
_CELL = re.compile(r"cell(\d+)_v")


@dataclass(frozen=True)
class CellCurve:
    column: str                 # in PlotData.data
    cell: int                   # 1-based; 0 for the lowest/highest of many
    kind: str                   # "cell", "bleed", "min", "max"


@dataclass(frozen=True)
class PlotData:
    result: object                      # the SimResult
    data: dict[str, np.ndarray]         # the log's columns (the cells' too, if any) and the cell curves'
    envelope: Envelope                  # over CURVES' columns and the cell curves', clock CLOCK
    cells: tuple[str, ...] = ()         # the log's cell columns, cell 1 first
    cell_curves: tuple[CellCurve, ...] = field(default=())

    def __len__(self) -> int:
        return len(self.data[CLOCK])


def cell_columns(data: Mapping[str, np.ndarray]) -> tuple[str, ...]:
    """``cell1_v`` … ``cellN_v`` as far as they run without a hole (a log of one cell has none)."""
    numbers = {int(m.group(1)) for m in map(_CELL.fullmatch, data) if m}
    count = 0
    while count + 1 in numbers:
        count += 1
    return tuple(f"cell{k}_v" for k in range(1, count + 1)) if count > 1 else ()


def cell_curves(data: dict[str, np.ndarray], cells: tuple[str, ...]) -> tuple[CellCurve, ...]:
    """Adds the derived columns the cell curves draw to ``data`` (and the lowest and highest cell,
    ``LOWEST`` and ``HIGHEST``, always); returns the curves in drawing order."""
    if not cells:
        return ()
    stack = np.vstack([data[c] for c in cells])
    data[LOWEST], data[HIGHEST] = np.nanmin(stack, axis=0), np.nanmax(stack, axis=0)     # the y range takes them
    mask = data.get(MASK)
    # A balancer that never bled (or a pack whose log keeps a mask of zeros) draws nothing over the cells.
    bits = np.asarray(mask, dtype=np.int64) if mask is not None and np.any(mask) else None
    if len(cells) <= MAX_EACH:
        curves = [CellCurve(c, k, "cell") for k, c in enumerate(cells, 1)]
        if bits is not None:
            for k, c in enumerate(cells, 1):
                column = f"cell{k}_bleed"
                data[column] = np.where((bits >> (k - 1)) & 1, data[c], np.nan)
                curves.append(CellCurve(column, k, "bleed"))
        return tuple(curves)
    curves = [CellCurve(LOWEST, 0, "min"), CellCurve(HIGHEST, 0, "max")]
    if bits is not None:
        data[BLEEDING] = np.where(bits != 0, data[HIGHEST], np.nan)
        curves.append(CellCurve(BLEEDING, 0, "bleed"))
    return tuple(curves)


def prepare_plot(result) -> PlotData:
    """Costs about as much as a tenth of the simulation: run it off the GUI thread."""
    data = result.log.arrays()
    if not result.log.per_cell:
        # Identical cells are each the pack's voltage over their count: N lines on one, nothing to read.
        for column in cell_columns(data) + (MASK,):
            data.pop(column, None)
    cells = cell_columns(data)
    curves = cell_curves(data, cells)
    envelope = Envelope(tuple(CURVES.values()) + tuple(c.column for c in curves), clock=CLOCK)
    envelope.update(len(data[CLOCK]), data)
    return PlotData(result, data, envelope, cells, curves)
