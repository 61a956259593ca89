"""The pack's cells on a stacked plot's voltage pane, the simulator's and the live view's alike:
each cell read on the per-cell (right) axis, which shows the pack's volts divided by its cells,
so a cell is drawn at its voltage times the pack's cells. Up to ``MAX_EACH`` cells each has its
line, colour and legend entry (cell k the k-th from the pack's negative end, the same colour in
both plots); more are drawn as the lowest and the highest cell with the spread between them
shaded. While a balancer bleeds a cell, its line is drawn again wide and translucent over it.

Which curves to draw comes from ``plot_data.CellCurve`` (the simulator's columns, or the live
view's): this module only draws them."""
from __future__ import annotations

from typing import Sequence

import numpy as np
import pyqtgraph as pg
from PySide6.QtGui import QColor

from ...i18n import _
from .plot_data import CellCurve
from .stacked_plot import StackedPlot, curve_pen, rgba

CELL_WIDTH = 1.4
BLEED_WIDTH = 6.0
BLEED_ALPHA = 110
SPREAD_ALPHA = 60
LOWEST_HUE, HIGHEST_HUE = 1, 4      # of many cells: the lowest in cell 1's red, the highest in cell 4's orange


def cell_hue(plot: StackedPlot, cell: int) -> str:
    """Cell ``cell``'s colour (1-based) on the plot's paper."""
    hues = plot.colours.plot.pack_cells
    return hues[(max(cell, 1) - 1) % len(hues)]


def legend_name(curve: CellCurve) -> str:
    if curve.kind == "min":
        return _("lowest cell")
    if curve.kind == "max":
        return _("highest cell")
    return _("cell {n}").format(n=curve.cell)


class CellCurves:
    """The cell curves of one plot: ``set_layout`` when the cells change, ``set_data`` per view."""

    def __init__(self, plot: StackedPlot):
        self.plot = plot
        self.layout: tuple[CellCurve, ...] = ()
        self.items: dict[str, pg.PlotDataItem] = {}      # by column
        self.spread: pg.FillBetweenItem | None = None
        self.scale = 1.0

    def set_layout(self, curves: Sequence[CellCurve], series: int) -> None:
        """The curves to draw (none: the plot as without cells); ``series``: the pack's cells, the
        per-cell axis's divisor."""
        self.scale = float(max(1, series))
        curves = tuple(curves)
        if curves == self.layout:
            return
        self._remove()
        self.layout = curves
        for c in curves:
            item = pg.PlotDataItem([], [], antialias=False, connect="finite", skipFiniteCheck=False)
            item.setClipToView(False)
            item.setDownsampling(ds=1, auto=False)
            item.setZValue(-3 if c.kind == "bleed" else -2)     # under the pack's curve, over the bands (-15, -20)
            self.plot.vplot.addItem(item)
            self.items[c.column] = item
        if any(c.kind == "min" for c in curves):
            low, high = (self.items[c.column] for c in curves if c.kind in ("min", "max"))
            self.spread = pg.FillBetweenItem(low, high)
            self.spread.setZValue(-4)
            self.plot.vplot.addItem(self.spread)
        self.recolour()

    def _remove(self) -> None:
        for item in self.items.values():
            self.plot.vplot.removeItem(item)
        if self.spread is not None:
            self.plot.vplot.removeItem(self.spread)
        self.items, self.spread = {}, None
        self.plot.legends[self.plot.vplot].set_entries(self._pack_entry())

    def _pack_entry(self) -> list[tuple[str, str]]:
        return [(self.plot.curves["voltage"].opts["name"], self.plot.hue("voltage"))]

    def recolour(self) -> None:
        """Pens, the spread's fill and the legend in the plot's colours (after a theme change too)."""
        entries = self._pack_entry()
        for c in self.layout:
            hue = cell_hue(self.plot, c.cell or (LOWEST_HUE if c.kind == "min" else HIGHEST_HUE))
            item = self.items[c.column]
            if c.kind == "bleed":
                item.setPen(pg.mkPen(QColor(*rgba(hue, BLEED_ALPHA)), width=BLEED_WIDTH))
                continue
            item.setPen(curve_pen(hue, CELL_WIDTH))
            entries.append((legend_name(c), hue))
        if self.spread is not None:
            self.spread.setBrush(pg.mkBrush(*rgba(cell_hue(self.plot, HIGHEST_HUE), SPREAD_ALPHA)))
        if self.layout:
            self.plot.legends[self.plot.vplot].set_entries(entries)

    def set_data(self, x: np.ndarray, ys: dict[str, np.ndarray]) -> None:
        """The view's points (an envelope's, or the samples): ``ys`` by column, in volts per cell."""
        for column, item in self.items.items():
            item.setData(x, np.asarray(ys[column]) * self.scale)

    def clear(self) -> None:
        self.set_layout((), 1)

    def displayed(self) -> list[tuple[np.ndarray, np.ndarray]]:
        """What is drawn, for placing the legend clear of it."""
        out = []
        for item in self.items.values():
            x, y = item.getData()
            if x is not None:
                out.append((x, y))
        return out
