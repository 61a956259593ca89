"""A pack's trend over its sessions: capacity (% of rated), resistance per cell and cell deviation,
one plot each on a shared date axis, each with the health check's limit as a dashed line."""
from __future__ import annotations

import datetime as dt

import numpy as np
import pyqtgraph as pg
from PySide6.QtCore import QEvent, Qt

from ...packs.health import CAPACITY_MIN_SHARE, CELL_DEVIATION_MAX_MV, RESISTANCE_MAX_GROWTH, TrendPoint
from ..base import theme
from ..plots.stacked_plot import colour_axes, curve_pen
from ...i18n import N_, _

# (field, axis title, the quantity hue it borrows)
# Short titles: three plots share a dock's height, a long title would run over the next plot's.
ROWS = (("capacity_pct", N_("capacity %"), "voltage"),
        ("resistance_mohm_per_cell", N_("mΩ/cell"), "current"),
        ("cell_deviation_mv", N_("cells ΔV mV"), "temp"))


def timestamp(recorded: str) -> float:
    """Seconds since the epoch of a session's date (a date alone is its midnight, UTC)."""
    when = dt.datetime.fromisoformat(recorded)
    return (when if when.tzinfo else when.replace(tzinfo=dt.timezone.utc)).timestamp()


class PackTrendPlot(pg.GraphicsLayoutWidget):
    """Follows the theme: a palette change redraws it in the new colours."""

    def __init__(self, parent=None):
        super().__init__(parent)
        self.look = theme.colours(self.palette())
        self.setBackground(self.look.plot.paper)
        self.shown: list[TrendPoint] = []
        self.points: dict[str, tuple[np.ndarray, np.ndarray]] = {}
        self.plots: dict[str, pg.PlotItem] = {}
        first = None
        for row, (field, title, _hue) in enumerate(ROWS):
            plot = self.addPlot(row=row, col=0, axisItems={"bottom": pg.DateAxisItem(orientation="bottom")})
            plot.setLabel("left", _(title))
            plot.getAxis("left").enableAutoSIPrefix(False)      # "mΩ/cell", never "mΩ/cell (x0.001)"
            plot.getAxis("left").setWidth(52)        # the same for all three: their x axes line up
            plot.showGrid(x=True, y=True, alpha=self.look.plot.grid_alpha)
            plot.setMenuEnabled(False)
            colour_axes(plot, self.look.plot)
            if first is not None:
                plot.setXLink(first)
            first = first or plot
            if row < len(ROWS) - 1:
                plot.getAxis("bottom").setStyle(showValues=False)
            self.plots[field] = plot

    def show_trend(self, points: list[TrendPoint]) -> None:
        """Draw the points (a session without a figure leaves no point on that plot, and a plot with no
        point draws no line and says so)."""
        self.shown = list(points)
        self.points = {}
        resistance = [p.resistance_mohm_per_cell for p in points if p.resistance_mohm_per_cell is not None]
        limits = {"capacity_pct": CAPACITY_MIN_SHARE * 100.0, "cell_deviation_mv": CELL_DEVIATION_MAX_MV,
                  "resistance_mohm_per_cell": resistance[0] * RESISTANCE_MAX_GROWTH if resistance else None}
        for field, _title, hue in ROWS:
            plot = self.plots[field]
            plot.clear()
            have = [p for p in points if getattr(p, field) is not None]
            x = np.array([timestamp(p.recorded) for p in have], float)
            y = np.array([getattr(p, field) for p in have], float)
            self.points[field] = (x, y)
            colour = self.look.quantities[hue]
            if len(x):
                plot.plot(x, y, pen=curve_pen(colour), symbol="o", symbolSize=7, symbolBrush=colour,
                          symbolPen=colour)
            else:
                empty = pg.TextItem(_("– (no session measures it)"), color=self.look.plot.ink, anchor=(0.5, 0.5))
                plot.addItem(empty)
            if limits[field] is not None:
                plot.addItem(pg.InfiniteLine(limits[field], angle=0, pen=pg.mkPen(
                        self.look.error, width=1, style=Qt.PenStyle.DashLine)))
            # The limit and zero in view, so a point's distance from the limit reads at a glance.
            top = max([limits[field] or 0.0, *y]) if len(y) or limits[field] else 1.0
            plot.setYRange(0.0, top * 1.1, padding=0)
            if not len(x):                      # the words in the middle of the plot, not on its edge
                stamps = [timestamp(p.recorded) for p in points] or [0.0]
                empty.setPos((min(stamps) + max(stamps)) / 2.0, top * 0.55)
        if points:
            stamps = [timestamp(p.recorded) for p in points]
            pad = max(86400.0 * 15, (max(stamps) - min(stamps)) * 0.05)
            self.plots[ROWS[0][0]].setXRange(min(stamps) - pad, max(stamps) + pad, padding=0)

    def changeEvent(self, event) -> None:  # noqa: N802
        super().changeEvent(event)
        if event.type() == QEvent.Type.PaletteChange and hasattr(self, "plots"):
            look = theme.colours(self.palette())
            if look is not self.look:
                self.look = look
                self.setBackground(look.plot.paper)
                for plot in self.plots.values():
                    colour_axes(plot, look.plot)
                self.show_trend(self.shown)
