"""What the simulator's plot and the device's live plot share: voltage, current and
temperature stacked over one h:mm time axis, in one look (colours, axes, legends), with
the phases as labelled bands and a strip on top of the voltage plot kept for their labels.

Colours come from the palette's colour set (``theme.colours``: light or dark paper) and are
applied again when the palette changes (``set_colours``); the data and the view stay.

Performance follows the research notes (ide.md §3): clip to view, peak downsampling,
no antialiasing, no OpenGL."""
from __future__ import annotations

import numpy as np
import pyqtgraph as pg
from PySide6.QtCore import QEvent, QRectF, Qt, Signal
from PySide6.QtGui import QBrush, QColor, QFont, QFontMetrics, QPen, QTextOption

from ...i18n import N_, _
from ...logs import gaps
from ...sim.reasons import shown_reason
from ..base import theme
from ..base.timefmt import TimeAxisItem

CURVE_WIDTH = 2

# Smallest y spans: a flat 25 °C reads 24–26, not 24.995–25.005.
MIN_SPAN = {"current": 0.2, "temp": 2.0}
FILL_PX = 2                   # the area under the current: one point per this many pixels at most
AXIS_WIDTH = 54               # left and right axes, fixed: the three view boxes line up
LABEL_PT = 8
TICK_PT = 8
# Vertical axis titles in words, or just the unit when the plots are too low for the words.
# Quantities are translated, units are not (a short title with a word in it is translated too).
AXIS_LABELS = {"long": (N_("pack (V)"), N_("per cell (V)"), N_("current (A)"), N_("temp. (°C)")),
               "short": ("V", N_("V/cell"), "A", "°C")}


def band_label(p, short: bool = False) -> str:
    """``C1: IF(V>4.1S) STOP_FAZE``; a phase a default ended, or a charge a timer cut before full,
    gets a warning sign (and the latter says so)."""
    head = (_("C{index}") if p.section == "charge" else _("D{index}")).format(index=p.index or "")
    warn = "⚠ " if band_warns(p) else ""
    if short:
        return warn + head
    short_of_full = " " + _("(timer before full)") if getattr(p, "timer_before_full", False) else ""
    return f"{warn}{head}: {shown_reason(p.reason) or '…'}{short_of_full}"


def band_warns(p) -> bool:
    # A simulated phase knows whether it warns; a charger's phase (live) only how it ended.
    return p.warns if hasattr(p, "warns") else p.by_default


def curve_pen(colour: str, width: float = CURVE_WIDTH) -> QPen:
    return pg.mkPen(colour, width=width)


def colour_axes(plot: pg.PlotItem, look: theme.PlotColours) -> None:
    for name in ("left", "right", "bottom"):
        axis = plot.getAxis(name)
        axis.setPen(look.axis)
        axis.setTextPen(look.ink)            # after the pen: both set the title's colour


def rgba(colour: str, alpha: int) -> tuple[int, int, int, int]:
    c = QColor(colour)
    return c.red(), c.green(), c.blue(), alpha


def covered(t: np.ndarray, y: np.ndarray, x0: float, x1: float, y0: float, y1: float) -> int:
    """How many segments of the trace (t, y) pass through the rectangle x0..x1 × y0..y1: a
    steep edge between two samples outside it still crosses it (a gap, NaN, crosses nothing)."""
    if not len(t):
        return 0
    i0, i1 = np.searchsorted(t, [x0, x1])
    i0, i1 = max(0, i0 - 1), min(len(t), i1 + 1)      # the segments entering and leaving it
    seg = np.asarray(y[i0:i1], dtype=float)
    if len(seg) == 1:
        return int(y0 <= seg[0] <= y1)
    lo, hi = np.fmin(seg[:-1], seg[1:]), np.fmax(seg[:-1], seg[1:])
    with np.errstate(invalid="ignore"):
        return int(np.count_nonzero((hi >= y0) & (lo <= y1) & np.isfinite(seg[:-1]) & np.isfinite(seg[1:])))


class InlineLegend(pg.TextItem):
    """A one-line legend ("━ battery  ━ heat sink") in the corner of a plot where it
    hides the least data: a fraction of the height pyqtgraph's LegendItem takes, which
    matters in a plot 100 px high."""

    CORNERS = ("top-right", "bottom-right", "top-left", "bottom-left")

    def __init__(self, plot: pg.PlotItem, font: QFont, look: theme.PlotColours,
                 corners: tuple[str, ...] = CORNERS):
        super().__init__("", anchor=(1, 0))
        self.setFont(font)
        self.entries: list[tuple[str, str]] = []      # (name, colour)
        self.ink = look.ink
        self.fill = pg.mkBrush(*look.legend_fill)
        self.corners = corners
        self.corner = corners[0]
        self.vb = plot.vb
        self.setParentItem(self.vb)                    # view box pixels, not data coordinates
        self.setZValue(50)
        self.vb.sigResized.connect(self.reposition)

    def set_look(self, look: theme.PlotColours, entries: list[tuple[str, str]]) -> None:
        """The palette's ink and fill, and the entries again in their new colours."""
        self.ink = look.ink
        self.fill = pg.mkBrush(*look.legend_fill)
        self.set_entries(entries)

    def add(self, name: str, color: str) -> None:
        self.entries.append((name, color))
        self._render()

    def set_entries(self, entries: list[tuple[str, str]]) -> None:
        """Replace every entry at once: (name, colour)."""
        self.entries = list(entries)
        self._render()

    def rename(self, index: int, name: str) -> None:
        self.entries[index] = (name, self.entries[index][1])
        self._render()

    def names(self) -> list[str]:
        return [name for name, _ in self.entries]

    def _render(self) -> None:
        parts = [f'<span style="color:{color}; font-weight:bold;">&#9473;&#9473;</span>&nbsp;'
                 f'<span style="color:{self.ink};">{name}</span>' for name, color in self.entries]
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
        """Move to the corner that covers the least of the traces ``series`` (t, y)."""
        best, best_hits = self.corner, None
        for corner in self.corners:
            r = self._corner_rect(corner)
            if corner.startswith("top"):
                r.translate(0, reserved_top_px)
            a, b = self.vb.mapToView(r.topLeft()), self.vb.mapToView(r.bottomRight())
            x0, x1 = sorted((a.x(), b.x()))
            y0, y1 = sorted((a.y(), b.y()))
            hits = sum(covered(t, y, x0, x1, y0, y1) for t, y in series)
            if best_hits is None or hits < best_hits:
                best, best_hits = corner, hits
            if hits == 0:
                break
        self.corner = best
        self.reposition()
        if best.startswith("top") and reserved_top_px:
            self.setPos(self.pos().x(), self.pos().y() + reserved_top_px)


LABEL_GAP = 0.3                 # between two tick labels of an axis, at least this share of a label's height
PLACEHOLDER_MARGIN_PX = 12


class TidyAxisItem(pg.AxisItem):
    """A value axis whose tick labels never run into each other nor into the next plot's: pyqtgraph
    draws its first level of labels however crowded the axis, and lets a vertical axis's labels
    hang 15 px past its ends, over the plot above or below (a low plot at 1366x768)."""

    def __init__(self, orientation: str):
        super().__init__(orientation)
        self.setStyle(hideOverlappingLabels=True)

    def generateDrawSpecs(self, p):  # noqa: N802
        specs = super().generateDrawSpecs(p)
        if specs is None:
            return None
        axis, ticks, texts = specs
        kept: list = []
        for spec in texts:          # the coarsest level first: a label that would crowd one drawn is left out
            rect = spec[0]
            room = rect.adjusted(0, -LABEL_GAP * rect.height(), 0, LABEL_GAP * rect.height())
            if not any(room.intersects(other[0]) for other in kept):
                kept.append(spec)
        return axis, ticks, kept


def tidy_axes() -> dict[str, TidyAxisItem]:
    return {"left": TidyAxisItem("left"), "right": TidyAxisItem("right")}


class StackedPlot(pg.GraphicsLayoutWidget):
    """The three x-linked plots (``vplot``, ``iplot``, ``tplot``) with their axes, legends,
    zero line, placeholder text and phase labels. Subclasses add the curves and the bands
    (``self._phases``: objects with section, index, reason, by_default, start_s, end_s;
    ``self.curves``: quantity -> PlotDataItem, drawn in the quantity's hue).

    ``colours`` is the colour set drawn with; a palette change that turns it (light to dark
    or back) applies the other (``set_colours``), and subclasses re-colour what they added
    in ``_recolour``."""
    coloursChanged = Signal()           # after the plot took another colour set
    DENSE_PER_PX = 1.5                  # points per pixel across from which a curve is drawn 1 px wide

    def __init__(self, object_name: str, placeholder: str, grid: bool, parent=None):
        super().__init__(parent)
        self.setObjectName(object_name)
        self.colours = theme.colours(self.palette())
        look = self.colours.plot
        self.setBackground(look.paper)
        self.ci.setContentsMargins(2, 4, 4, 2)
        self.ci.setSpacing(0)
        self._label_font = QFont(self.font())
        self._label_font.setPointSize(LABEL_PT)
        self._tick_font = QFont(self.font())
        self._tick_font.setPointSize(TICK_PT)
        self._text_widths: dict[str, int] = {}
        self._short_labels: bool | None = None
        self._phases: list = []
        self.labels: list[pg.TextItem] = []
        self.curves: dict[str, pg.PlotDataItem] = {}
        self.grid = grid
        self.series_cells = 1              # the pack's cells: the per-cell axis divides by them

        self.time_axis = TimeAxisItem("bottom")
        self.vplot = self.addPlot(row=0, col=0, axisItems=tidy_axes())
        self.iplot = self.addPlot(row=1, col=0, axisItems=tidy_axes())
        self.tplot = self.addPlot(row=2, col=0, axisItems={"bottom": self.time_axis, **tidy_axes()})
        self.plots = (self.vplot, self.iplot, self.tplot)
        for plot in self.plots:
            self._style(plot, grid)
        for plot in self.plots[:-1]:
            plot.setXLink(self.tplot)
            plot.hideAxis("bottom")
        self.time_axis.title_style = {"color": look.ink, "font-size": f"{LABEL_PT}pt"}
        self.time_axis.set_format("h:mm")
        self.tplot.getAxis("bottom").setHeight(34)
        self._label_axes(short=False)
        # What the titles in words take as rendered (rich text, a little wider than the font's metrics).
        self._long_title_px = max(axis.label.boundingRect().width() for axis in self._title_axes())
        self.vplot.getAxis("right").setStyle(showValues=True)
        # The bottom plot carries the time axis; give it the extra height so the data areas match.
        self.ci.layout.setRowStretchFactor(0, 10)
        self.ci.layout.setRowStretchFactor(1, 10)
        self.ci.layout.setRowStretchFactor(2, 12)

        self.legends = {plot: InlineLegend(plot, self._label_font, look) for plot in self.plots}
        self.zero_line = pg.InfiniteLine(pos=0.0, angle=0, pen=self._zero_pen(), movable=False)
        self.iplot.addItem(self.zero_line, ignoreBounds=True)
        # The area under the current (``_set_current_fill``), drawn apart from its curve.
        self.current_fill = pg.PlotDataItem([], [], pen=None, fillLevel=0.0, fillBrush=self.current_fill_brush(),
                                            antialias=False, connect="finite")
        self.iplot.addItem(self.current_fill)
        self.placeholder = pg.TextItem(placeholder, color=look.placeholder, anchor=(0.5, 0.5))
        self.placeholder.setFont(self._label_font)
        self.vplot.addItem(self.placeholder, ignoreBounds=True)
        for plot in (self.iplot, self.tplot):
            plot.enableAutoRange(axis="y")
            plot.setAutoVisible(y=True)
        self.iplot.setLimits(minYRange=MIN_SPAN["current"])
        self.tplot.setLimits(minYRange=MIN_SPAN["temp"])

    # -- colours ----------------------------------------------------------------------------
    def changeEvent(self, event) -> None:  # noqa: N802
        super().changeEvent(event)
        if event.type() == QEvent.Type.PaletteChange and hasattr(self, "legends"):
            colours = theme.colours(self.palette())
            if colours is not self.colours:
                self.set_colours(colours)

    def set_colours(self, colours: theme.Colours) -> None:
        """Draw with another colour set: paper, axes, titles, legends, bands, labels and curves
        (the data and the view stay)."""
        self.colours = colours
        look = colours.plot
        self.setBackground(look.paper)
        for plot in self.plots:
            colour_axes(plot, look)
            if self.grid:
                plot.showGrid(x=True, y=True, alpha=look.grid_alpha)
        self.time_axis.title_style = {**self.time_axis.title_style, "color": look.ink}   # its next title
        self.zero_line.setPen(self._zero_pen())
        self.current_fill.setFillBrush(self.current_fill_brush())
        self.placeholder.setColor(look.placeholder)
        self._recolour()
        self.coloursChanged.emit()

    def _recolour(self) -> None:
        """The subclass's share of ``set_colours``: its curves, bands and labels."""

    def hue(self, quantity: str) -> str:
        return self.colours.quantities[quantity]

    def current_fill_brush(self) -> QBrush:
        return pg.mkBrush(*rgba(self.hue("current"), self.colours.plot.current_fill_alpha))

    def band_looks(self, section: str, alpha: int, opaque: bool = True) -> tuple[QBrush, QPen]:
        """A phase band's fill and edge in the section's hue (``opaque``: mixed over the paper
        beforehand, which the raster engine fills eight times faster)."""
        look = self.colours.plot
        rgb, edge = look.band_rgb(section), look.band_edge_alpha
        if opaque:
            return (pg.mkBrush(over_paper(rgb, alpha, look.paper)),
                    pg.mkPen(over_paper(rgb, edge, look.paper), width=1))
        return pg.mkBrush(*rgb, alpha), pg.mkPen(*rgb, edge, width=1)

    def label_colour(self, warns: bool) -> str:
        return self.colours.plot.band_warning if warns else self.colours.plot.band_label

    def _zero_pen(self) -> QPen:
        return pg.mkPen(self.colours.plot.zero, width=1, style=Qt.PenStyle.DashLine)

    def _recolour_curves(self) -> None:
        """``self.curves`` in their quantities' hues (a thinned curve stays thin), and the legends
        of the plots they lie in."""
        for name, curve in self.curves.items():
            curve.full_pen = curve_pen(self.hue(name))
            pen = pg.mkPen(curve.full_pen)
            if getattr(curve, "thin", False):
                pen.setWidthF(1.0)
            curve.setPen(pen)
        for plot, legend in self.legends.items():
            items = plot.listDataItems()
            legend.set_look(self.colours.plot, [(curve.opts["name"], self.hue(name))
                                                for name, curve in self.curves.items() if curve in items])

    # -- construction ------------------------------------------------------------------------
    def _style(self, plot: pg.PlotItem, grid: bool) -> None:
        plot.showAxis("right")
        plot.hideButtons()
        plot.setMenuEnabled(True)
        plot.setMouseEnabled(x=True, y=False)       # zoom and pan in time; y follows the data
        if grid:
            plot.showGrid(x=True, y=True, alpha=self.colours.plot.grid_alpha)
        plot.setClipToView(True)
        plot.setDownsampling(auto=True, mode="peak")
        plot.getViewBox().setDefaultPadding(0.04)
        for name in ("left", "right", "bottom"):
            axis = plot.getAxis(name)
            axis.setTickFont(self._tick_font)
            axis.enableAutoSIPrefix(False)
            if name != "bottom":
                axis.setWidth(AXIS_WIDTH)
        colour_axes(plot, self.colours.plot)
        plot.getAxis("right").setStyle(showValues=False)
        plot.getAxis("top").enableAutoSIPrefix(False)   # hidden, but would re-render its label every frame
        plot.layout.setContentsMargins(0, 0, 0, 0)

    def _axis_label(self, axis: pg.AxisItem, text: str) -> None:
        axis.setLabel(text, **{"color": self.colours.plot.ink, "font-size": f"{LABEL_PT}pt"})

    def _label_axes(self, short: bool) -> None:
        if short == self._short_labels:
            return
        self._short_labels = short
        for axis, text in zip(self._title_axes(), AXIS_LABELS["short" if short else "long"]):
            self._axis_label(axis, _(text))

    def _title_axes(self) -> tuple[pg.AxisItem, ...]:
        return (self.vplot.getAxis("left"), self.vplot.getAxis("right"), self.iplot.getAxis("left"),
                self.tplot.getAxis("left"))

    def resizeEvent(self, event) -> None:  # noqa: N802
        super().resizeEvent(event)
        if not hasattr(self, "legends"):        # pyqtgraph resizes during construction
            return
        lowest = min(plot.vb.height() for plot in self.plots)
        self._label_axes(short=lowest < self._long_title_px + 8)

    def set_series_count(self, cells: int) -> None:
        """Cells in series: the right voltage axis shows volts per cell."""
        self.series_cells = max(1, int(cells or 1))
        self.vplot.getAxis("right").setScale(1.0 / self.series_cells)

    def set_sensor(self, sensor: bool) -> None:
        name = _("battery") if sensor else _("battery (no sensor)")
        if self.curves["temp"].opts["name"] == name:       # a new legend costs a millisecond: only on a change
            return
        self.curves["temp"].opts["name"] = name
        self.legends[self.tplot].rename(0, name)

    # -- view --------------------------------------------------------------------------------
    def _text_width(self, text: str) -> int:
        width = self._text_widths.get(text)
        if width is None:
            width = self._text_widths[text] = QFontMetrics(self._label_font).horizontalAdvance(text)
        return width

    def _label_height_px(self) -> float:
        return QFontMetrics(self._label_font).height() + 4.0

    def _fit_voltage(self, t: np.ndarray, v: np.ndarray, *more: tuple[np.ndarray, np.ndarray]) -> None:
        """Y follows the visible voltage (and the ``more`` curves, (t, y) each: the cells), with a
        strip on top kept free for the phase labels."""
        vb = self.vplot.vb
        if not len(t):
            vb.setYRange(0.0, 1.0, padding=0)
            return
        x0, x1 = vb.viewRange()[0]

        def in_view(clock: np.ndarray, y: np.ndarray) -> np.ndarray:
            i0, i1 = np.searchsorted(clock, [x0, x1])
            return y[max(0, i0 - 1):min(len(y), i1 + 1)]

        seg = np.concatenate([in_view(t, v), *(in_view(*curve) for curve in more)]) if more else in_view(t, v)
        seg = seg[np.isfinite(seg)]          # a NaN breaks a line at a gap
        if not len(seg):
            seg = v[np.isfinite(v)]
        if not len(seg):
            vb.setYRange(0.0, 1.0, padding=0)
            return
        lo, hi = float(np.min(seg)), float(np.max(seg))
        span = max(hi - lo, 0.02 * max(abs(hi), 1.0))
        pad = 0.06 * span
        height = max(vb.height(), 20.0)
        room = min(self._label_height_px(), height * 0.4) if self._phases else 0.0
        per_px = (span + 2 * pad) / max(height - room, 10.0)
        vb.setYRange(lo - pad, hi + pad + room * per_px, padding=0)

    def _place_placeholder(self) -> None:
        if self.placeholder.isVisible():
            (x0, x1), (y0, y1) = self.vplot.vb.viewRange()
            self.placeholder.setPos((x0 + x1) / 2, (y0 + y1) / 2)
            # Wrapped to the plot's width: a narrow plot (Russian runs longer) must not cut it at both ends.
            width = max(60.0, self.vplot.vb.width() - 2 * PLACEHOLDER_MARGIN_PX)
            if self.placeholder.textItem.textWidth() != width:
                self.placeholder.setTextWidth(width)
                self.placeholder.textItem.document().setDefaultTextOption(QTextOption(Qt.AlignmentFlag.AlignHCenter))

    def _new_label(self) -> pg.TextItem:
        label = pg.TextItem("", color=self.label_colour(False), anchor=(0, 0))
        label.setFont(self._label_font)
        label.setZValue(20)
        self.vplot.addItem(label, ignoreBounds=True)
        self.labels.append(label)
        return label

    def _label_texts(self, p) -> tuple[str, ...]:
        """A band's label, longest first: the first that fits the band's visible width is shown."""
        return band_label(p), band_label(p, short=True)

    def _place_labels(self) -> None:
        if not self.labels:
            return
        vb = self.vplot.vb
        (x0, x1), (_, ytop) = vb.viewRange()
        px = vb.viewPixelSize()[0] or 1.0        # seconds per pixel
        for p, label in zip(self._phases, self.labels):
            start, end = max(p.start_s, x0), min(p.end_s, x1)
            width_px = (end - start) / px - 6
            text = None
            if width_px > 0:
                text = next((c for c in self._label_texts(p) if self._text_width(c) + 4 <= width_px), None)
            label.setVisible(text is not None)
            if text is not None:
                if getattr(label, "shown_text", None) != text:    # toPlainText costs half a millisecond
                    label.setText(text)
                    label.shown_text = text
                label.setPos(start + 2 * px, ytop)

    def _set_current_fill(self, x: np.ndarray, y: np.ndarray, pairs: bool, gap_s: float = float("inf")) -> None:
        """The area under the current, from at most one point per FILL_PX pixels: pyqtgraph fills
        a curve 50 points a polygon, and a filled curve of thousands of points (an envelope's
        min/max pairs: ``pairs``) was the slowest thing on the plot. No area spans a step of
        more than ``gap_s`` (a gap in the recording): each stretch between gaps is its own."""
        points = max(50, int(self.iplot.vb.width()) // FILL_PX)
        cuts = list(gaps.gap_after(x, gap_s) + 1) if len(x) else []
        xs: list[np.ndarray] = []
        ys: list[np.ndarray] = []
        for a, b in zip([0, *cuts], [*cuts, len(x)]):
            ox, oy = area_outline(x[a:b], y[a:b], max(2, points * (b - a) // max(1, len(x))), pairs)
            if xs:
                xs.append(np.array([ox[0]]))
                ys.append(np.array([np.nan]))
            xs.append(ox)
            ys.append(oy)
        self.current_fill.setData(np.concatenate(xs) if xs else x, np.concatenate(ys) if ys else y)

    def _thin_dense_curves(self) -> None:
        """Dense curves (more points drawn than the plot has pixels across, as when hours of
        samples are in view) are drawn 1 px wide: the envelope fills the band anyway, and a
        raster painter strokes 2 px lines at twice the cost."""
        limit = self.DENSE_PER_PX * max(self.vplot.vb.width(), 100.0)
        for curve in self.curves.values():
            x, _ = curve.getData()
            dense = x is not None and len(x) > limit
            if dense != getattr(curve, "thin", False):
                if not hasattr(curve, "full_pen"):
                    curve.full_pen = pg.mkPen(curve.opts["pen"])
                curve.thin = dense
                pen = pg.mkPen(curve.full_pen)
                if dense:
                    pen.setWidthF(1.0)
                curve.setPen(pen)

    def export_png(self, path: str) -> bool:
        return self.grab().save(path, "PNG")


def over_paper(rgb: tuple[int, int, int], alpha: int, paper: str) -> QColor:
    """The opaque colour a translucent one makes over the paper."""
    a, under = alpha / 255.0, QColor(paper)
    return QColor(*(int(round(p + (c - p) * a)) for c, p in zip(rgb, (under.red(), under.green(), under.blue()))))


def area_outline(x: np.ndarray, y: np.ndarray, points: int, pairs: bool) -> tuple[np.ndarray, np.ndarray]:
    """At most about ``points`` points that keep, per group of samples (or of min/max pairs:
    ``pairs``), the one farthest from zero: the outline of the area under a curve."""
    if pairs:
        x, y = x[0::2], np.where(y[1::2] > -y[0::2], y[1::2], y[0::2])
    step = max(1, -(-len(x) // max(1, points)))
    if step == 1:
        return x, y
    k = len(x) // step * step
    groups = y[:k].reshape(-1, step)
    far = groups[np.arange(len(groups)), np.abs(groups).argmax(axis=1)]
    return np.append(x[:k:step], x[k:]), np.append(far, y[k:])
