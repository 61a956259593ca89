"""The Compare-with-Log dialog's two plots: the log's and the model's voltage per cell over
minutes, and their difference below, drawn in the palette's colour set (``theme.colours``) and
drawn again in the other set when the palette turns light or dark."""
from __future__ import annotations

import numpy as np
import pyqtgraph as pg
from PySide6.QtCore import QEvent

from ...i18n import _
from ...logs import gaps
from ..base import theme
from ..plots.cell_curves import CELL_WIDTH, HIGHEST_HUE, LOWEST_HUE, cell_hue
from ..plots.stacked_plot import colour_axes, curve_pen
from ..plots.plot_data import CellCurve

LINE_WIDTH = 1.5
CELL_ROLE = "cell:"


def cell_role(curve: CellCurve) -> str:
    """The role of a cell's line: its cell's hue (of many cells, the lowest's and the highest's)."""
    return f"{CELL_ROLE}{curve.cell or (LOWEST_HUE if curve.kind == 'min' else HIGHEST_HUE)}"


class ComparePlots(pg.GraphicsLayoutWidget):
    """``show_lines`` draws the lines; each is (plot, x, y, role, name) with the role one of
    ``PlotColours.compare``'s keys ("real", "model", "diff") or a cell's (``cell_role``: its hue is the
    pack's cell's, as in the simulator's and the live plot)."""

    def __init__(self, parent=None):
        super().__init__(parent)
        self.setObjectName("comparePlots")
        self.colours = theme.colours(self.palette())
        self.v_plot = self.addPlot(row=0, col=0)
        self.v_plot.setLabel("left", _("per cell"), units="V")
        self.legend = self.v_plot.addLegend(offset=(10, 10))
        self.d_plot = self.addPlot(row=1, col=0)
        self.d_plot.setLabel("left", _("model − real"), units="mV/cell")
        self.d_plot.setLabel("bottom", _("time"), units="min")
        self.d_plot.setXLink(self.v_plot)
        self.ci.layout.setRowStretchFactor(0, 3)
        self.ci.layout.setRowStretchFactor(1, 1)
        self._lines: list[tuple[pg.PlotItem, np.ndarray, np.ndarray, str, str | None]] = []
        self._apply_look()

    def show_lines(self, lines: list[tuple[pg.PlotItem, np.ndarray, np.ndarray, str, str | None]]) -> None:
        self._lines = list(lines)
        self._draw()

    def _draw(self) -> None:
        """Clearing keeps each view's range; the legend's labels are made anew in its text colour."""
        self.v_plot.clear()
        self.d_plot.clear()
        hues = self.colours.plot.compare
        for plot, x, y, role, name in self._lines:
            hue, width = ((hues[role], LINE_WIDTH) if role in hues
                          else (cell_hue(self, int(role[len(CELL_ROLE):])), CELL_WIDTH))
            # A gap in the log stays a gap (``logs/gaps.py``): no line is drawn across it.
            plot.plot(*gaps.broken(x, y), pen=curve_pen(hue, width=width), name=name, connect="finite")

    def _apply_look(self) -> None:
        look = self.colours.plot
        self.setBackground(look.paper)
        for plot in (self.v_plot, self.d_plot):
            colour_axes(plot, look)
        self.legend.setLabelTextColor(look.ink)
        self.legend.setBrush(*look.legend_fill)
        self.legend.setPen(look.readout_border)

    def changeEvent(self, event) -> None:  # noqa: N802
        super().changeEvent(event)
        if event.type() == QEvent.Type.PaletteChange and hasattr(self, "legend"):
            colours = theme.colours(self.palette())
            if colours is not self.colours:
                self.colours = colours
                self._apply_look()
                self._draw()
