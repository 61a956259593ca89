"""A log file in the stacked V/I/T plot the simulator and the live view share
(``ui/stacked_plot.py``): phase bands from the log's states, per-cell voltages on the
per-cell axis, other logs or cycles laid over in their own colours, and a crosshair whose
readout names time, V, I, T and phase at the cursor."""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pyqtgraph as pg
from PySide6.QtCore import Signal

from ...i18n import N_, _, ngettext
from ...logs import Log
from ...logs.model import Phase, state_of
from ..plot_backdrop import BackdropItem
from ..stacked_plot import (BAND_ALPHA, BATTERY_T_PEN, CURRENT_FILL, CURRENT_PEN, HEATSINK_T_PEN, INK,
                            LABEL_COLOR, VOLTAGE_PEN, StackedPlot, band_rgb)
from ..timefmt import hmmss

CURSOR_PEN = pg.mkPen("#505050", width=1)
CELL_COLORS = ("#4f81bd", "#c0504d", "#9bbb59", "#8064a2", "#4bacc6", "#f79646", "#2c4d75", "#772c2a",
               "#5f7530", "#4d3b62", "#276a7c", "#b65708")
OVERLAY_COLORS = ("#e08a00", "#8e44ad", "#16a085", "#c0392b", "#7f8c8d", "#2c3e50", "#d35400", "#27ae60")
BAND_STATES = ("charge", "discharge", "pause")
SHORT = {"charge": N_("C{index}"), "discharge": N_("D{index}"), "pause": N_("P{index}")}
STATE_WORDS = {"charge": N_("charge"), "discharge": N_("discharge"), "pause": N_("pause")}


@dataclass
class Layer:
    name: str
    log: Log
    data: dict
    color: str | None = None      # None: the first log, in the quantities' own colours


class LogPlot(StackedPlot):
    cursorMoved = Signal(str)      # the readout at the crosshair

    def __init__(self, parent=None):
        super().__init__("logPlot", _("no log open: File ▸ Open Log…"), grid=True, parent=parent)
        self.layers: list[Layer] = []
        self.items: list[tuple[pg.PlotItem, pg.GraphicsObject]] = []
        # Every band of a plot in one item: a LinearRegionItem per phase and plot took a third
        # of a second to add for a log of 28 phases, on the GUI thread.
        self.band_items = [BackdropItem(plot, self.time_axis, grid=False) for plot in self.plots]
        for plot, item in zip(self.plots, self.band_items):
            plot.addItem(item, ignoreBounds=True)
        self._t = np.zeros(0)
        self._v = np.zeros(0)
        self.cursor_lines = []
        for plot in self.plots:
            line = pg.InfiniteLine(angle=90, movable=False, pen=CURSOR_PEN)
            line.setZValue(30)
            line.setVisible(False)
            plot.addItem(line, ignoreBounds=True)
            self.cursor_lines.append(line)
        self.placeholder.setPos(0.5, 0.5)
        for legend in self.legends.values():
            legend.setVisible(False)
        self.vplot.sigXRangeChanged.connect(self._view_changed)
        self.vplot.vb.sigResized.connect(self._view_changed)
        for plot in (self.iplot, self.tplot):      # their y auto-range is applied lazily, before painting
            plot.sigYRangeChanged.connect(lambda *_: self._place_legends())
        self.scene().sigMouseMoved.connect(self._mouse_moved)

    # -- data --------------------------------------------------------------------------------
    def show_layers(self, layers: list[tuple[str, Log]], bands: bool = True) -> None:
        """Draw logs over one time axis: the first in the quantities' colours with its phase
        bands (``bands``), the others each in one colour."""
        for plot, item in self.items:
            plot.removeItem(item)
        self.items.clear()
        for band_item in self.band_items:
            band_item.set_bands([])
        for label in self.labels:
            self.vplot.removeItem(label)
        self.labels.clear()
        self.layers = [Layer(name, log, log.arrays(), None if k == 0 else OVERLAY_COLORS[(k - 1) % len(OVERLAY_COLORS)])
                       for k, (name, log) in enumerate(layers)]
        self._phases = []
        if not self.layers:
            self._t, self._v = np.zeros(0), np.zeros(0)
            self.placeholder.setVisible(True)
            for legend in self.legends.values():
                legend.setVisible(False)
            return
        first = self.layers[0]
        cells = first.data["cells"].shape[1]       # Log.cells, counted once already (a pass over the samples)
        self.set_series_count(cells or 1)
        alone = len(self.layers) == 1
        for layer in self.layers:
            self._draw(layer, cells, alone)
        if bands:
            self._set_bands([p for p in first.log.phases() if p.state in BAND_STATES])
        t = np.concatenate([layer.data["t"] for layer in self.layers])
        v = np.concatenate([layer.data["voltage"] for layer in self.layers])
        order = np.argsort(t, kind="stable")
        self._t, self._v = t[order], v[order]
        self._set_legends(cells)
        self.placeholder.setVisible(False)
        start, end = float(self._t[0]), float(self._t[-1])
        span = max(end - start, 10.0)
        for plot in self.plots:
            plot.setLimits(xMin=start - 0.05 * span, xMax=end + 0.05 * span, minXRange=min(10.0, span / 2))
        self.tplot.setXRange(start, start + span, padding=0.01)
        self._view_changed()

    def _curve(self, plot: pg.PlotItem, x, y, pen, **kw) -> None:
        finite = np.isfinite(y)
        if not finite.any():
            return
        curve = plot.plot(x, y, pen=pen, antialias=False, connect="finite", **kw)
        curve.setClipToView(True)
        curve.setDownsampling(auto=True, method="peak")
        self.items.append((plot, curve))

    def _draw(self, layer: Layer, cells: int, alone: bool) -> None:
        """The first log in the quantities' colours (with its cells and the charger's inside
        temperature when it is alone), an overlay in its one colour."""
        d = layer.data
        t = d["t"]
        if layer.color is None:
            self._curve(self.vplot, t, d["voltage"], VOLTAGE_PEN)
            # Cells on the pack axis times the cell count: the right axis reads them in V per cell.
            for k in range(d["cells"].shape[1] if alone else 0):
                pen = pg.mkPen(CELL_COLORS[k % len(CELL_COLORS)], width=1)
                self._curve(self.vplot, t, d["cells"][:, k] * cells, pen)
            if layer.log.meta.get("current_measured", True):
                self._curve(self.iplot, t, d["current"], CURRENT_PEN, fillLevel=0.0, fillBrush=CURRENT_FILL)
            self._curve(self.tplot, t, d["temp"], BATTERY_T_PEN)
            if alone:
                self._curve(self.tplot, t, d["heatsink"], HEATSINK_T_PEN)
            return
        pen = pg.mkPen(layer.color, width=2)
        self._curve(self.vplot, t, d["voltage"], pen)
        if layer.log.meta.get("current_measured", True):
            self._curve(self.iplot, t, d["current"], pen)
        self._curve(self.tplot, t, d["temp"], pen)

    def _set_legends(self, cells: int) -> None:
        first = self.layers[0]
        if len(self.layers) > 1:
            entries = [(first.name, VOLTAGE_PEN.color().name())] + [(layer.name, layer.color)
                                                                    for layer in self.layers[1:]]
        else:
            entries = [(_("pack voltage"), VOLTAGE_PEN.color().name())]
            if cells:
                entries.append((ngettext("{n} cell (right axis)", "{n} cells (right axis)", cells).format(n=cells),
                                CELL_COLORS[0]))
        self.legends[self.vplot].set_entries(entries)
        self.legends[self.iplot].set_entries([(_("+ charge, − discharge"), CURRENT_PEN.color().name())])
        temps = []
        if np.isfinite(first.data["temp"]).any():
            temps.append((_("battery"), BATTERY_T_PEN.color().name()))
        if len(self.layers) == 1 and np.isfinite(first.data["heatsink"]).any():
            temps.append((_("charger inside"), HEATSINK_T_PEN.color().name()))
        self.legends[self.tplot].set_entries(temps or [(_("no temperature in this log"), INK)])
        for legend in self.legends.values():
            legend.setVisible(True)

    def _set_bands(self, phases: list[Phase]) -> None:
        self._phases = phases
        parity = {state: 0 for state in BAND_STATES}
        spans = []
        for p in phases:
            alpha = BAND_ALPHA[parity[p.state] % 2]
            parity[p.state] += 1
            r, g, b = band_rgb(p.state)
            spans.append((p.start_s, p.end_s, pg.mkBrush(r, g, b, alpha), pg.mkPen(r, g, b, 110, width=1)))
            label = self._new_label()
            label.setColor(LABEL_COLOR)
        for band_item in self.band_items:
            band_item.set_bands(spans)

    def _label_texts(self, p) -> tuple[str, ...]:
        short = _(SHORT[p.state])
        return (f"{_(STATE_WORDS[p.state])} {p.index}", short.format(index=p.index), short.format(index=""))

    # -- view --------------------------------------------------------------------------------
    def _view_changed(self, *_) -> None:
        self._fit_voltage(self._t, self._v)
        self._place_placeholder()
        self._place_labels()
        self._place_legends()

    def _place_legends(self) -> None:
        """Each legend to the corner where it hides the fewest samples."""
        if not self.layers:
            return
        room = self._label_height_px() if self._phases else 0.0
        self.legends[self.vplot].place([(self._t, self._v)], reserved_top_px=room)
        series = {self.iplot: [], self.tplot: []}
        for layer in self.layers:
            d = layer.data
            series[self.iplot].append((d["t"], d["current"]))
            series[self.tplot] += [(d["t"], d["temp"]), (d["t"], d["heatsink"])]
        for plot, items in series.items():
            self.legends[plot].place(items)

    # -- cursor ------------------------------------------------------------------------------
    def readout(self, seconds: float) -> str:
        """What the log says at a time: the nearest sample of the first log (and the voltage
        of each overlay)."""
        if not self.layers:
            return ""
        parts = [self._sample_text(self.layers[0], seconds)]
        for layer in self.layers[1:]:
            k = _nearest(layer.data["t"], seconds)
            if k is not None:
                parts.append(f"{layer.name}: {layer.data['voltage'][k]:.3f} V")
        return "   │   ".join(p for p in parts if p)

    def _sample_text(self, layer: Layer, seconds: float) -> str:
        d = layer.data
        k = _nearest(d["t"], seconds)
        if k is None:
            return ""
        sample = layer.log.samples[k]
        items = [hmmss(d["t"][k]), f"{d['voltage'][k]:.3f} V"]
        if layer.log.meta.get("current_measured", True):
            items.append(f"{d['current'][k]:+.3f} A")
        if not math.isnan(d["temp"][k]):
            items.append(f"{d['temp'][k]:.1f} °C")
        items.append(state_of(sample))
        if sample.cells_v:
            items.append(_("cells {voltages}").format(voltages=" ".join(f"{c:.3f}" for c in sample.cells_v)))
        return "  ".join(items)

    def set_cursor(self, seconds: float | None) -> str:
        for line in self.cursor_lines:
            line.setVisible(seconds is not None and bool(self.layers))
            if seconds is not None:
                line.setPos(seconds)
        text = "" if seconds is None else self.readout(seconds)
        self.cursorMoved.emit(text)
        return text

    def _mouse_moved(self, pos) -> None:
        for plot in self.plots:
            if plot.vb.sceneBoundingRect().contains(pos):
                self.set_cursor(plot.vb.mapSceneToView(pos).x())
                return
        self.set_cursor(None)


def _nearest(t: np.ndarray, seconds: float) -> int | None:
    if not len(t):
        return None
    k = int(np.searchsorted(t, seconds))
    if k >= len(t):
        return len(t) - 1
    if k > 0 and seconds - t[k - 1] < t[k] - seconds:
        return k - 1
    return k
