"""A log file in the stacked V/I/T plot the simulator and the live view share
(``ui/plots/stacked_plot.py``): phase bands from the log's states, per-cell voltages on the
per-cell axis, other logs or cycles laid over in their own colours, and a crosshair whose
readout names time, V, I, T and phase at the cursor.

Nothing is drawn where a log has no samples (``logs/gaps.py``): every curve is handed, per view,
a min and a max per pixel column of the samples in view, broken at each gap; the phase bands
leave the gaps out; the readout says "no data" in a gap.

Two cursors (A and B, each a vertical line through the three plots, dragged with the mouse)
mark a span: ``cursorsMoved`` tells where they are, the document shows what the log says
between them (``logs/window_stats.py``). Each curve can be hidden (``set_hidden``, by its key:
"voltage", "cell 1"…, "deviation", "current", "temp", "heatsink"); every cell has its own legend
entry; with two cells or more the cell deviation (highest − lowest, mV) is drawn in the
temperature plot on its right axis."""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import pyqtgraph as pg
from PySide6.QtCore import Qt, Signal
from PySide6.QtGui import QColor

from ...i18n import N_, _
from ...logs import Log, gaps
from ...logs.model import Phase, state_of
from ...logs.window_stats import deviation_mv
from ..plots.plot_backdrop import BackdropItem
from ..plots.stacked_plot import StackedPlot, curve_pen
from ..base.timefmt import hmmss

BAND_STATES = ("charge", "discharge", "pause")
DEVIATION_HUE = 4                 # the grey of the overlay hues: apart from both temperatures' hues
SHORT = {"charge": N_("C{index}"), "discharge": N_("D{index}"), "pause": N_("P{index}")}
STATE_WORDS = {"charge": N_("charge"), "discharge": N_("discharge"), "pause": N_("pause"), "idle": N_("idle")}


@dataclass
class Layer:
    name: str
    log: Log
    data: dict
    overlay: int | None = None    # which of the overlay colours; None: the first log, in the quantities' own
    gap_s: float = math.inf       # a step between samples longer than this is a gap (``gaps.gap_threshold``)


# What a curve shows, which picks its pen from the colour set: a quantity ("voltage", "current",
# "temp", "heatsink"), ("cell", k) or ("overlay", k).
Role = str | tuple[str, int]


def curve_key(role: Role) -> str:
    """The name a curve is hidden and remembered by."""
    if isinstance(role, tuple):
        return f"cell {role[1] + 1}" if role[0] == "cell" else f"overlay {role[1] + 1}"
    return role


class LogPlot(StackedPlot):
    cursorMoved = Signal(str)      # the readout at the crosshair
    cursorsMoved = Signal(float, float)     # cursors A and B (s), while shown

    def __init__(self, parent=None):
        super().__init__("logPlot", _("no log open: File ▸ Open Log…"), grid=True, parent=parent)
        self.layers: list[Layer] = []
        self.items: list[tuple[pg.PlotItem, pg.PlotDataItem, Role]] = []
        # Every band of a plot in one item: a LinearRegionItem per phase and plot took a third
        # of a second to add for a log of 28 phases, on the GUI thread.
        self.band_items = [BackdropItem(plot, self.time_axis) for plot in self.plots]
        for plot, item in zip(self.plots, self.band_items):
            plot.addItem(item, ignoreBounds=True)
        self._t = np.zeros(0)
        self._v = np.zeros(0)
        self.cursor_lines = []
        for plot in self.plots:
            line = pg.InfiniteLine(angle=90, movable=False, pen=self.colours.plot.cursor)
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
        self.hidden: set[str] = set()
        self._generation = 0
        # The cell deviation's own y axis: the temperature plot's right axis, over a view box of its own.
        self.deviation_vb = pg.ViewBox()
        self.deviation_vb.setXLink(self.tplot)
        self.tplot.scene().addItem(self.deviation_vb)
        self.tplot.getAxis("right").linkToView(self.deviation_vb)
        self.tplot.vb.sigResized.connect(self._place_deviation_box)
        self.deviation_vb.enableAutoRange(axis="y")
        self.deviation_vb.setAutoVisible(y=True)
        # Cursors A and B: a line per plot, the span between them shaded.
        self.ab_lines: dict[str, list[pg.InfiniteLine]] = {"a": [], "b": []}
        self.ab_spans: list[pg.LinearRegionItem] = []
        for plot in self.plots:
            span = pg.LinearRegionItem(movable=False, brush=self._span_brush(), pen=pg.mkPen(None))
            span.setZValue(-5)
            span.setVisible(False)
            plot.addItem(span, ignoreBounds=True)
            self.ab_spans.append(span)
            for which in ("a", "b"):
                line = pg.InfiniteLine(angle=90, movable=True, pen=self._ab_pen(), hoverPen=self._ab_pen(3),
                                       label=which.upper(),
                                       labelOpts={"position": 0.96, "color": self.colours.plot.ink})
                line.setZValue(40)
                line.setVisible(False)
                line.sigPositionChanged.connect(lambda moved, which=which: self._ab_moved(which, moved))
                plot.addItem(line, ignoreBounds=True)
                self.ab_lines[which].append(line)

    # -- data --------------------------------------------------------------------------------
    def show_layers(self, layers: list[tuple[str, Log]], bands: bool = True) -> None:
        """Draw logs over one time axis: the first in the quantities' colours with its phase
        bands (``bands``), the others each in one colour."""
        for plot, item, role in self.items:
            (self.deviation_vb if role == "deviation" else plot).removeItem(item)
        self.items.clear()
        self._generation += 1             # new curves: their points are made whatever the view
        for band_item in self.band_items:
            band_item.set_bands([])
        for label in self.labels:
            self.vplot.removeItem(label)
        self.labels.clear()
        self.layers = []
        for k, (name, log) in enumerate(layers):
            data = log.arrays()
            self.layers.append(Layer(name, log, data, None if k == 0 else k - 1, gaps.gap_threshold(data["t"])))
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
        # No per-cell voltages (a NiMH pack on a charger's one slot): no per-cell axis, or it would read
        # the pack's voltage as one cell's.
        self.per_cell_axis = cells > 0
        right = self.vplot.getAxis("right")
        right.setStyle(showValues=self.per_cell_axis)
        short, self._short_labels = bool(self._short_labels), None
        self._label_axes(short)                     # the titles again, the per-cell one as it now is
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

    def _axis_label(self, axis, text: str) -> None:
        if axis is self.vplot.getAxis("right") and not getattr(self, "per_cell_axis", True):
            text = ""
        super()._axis_label(axis, text)

    def _colour(self, role: Role) -> str:
        if role == "deviation":
            return self.colours.plot.overlays[DEVIATION_HUE]
        if isinstance(role, str):
            return self.hue(role)
        kind, k = role
        hues = self.colours.plot.cells if kind == "cell" else self.colours.plot.overlays
        return hues[k % len(hues)]

    def _pen(self, role: Role):
        thin = (isinstance(role, tuple) and role[0] == "cell") or role == "deviation"
        return curve_pen(self._colour(role), width=1 if thin else 2)

    def _ab_pen(self, width: float = 1.5):
        return pg.mkPen(self.colours.plot.ink, width=width, style=Qt.PenStyle.DashLine)

    def _span_brush(self):
        ink = QColor(self.colours.plot.ink)
        ink.setAlpha(22)
        return pg.mkBrush(ink)

    def _curve(self, plot: pg.PlotItem, layer: Layer, y, role: Role, scale: float = 1.0, **kw) -> None:
        """A curve whose points ``_draw_view`` gives for each view (pyqtgraph's own peak
        downsampling groups samples by count, not time, and joins them across gaps); ``scale``
        multiplies the drawn points, not the log's column (a long log's cells are not copied)."""
        y = np.asarray(y, dtype=float)
        if not np.isfinite(y).any():
            return
        if role == "deviation":
            curve = pg.PlotDataItem([], [], pen=self._pen(role), antialias=False, connect="finite", **kw)
            self.deviation_vb.addItem(curve)
            plot = self.tplot
        else:
            curve = plot.plot([], [], pen=self._pen(role), antialias=False, connect="finite", **kw)
        curve.setClipToView(False)
        curve.setDownsampling(ds=1, auto=False)
        curve.source = (layer.data["t"], y, layer.gap_s, scale)
        curve.setVisible(curve_key(role) not in self.hidden)
        self.items.append((plot, curve, role))

    def _draw_view(self) -> None:
        """Every curve's points for the time span in view, a min and a max per pixel column (once per
        view: opening a log moves the range several times, often to where it was)."""
        (x0, x1), _y = self.vplot.vb.viewRange()
        pixels = max(100, int(self.vplot.vb.width()))
        key = (x0, x1, pixels, self._generation)
        if key == getattr(self, "_drawn_view", None):
            return
        self._drawn_view = key
        for _plot, curve, _role in self.items:
            t, y, gap_s, scale = curve.source
            x, drawn = gaps.envelope(t, y, x0, x1, pixels, gap_s)
            curve.setData(x, drawn * scale if scale != 1.0 else drawn)

    def _draw(self, layer: Layer, cells: int, alone: bool) -> None:
        """The first log in the quantities' colours (with its cells and the charger's inside
        temperature when it is alone), an overlay in its one colour."""
        d = layer.data
        if layer.overlay is None:
            self._curve(self.vplot, layer, d["voltage"], "voltage")
            # Cells on the pack axis times the cell count: the right axis reads them in V per cell.
            for k in range(d["cells"].shape[1] if alone else 0):
                self._curve(self.vplot, layer, d["cells"][:, k], ("cell", k), scale=cells)
            deviation = alone and d["cells"].shape[1] >= 2
            if deviation:
                self._curve(self.tplot, layer, deviation_mv(d["cells"]), "deviation")
            self.tplot.getAxis("right").setStyle(showValues=deviation)
            self._axis_label(self.tplot.getAxis("right"), "mV" if deviation else "")
            if layer.log.meta.get("current_measured", True):
                self._curve(self.iplot, layer, d["current"], "current", fillLevel=0.0,
                            fillBrush=self.current_fill_brush())
            self._curve(self.tplot, layer, d["temp"], "temp")
            if alone:
                self._curve(self.tplot, layer, d["heatsink"], "heatsink")
            return
        role = ("overlay", layer.overlay)
        self._curve(self.vplot, layer, d["voltage"], role)
        if layer.log.meta.get("current_measured", True):
            self._curve(self.iplot, layer, d["current"], role)
        self._curve(self.tplot, layer, d["temp"], role)

    def _set_legends(self, cells: int) -> None:
        first = self.layers[0]
        if len(self.layers) > 1:
            entries = [(first.name, self.hue("voltage"))] + [(layer.name, self._colour(("overlay", layer.overlay)))
                                                             for layer in self.layers[1:]]
        else:
            entries = [(_("pack voltage"), self.hue("voltage"))] if "voltage" not in self.hidden else []
            entries += [(_("cell {n}").format(n=k + 1) + (" " + _("(right axis)") if k == 0 else ""),
                         self._colour(("cell", k))) for k in range(cells) if f"cell {k + 1}" not in self.hidden]
        look = self.colours.plot
        self.legends[self.vplot].set_look(look, entries)
        self.legends[self.iplot].set_look(look, [(_("+ charge, − discharge"), self.hue("current"))])
        temps = []
        if np.isfinite(first.data["temp"]).any() and "temp" not in self.hidden:
            temps.append((_("battery"), self.hue("temp")))
        if len(self.layers) == 1 and np.isfinite(first.data["heatsink"]).any() and "heatsink" not in self.hidden:
            temps.append((_("charger inside"), self.hue("heatsink")))
        if any(role == "deviation" for _p, _c, role in self.items) and "deviation" not in self.hidden:
            temps.append((_("cell deviation (mV, right axis)"), self._colour("deviation")))
        self.legends[self.tplot].set_look(look, temps or [(_("no temperature in this log"), look.ink)])
        for legend in self.legends.values():
            legend.setVisible(True)

    def _set_bands(self, phases: list[Phase]) -> None:
        self._phases = phases
        for _p in phases:
            self._new_label()
        self._draw_bands()

    def _draw_bands(self) -> None:
        """Translucent over pyqtgraph's grid (drawn in the axes' pictures, under everything);
        a band covers only where the log has samples, never a gap."""
        parity = {state: 0 for state in BAND_STATES}
        spans = []
        covered = gaps.covered_spans(self.layers[0].data["t"], self.layers[0].gap_s) if self.layers else []
        for p in self._phases:
            alpha = self.colours.plot.band_alpha[parity[p.state] % 2]
            parity[p.state] += 1
            looks = self.band_looks(p.state, alpha, opaque=False)
            for a, b in covered:
                if a < p.end_s and b > p.start_s:
                    spans.append((max(a, p.start_s), min(b, p.end_s), *looks))
        for band_item in self.band_items:
            band_item.set_bands(spans)

    def _recolour(self) -> None:
        for plot, curve, role in self.items:
            curve.setPen(self._pen(role))
            if role == "current":
                curve.setFillBrush(self.current_fill_brush())
        for line in self.cursor_lines:
            line.setPen(self.colours.plot.cursor)
        for line in self.ab_lines["a"] + self.ab_lines["b"]:
            line.setPen(self._ab_pen())
        for span in self.ab_spans:
            span.setBrush(self._span_brush())
        for label in self.labels:
            label.setColor(self.label_colour(False))
        self._draw_bands()
        if self.layers:
            self._set_legends(self.layers[0].data["cells"].shape[1])

    def _label_texts(self, p) -> tuple[str, ...]:
        short = _(SHORT[p.state])
        return (f"{_(STATE_WORDS[p.state])} {p.index}", short.format(index=p.index), short.format(index=""))

    # -- view --------------------------------------------------------------------------------
    def _view_changed(self, *_) -> None:
        self._draw_view()
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

    def _place_deviation_box(self, *_) -> None:
        self.deviation_vb.setGeometry(self.tplot.vb.sceneBoundingRect())

    # -- curves shown ------------------------------------------------------------------------
    def curve_keys(self) -> list[tuple[str, str]]:
        """(key, name) of every curve of the first log that can be hidden, in drawing order."""
        names = {"voltage": _("pack voltage"), "current": _("current"), "temp": _("battery temperature"),
                 "heatsink": _("charger inside"), "deviation": _("cell deviation (max − min)")}
        out = []
        for _plot, _curve, role in self.items:
            key = curve_key(role)
            if not key.startswith("overlay"):
                out.append((key, names.get(key) or _("cell {n}").format(n=key.split()[1])))
        return out

    def set_hidden(self, keys: set[str]) -> None:
        """Hide the curves of these keys (``curve_key``), show the others."""
        self.hidden = set(keys)
        for _plot, curve, role in self.items:
            curve.setVisible(curve_key(role) not in self.hidden)
        if self.layers:
            self._set_legends(self.layers[0].data["cells"].shape[1])

    # -- cursors A and B ---------------------------------------------------------------------
    def show_cursors(self, on: bool) -> None:
        """Two cursors at a third and two thirds of the view (or where they were)."""
        for item in self.ab_lines["a"] + self.ab_lines["b"] + self.ab_spans:
            item.setVisible(on and bool(self.layers))
        if on and self.layers:
            (x0, x1), _y = self.vplot.vb.viewRange()
            a, b = self.cursors() or (x0 + (x1 - x0) / 3, x0 + 2 * (x1 - x0) / 3)
            if not (x0 <= a <= x1 and x0 <= b <= x1):
                a, b = x0 + (x1 - x0) / 3, x0 + 2 * (x1 - x0) / 3
            self.set_cursors(a, b)

    def cursors_shown(self) -> bool:
        return bool(self.ab_lines["a"]) and self.ab_lines["a"][0].isVisible()

    def cursors(self) -> tuple[float, float] | None:
        if not getattr(self, "_ab_set", False):
            return None
        return float(self.ab_lines["a"][0].value()), float(self.ab_lines["b"][0].value())

    def set_cursors(self, a: float, b: float) -> None:
        self._ab_set = True
        for which, x in (("a", a), ("b", b)):
            for line in self.ab_lines[which]:
                line.blockSignals(True)
                line.setValue(x)
                line.blockSignals(False)
        self._ab_changed()

    def _ab_moved(self, which: str, moved: pg.InfiniteLine) -> None:
        """One line dragged: the same cursor in the other plots follows."""
        x = moved.value()
        for line in self.ab_lines[which]:
            if line is not moved:
                line.blockSignals(True)
                line.setValue(x)
                line.blockSignals(False)
        self._ab_changed()

    def _ab_changed(self) -> None:
        a, b = self.cursors()
        for span in self.ab_spans:
            span.setRegion(sorted((a, b)))
        if self.cursors_shown():
            self.cursorsMoved.emit(a, b)

    # -- cursor ------------------------------------------------------------------------------
    def readout(self, seconds: float) -> str:
        """What the log says at a time: the nearest sample of the first log (and the voltage
        of each overlay)."""
        if not self.layers:
            return ""
        parts = [self._sample_text(self.layers[0], seconds)]
        for layer in self.layers[1:]:
            k = _nearest(layer.data["t"], seconds)
            if gaps.in_gap(layer.data["t"], seconds, layer.gap_s):
                parts.append(f"{layer.name}: " + _("no data"))
            elif k is not None:
                parts.append(f"{layer.name}: {layer.data['voltage'][k]:.3f} V")
        return "   │   ".join(p for p in parts if p)

    def _sample_text(self, layer: Layer, seconds: float) -> str:
        d = layer.data
        k = _nearest(d["t"], seconds)
        if k is None:
            return ""
        if gaps.in_gap(d["t"], seconds, layer.gap_s):
            return "  ".join((hmmss(seconds), _("no data")))
        sample = layer.log.samples[k]
        items = [hmmss(d["t"][k]), f"{d['voltage'][k]:.3f} V"]
        if layer.log.meta.get("current_measured", True):
            items.append(f"{d['current'][k]:+.3f} A")
        if not math.isnan(d["temp"][k]):
            items.append(f"{d['temp'][k]:.1f} °C")
        items.append(_(STATE_WORDS[state_of(sample)]))
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
