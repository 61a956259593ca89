"""A cursor readout for the stacked V/I/T plots (simulator and live): a vertical line through
the three plots under the mouse and, beside it, the time, the values there and the phase.

The plot supplies its samples through a callable, so the readout does not care how they are
stored; the phases are the plot's own bands (``StackedPlot._phases``)."""
from __future__ import annotations

from typing import Callable, NamedTuple

import numpy as np
import pyqtgraph as pg
from PySide6.QtCore import QPointF, Qt

from ...i18n import _, ngettext
from .plot_data import MASK, MAX_EACH, cell_columns
from .stacked_plot import StackedPlot, band_label
from ..base.timefmt import hmmss

GAP_PX = 6


class Quantity(NamedTuple):
    key: str              # the column in the samples
    unit: str
    decimals: int


#: What the readout shows, in order (the samples' column names).
QUANTITIES = (Quantity("voltage_v", "V", 3), Quantity("current_a", "A", 2), Quantity("temp_c", "°C", 1))

Samples = Callable[[], tuple[np.ndarray, dict[str, np.ndarray]]]


def readout_text(t: np.ndarray, data: dict[str, np.ndarray], phases: list, seconds: float,
                 gap_s: float = float("inf")) -> str:
    """``0:23:45 · 1.382 V · 2.00 A · 27.3 °C`` and, on a second line, the phase running then
    (from the sample nearest ``seconds``); ``0:23:45 · no data`` between two samples more than
    ``gap_s`` apart (a gap: ``logs/gaps.py``); '' without samples."""
    if not len(t):
        return ""
    k = int(t.searchsorted(seconds))
    if 0 < k < len(t) and float(t[k]) != seconds and float(t[k]) - float(t[k - 1]) > gap_s:
        return f"{hmmss(seconds)} · " + _("no data")
    i = int(np.clip(np.searchsorted(t, seconds), 0, len(t) - 1))
    if i and abs(t[i - 1] - seconds) < abs(t[i] - seconds):
        i -= 1
    parts = [hmmss(float(t[i]))]
    parts += [f"{float(data[q.key][i]):.{q.decimals}f} {q.unit}" for q in QUANTITIES if q.key in data]
    text = " · ".join(parts)
    cells = cells_text(data, i)
    phase = next((p for p in phases if p.start_s <= t[i] <= p.end_s), None)
    return text + (f"\n{cells}" if cells else "") + (f"\n{band_label(phase)}" if phase is not None else "")


def cells_text(data: dict[str, np.ndarray], i: int) -> str:
    """Sample ``i``'s cells, each (up to MAX_EACH) or the lowest and highest, and the cells the
    balancer bleeds then; '' without cell columns or readings."""
    columns = cell_columns(data)
    if not columns:
        return ""
    volts = np.array([float(data[c][i]) for c in columns])
    if np.isnan(volts).all():           # no reading then (a live session's cells came later)
        return ""
    if len(columns) <= MAX_EACH:
        text = _("cells {values} V").format(values=" · ".join("–" if np.isnan(v) else f"{v:.3f}" for v in volts))
    else:
        low, high = int(np.nanargmin(volts)), int(np.nanargmax(volts))
        text = _("cells {low}–{high} V (lowest: cell {low_cell}, highest: cell {high_cell})").format(
            low=f"{volts[low]:.3f}", high=f"{volts[high]:.3f}", low_cell=low + 1, high_cell=high + 1)
    if MASK in data:
        bits = int(data[MASK][i])
        bleeding = [k for k in range(1, len(columns) + 1) if bits >> (k - 1) & 1]
        if bleeding:
            text += " · " + ngettext("the balancer bleeds cell {cells}", "the balancer bleeds cells {cells}",
                                     len(bleeding)).format(cells=", ".join(map(str, bleeding)))
    return text


class CursorReadout:
    """Follows the mouse over ``plot``; ``show_at(seconds)`` places it by hand (tests)."""

    def __init__(self, plot: StackedPlot, samples: Samples, gap_s: Callable[[], float] | None = None):
        self.plot = plot
        self.samples = samples
        self.gap_s = gap_s or (lambda: float("inf"))
        self.lines = []
        for p in plot.plots:
            line = pg.InfiniteLine(angle=90, movable=False)
            line.setZValue(40)
            line.hide()
            p.addItem(line, ignoreBounds=True)
            self.lines.append(line)
        self.label = pg.TextItem("", anchor=(0, 0))
        self.label.setFont(plot._label_font)
        self.label.setZValue(60)
        self.label.setParentItem(plot.vplot.vb)        # view box pixels: stays readable at any zoom
        self.label.hide()
        self._colour()
        plot.coloursChanged.connect(self._colour)
        plot.scene().sigMouseMoved.connect(self._mouse_moved)

    def _colour(self) -> None:
        """The plot's colour set: the line, the text, and the paper behind it."""
        look = self.plot.colours.plot
        for line in self.lines:
            line.setPen(pg.mkPen(look.cursor, width=1, style=Qt.PenStyle.DotLine))
        self.label.setColor(look.ink)
        self.label.fill = pg.mkBrush(*look.legend_fill)
        self.label.border = pg.mkPen(look.readout_border)
        self.label.update()

    def text(self) -> str:
        return self.label.toPlainText() if self.label.isVisible() else ""

    def show_at(self, seconds: float) -> bool:
        t, data = self.samples()
        text = readout_text(t, data, self.plot._phases, seconds, self.gap_s())
        if not text:
            self.hide()
            return False
        for line in self.lines:
            line.setPos(seconds)
            line.show()
        self.label.setText(text)
        vb = self.plot.vplot.vb
        x = vb.mapViewToScene(QPointF(seconds, 0)).x() - vb.sceneBoundingRect().left()
        box = self.label.textItem.boundingRect()
        # Beside the line, on the side with room; at the bottom of the voltage plot, under the labels.
        left = x + GAP_PX if x + GAP_PX + box.width() <= vb.width() else max(0.0, x - GAP_PX - box.width())
        self.label.setPos(left, max(0.0, vb.height() - 2 - box.height()))
        self.label.show()
        return True

    def hide(self) -> None:
        for line in self.lines:
            line.hide()
        self.label.hide()

    def _mouse_moved(self, pos) -> None:
        for p in self.plot.plots:
            if p.vb.sceneBoundingRect().contains(pos):
                self.show_at(p.vb.mapSceneToView(pos).x())
                return
        self.hide()
