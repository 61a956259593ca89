"""The simulated run as a charger's display would draw it, only better: voltage,
current and temperature stacked over one h:mm time axis, with the phases as shaded
bands labelled by what ended them.

Performance follows the research notes (ide.md §3): clip to view, peak
downsampling, no antialiasing, no OpenGL."""
from __future__ import annotations

import numpy as np
import pyqtgraph as pg
from PySide6.QtCore import QRectF, Qt, Signal
from PySide6.QtGui import QFont, QFontMetrics

from ..timefmt import TimeAxisItem

# Colours: light paper, dark ink, one hue per quantity.
BACKGROUND = "w"
INK = "#303030"
AXIS_PEN = "#9a9a9a"
GRID_ALPHA = 0.12
VOLTAGE_PEN = pg.mkPen("#1f4e9c", width=2)
CURRENT_PEN = pg.mkPen("#23803a", width=2)
CURRENT_FILL = pg.mkBrush(35, 128, 58, 28)
BATTERY_T_PEN = pg.mkPen("#d0481c", width=2)
HEATSINK_T_PEN = pg.mkPen("#7b5ea7", width=2)
ZERO_PEN = pg.mkPen("#707070", width=1, style=Qt.PenStyle.DashLine)
# Bands: charge bluish, discharge reddish; neighbours alternate between two strengths.
BAND_RGB = {"charge": (74, 134, 232), "discharge": (232, 96, 74)}
BAND_ALPHA = (34, 16)
SELECTED_ALPHA = 80
LABEL_COLOR = "#1c2a44"
WARNING_COLOR = "#b34700"

AXIS_WIDTH = 54               # left and right axes, fixed: the three view boxes line up
LABEL_PT = 8
TICK_PT = 8
PLOT_NAMES = ("voltage", "current", "temperature")


def band_label(p, short: bool = False) -> str:
    """``C1: IF(V>4.1S) STOP_FAZE``; a default-ended phase gets a warning sign."""
    head = ("C" if p.section == "charge" else "D") + (str(p.index) if p.index else "")
    if short:
        return ("⚠ " if p.by_default else "") + head
    return f"{'⚠ ' if p.by_default else ''}{head}: {p.reason or '…'}"


class InlineLegend(pg.TextItem):
    """A one-line legend ("━ battery  ━ heat sink") in the corner of a plot where it
    hides the least data: a fraction of the height pyqtgraph's LegendItem takes, which
    matters in a plot 100 px high."""

    CORNERS = ("top-right", "bottom-right", "top-left", "bottom-left")

    def __init__(self, plot: pg.PlotItem, font: QFont, corners: tuple[str, ...] = CORNERS):
        super().__init__("", anchor=(1, 0), fill=pg.mkBrush(255, 255, 255, 215))
        self.setFont(font)
        self.entries: list[tuple[str, str]] = []      # (name, colour)
        self.corners = corners
        self.corner = corners[0]
        self.vb = plot.vb
        self.setParentItem(self.vb)                    # view box pixels, not data coordinates
        self.setZValue(50)
        self.vb.sigResized.connect(self.reposition)

    def add(self, name: str, color: str) -> None:
        self.entries.append((name, color))
        self._render()

    def rename(self, index: int, name: str) -> None:
        self.entries[index] = (name, self.entries[index][1])
        self._render()

    def names(self) -> list[str]:
        return [name for name, _ in self.entries]

    def _render(self) -> None:
        parts = [f'<span style="color:{color}; font-weight:bold;">&#9473;&#9473;</span>&nbsp;'
                 f'<span style="color:{INK};">{name}</span>' for name, color in self.entries]
        self.setHtml("&nbsp;&nbsp;&nbsp;".join(parts))
        self.reposition()

    def _size(self) -> tuple[float, float]:
        r = self.textItem.boundingRect()
        return r.width(), r.height()

    def _corner_rect(self, corner: str) -> QRectF:
        """The legend's rectangle in view box pixels if put in that corner."""
        rect = self.vb.rect()
        w, h = self._size()
        x = rect.right() - 4 - w if corner.endswith("right") else rect.left() + 4
        y = rect.top() + 2 if corner.startswith("top") else rect.bottom() - 2 - h
        return QRectF(x, y, w, h)

    def reposition(self, *_) -> None:
        r = self._corner_rect(self.corner)
        self.setAnchor((0, 0))
        self.setPos(r.left(), r.top())

    def place(self, series: list[tuple[np.ndarray, np.ndarray]], reserved_top_px: float = 0.0) -> None:
        """Move to the corner that covers the fewest visible samples of ``series`` (t, y)."""
        best, best_hits = self.corner, None
        for corner in self.corners:
            r = self._corner_rect(corner)
            if corner.startswith("top"):
                r.translate(0, reserved_top_px)
            a, b = self.vb.mapToView(r.topLeft()), self.vb.mapToView(r.bottomRight())
            x0, x1 = sorted((a.x(), b.x()))
            y0, y1 = sorted((a.y(), b.y()))
            hits = 0
            for t, y in series:
                if not len(t):
                    continue
                i0, i1 = np.searchsorted(t, [x0, x1])
                seg = y[i0:i1]
                hits += int(np.count_nonzero((seg >= y0) & (seg <= y1)))
            if best_hits is None or hits < best_hits:
                best, best_hits = corner, hits
            if hits == 0:
                break
        self.corner = best
        self.reposition()
        if best.startswith("top") and reserved_top_px:
            self.setPos(self.pos().x(), self.pos().y() + reserved_top_px)


class ChargePlot(pg.GraphicsLayoutWidget):
    phaseActivated = Signal(int)        # FAZE byte offset of a double-clicked band
    phaseClicked = Signal(int)          # row (phase run - 1) of a clicked band, -1 outside bands

    def __init__(self, parent=None):
        super().__init__(parent)
        self.setBackground(BACKGROUND)
        self.setObjectName("simPlot")
        self.ci.setContentsMargins(2, 4, 4, 2)
        self.ci.setSpacing(0)
        self._label_font = QFont(self.font())
        self._label_font.setPointSize(LABEL_PT)
        self._tick_font = QFont(self.font())
        self._tick_font.setPointSize(TICK_PT)
        self._phases: list = []
        self._t = np.zeros(0)
        self._v = np.zeros(0)
        self._data: dict[str, np.ndarray] = {}
        self._selected = -1
        self.bands: list[list[pg.LinearRegionItem]] = [[], [], []]     # per plot, one per phase
        self.labels: list[pg.TextItem] = []

        time_axis = TimeAxisItem("bottom")
        self.vplot = self.addPlot(row=0, col=0)
        self.iplot = self.addPlot(row=1, col=0)
        self.tplot = self.addPlot(row=2, col=0, axisItems={"bottom": time_axis})
        self.plots = (self.vplot, self.iplot, self.tplot)
        for plot in self.plots:
            self._style(plot)
        for plot in self.plots[:-1]:
            plot.setXLink(self.tplot)
            plot.hideAxis("bottom")
        self._axis_label(self.tplot.getAxis("bottom"), "time (h:mm)")
        self.tplot.getAxis("bottom").setHeight(34)
        self._axis_label(self.vplot.getAxis("left"), "pack (V)")
        self._axis_label(self.vplot.getAxis("right"), "per cell (V)")
        self.vplot.getAxis("right").setStyle(showValues=True)
        self._axis_label(self.iplot.getAxis("left"), "current (A)")
        self._axis_label(self.tplot.getAxis("left"), "temp. (°C)")
        # The bottom plot carries the time axis; give it the extra height so the data areas match.
        self.ci.layout.setRowStretchFactor(0, 10)
        self.ci.layout.setRowStretchFactor(1, 10)
        self.ci.layout.setRowStretchFactor(2, 12)

        self.legends = {plot: InlineLegend(plot, self._label_font) for plot in self.plots}
        self.curves = {
            "voltage": self._curve(self.vplot, VOLTAGE_PEN, "pack voltage"),
            "current": self._curve(self.iplot, CURRENT_PEN, "+ charge, − discharge",
                                   fillLevel=0.0, fillBrush=CURRENT_FILL),
            "temp": self._curve(self.tplot, BATTERY_T_PEN, "battery"),
            "heatsink": self._curve(self.tplot, HEATSINK_T_PEN, "heat sink"),
        }
        self.zero_line = pg.InfiniteLine(pos=0.0, angle=0, pen=ZERO_PEN, movable=False)
        self.iplot.addItem(self.zero_line, ignoreBounds=True)
        self.placeholder = pg.TextItem("no simulation yet: Simulate (F5)", color="#8a8a8a", anchor=(0.5, 0.5))
        self.placeholder.setFont(self._label_font)
        self.vplot.addItem(self.placeholder, ignoreBounds=True)
        self.placeholder.setPos(0.5, 0.5)

        for legend in self.legends.values():
            legend.setVisible(False)                # until there is something to explain
        for plot in (self.iplot, self.tplot):
            plot.enableAutoRange(axis="y")
            plot.setAutoVisible(y=True)
        for plot in (self.iplot, self.tplot):      # their y auto-range is applied lazily, before painting
            plot.sigYRangeChanged.connect(self._place_legends)
        self.vplot.sigXRangeChanged.connect(self._view_changed)
        self.vplot.vb.sigResized.connect(self._view_changed)
        self.scene().sigMouseClicked.connect(self._scene_clicked)

    # -- construction ------------------------------------------------------------------------
    def _style(self, plot: pg.PlotItem) -> None:
        plot.showAxis("right")
        plot.hideButtons()
        plot.setMenuEnabled(True)
        plot.setMouseEnabled(x=True, y=False)       # zoom and pan in time; y follows the data
        plot.showGrid(x=True, y=True, alpha=GRID_ALPHA)
        plot.setClipToView(True)
        plot.setDownsampling(auto=True, mode="peak")
        plot.getViewBox().setDefaultPadding(0.04)
        for name in ("left", "right", "bottom"):
            axis = plot.getAxis(name)
            axis.setPen(AXIS_PEN)
            axis.setTextPen(INK)
            axis.setTickFont(self._tick_font)
            axis.enableAutoSIPrefix(False)
            if name != "bottom":
                axis.setWidth(AXIS_WIDTH)
        plot.getAxis("right").setStyle(showValues=False)
        plot.layout.setContentsMargins(0, 0, 0, 0)

    def _axis_label(self, axis: pg.AxisItem, text: str) -> None:
        axis.setLabel(text, **{"color": INK, "font-size": f"{LABEL_PT}pt"})

    def _curve(self, plot: pg.PlotItem, pen, name: str, **kw) -> pg.PlotDataItem:
        self.legends[plot].add(name, pen.color().name())
        curve = plot.plot([], [], pen=pen, name=name, antialias=False, skipFiniteCheck=True, **kw)
        curve.setClipToView(True)
        curve.setDownsampling(auto=True, method="peak")
        return curve

    # -- data --------------------------------------------------------------------------------
    def clear_result(self) -> None:
        for curve in self.curves.values():
            curve.setData([], [])
        self._set_bands([])
        self._t = self._v = np.zeros(0)
        self._data = {}
        self.placeholder.setVisible(True)
        for legend in self.legends.values():
            legend.setVisible(False)

    def show_result(self, result) -> None:
        """Draw a SimResult: samples, phase bands, labels, the per-cell axis."""
        data = result.log.arrays()
        t = data["time_s"]
        self._t, self._v, self._data = t, data["voltage_v"], data
        self.curves["voltage"].setData(t, data["voltage_v"])
        self.curves["current"].setData(t, data["current_a"])
        self.curves["temp"].setData(t, data["temp_c"])
        self.curves["heatsink"].setData(t, data["heatsink_c"])
        sensor = result.interpreter.params.sensor
        self.curves["temp"].opts["name"] = name = "battery" if sensor else "battery (no sensor)"
        self.legends[self.tplot].rename(0, name)
        series = max(1, int(result.series or 1))
        right = self.vplot.getAxis("right")
        right.setScale(1.0 / series)
        self.placeholder.setVisible(len(t) == 0)
        for legend in self.legends.values():
            legend.setVisible(len(t) > 0)
        self._set_bands(list(result.phases))
        end = max(float(t[-1]) if len(t) else 0.0, 60.0)
        for plot in self.plots:
            plot.setLimits(xMin=-0.05 * end, xMax=end * 1.05, minXRange=min(30.0, end / 2))
        self.tplot.setXRange(0.0, end, padding=0.01)
        self._view_changed()

    def _set_bands(self, phases: list) -> None:
        for plot, bands in zip(self.plots, self.bands):
            for band in bands:
                plot.removeItem(band)
            bands.clear()
        for label in self.labels:
            self.vplot.removeItem(label)
        self.labels.clear()
        self._phases = phases
        self._selected = -1
        parity = {"charge": 0, "discharge": 0}
        for p in phases:
            alpha = BAND_ALPHA[parity[p.section] % 2]
            parity[p.section] += 1
            end = p.end_s if p.reason else max(p.end_s, p.start_s)
            for plot, bands in zip(self.plots, self.bands):
                band = pg.LinearRegionItem((p.start_s, end), orientation="vertical", movable=False,
                                           brush=self._band_brush(p, alpha), pen=self._band_pen(p))
                band.setZValue(-20)
                band.setToolTip(f"{band_label(p)}\ndouble-click: show the FAZE in the editor")
                band.phase_alpha = alpha
                plot.addItem(band, ignoreBounds=True)
                bands.append(band)
            label = pg.TextItem(band_label(p), color=WARNING_COLOR if p.by_default else LABEL_COLOR, anchor=(0, 0))
            label.setFont(self._label_font)
            label.setZValue(20)
            self.vplot.addItem(label, ignoreBounds=True)
            self.labels.append(label)

    @staticmethod
    def _band_brush(p, alpha: int):
        r, g, b = BAND_RGB.get(p.section, (150, 150, 150))
        return pg.mkBrush(r, g, b, alpha)

    @staticmethod
    def _band_pen(p):
        r, g, b = BAND_RGB.get(p.section, (150, 150, 150))
        return pg.mkPen(r, g, b, 110, width=1)

    def highlight(self, row: int) -> None:
        """Make one phase's bands stand out (the table's selection); -1 for none."""
        if row == self._selected:
            return
        for index in (self._selected, row):
            if 0 <= index < len(self._phases):
                p = self._phases[index]
                for bands in self.bands:
                    band = bands[index]
                    alpha = SELECTED_ALPHA if index == row else band.phase_alpha
                    band.setBrush(self._band_brush(p, alpha))
                    band.update()
        self._selected = row

    # -- view --------------------------------------------------------------------------------
    def _view_changed(self, *_) -> None:
        self._fit_voltage()
        self._place_labels()
        self._place_legends()

    def _place_legends(self, *_) -> None:
        t = self._t
        data = self._data
        if not len(t):
            return
        room = self._label_height_px() if self._phases else 0.0
        self.legends[self.vplot].place([(t, data["voltage_v"])], reserved_top_px=room)
        self.legends[self.iplot].place([(t, data["current_a"])])
        self.legends[self.tplot].place([(t, data["temp_c"]), (t, data["heatsink_c"])])

    def _label_height_px(self) -> float:
        return QFontMetrics(self._label_font).height() + 4.0

    def _fit_voltage(self) -> None:
        """Y follows the visible voltage, with a strip on top kept free for the phase labels."""
        t, v = self._t, self._v
        vb = self.vplot.vb
        if not len(t):
            vb.setYRange(0.0, 1.0, padding=0)
            self.placeholder.setPos(float(np.mean(vb.viewRange()[0])), 0.5)
            return
        x0, x1 = vb.viewRange()[0]
        i0, i1 = np.searchsorted(t, [x0, x1])
        seg = v[max(0, i0 - 1):min(len(v), i1 + 1)]
        if not len(seg):
            seg = v
        lo, hi = float(seg.min()), float(seg.max())
        span = max(hi - lo, 0.02 * max(abs(hi), 1.0))
        pad = 0.06 * span
        height = max(vb.height(), 20.0)
        room = min(self._label_height_px(), height * 0.4) if self._phases else 0.0
        per_px = (span + 2 * pad) / max(height - room, 10.0)
        vb.setYRange(lo - pad, hi + pad + room * per_px, padding=0)

    def _place_labels(self) -> None:
        if not self.labels:
            return
        vb = self.vplot.vb
        (x0, x1), (_, ytop) = vb.viewRange()
        px = vb.viewPixelSize()[0] or 1.0        # seconds per pixel
        metrics = QFontMetrics(self._label_font)
        for p, label in zip(self._phases, self.labels):
            start, end = max(p.start_s, x0), min(p.end_s, x1)
            width_px = (end - start) / px - 6
            text = None
            if width_px > 0:
                for candidate in (band_label(p), band_label(p, short=True)):
                    if metrics.horizontalAdvance(candidate) + 4 <= width_px:
                        text = candidate
                        break
            label.setVisible(text is not None)
            if text is not None:
                if label.toPlainText() != text:
                    label.setText(text)
                label.setPos(start + 2 * px, ytop)

    # -- mouse -------------------------------------------------------------------------------
    def phase_at(self, seconds: float) -> int:
        """Row of the phase running at a time, -1 if none."""
        for row, p in enumerate(self._phases):
            if p.start_s <= seconds <= p.end_s:
                return row
        return -1

    def _scene_clicked(self, ev) -> None:
        pos = ev.scenePos()
        for plot in self.plots:
            if plot.vb.sceneBoundingRect().contains(pos):
                row = self.phase_at(plot.vb.mapSceneToView(pos).x())
                if ev.double():
                    if row >= 0:
                        self.phaseActivated.emit(self._phases[row].offset)
                else:
                    self.phaseClicked.emit(row)
                return

    # -- export ------------------------------------------------------------------------------
    def export_png(self, path: str) -> bool:
        return self.grab().save(path, "PNG")

    def data_rect(self, plot_index: int = 0) -> QRectF:
        return self.plots[plot_index].vb.sceneBoundingRect()
