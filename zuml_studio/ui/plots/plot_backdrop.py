"""What lies under a stacked plot's curves, in one item per plot: the grid and every phase
band. Shared by the simulator's plot and the device's live plot."""
from __future__ import annotations

import math

import numpy as np
import pyqtgraph as pg
from PySide6.QtCore import QLine, QRect, QRectF

class BackdropItem(pg.GraphicsObject):
    """What lies under a plot's curves, in one item: the grid (major ticks) and every phase
    band (a shaded span of x with edge lines).

    pyqtgraph's own grid (``showGrid``) costs about 7 ms per plot and frame offscreen (its
    axis pictures replay a hundred differently-styled lines), and a LinearRegionItem per
    phase and plot costs more per frame than curves of a million points; one item drawing
    a few batched lines costs well under a millisecond."""

    def __init__(self, plot: pg.PlotItem, time_axis: pg.AxisItem, grid_colour: str | None = None):
        super().__init__()
        self.plot = plot
        self.grid = grid_colour is not None     # False: bands only (an item laid over another's bands)
        self.time_axis = time_axis
        self._bands: list[tuple[float, float, object, object]] = []   # x0, x1, brush, pen
        self._tips: list[str] = []
        # Everything here is opaque, its translucent colour mixed over the paper beforehand
        # (``StackedPlot.band_looks``, ``PlotColours.grid``): the raster engine blends a
        # translucent fill at ~20 ns a pixel, eight times an opaque one, and this item lies
        # under everything.
        self.grid_pen = pg.mkPen(grid_colour, width=1)
        self.setZValue(-20)

    def set_grid_colour(self, colour: str) -> None:
        self.grid_pen = pg.mkPen(colour, width=1)
        self.update()

    def set_bands(self, bands: list[tuple[float, float, object, object]], tips: list[str] | None = None) -> None:
        """``tips``: one tooltip per band, shown while the mouse is over it."""
        self._bands = list(bands)
        self._tips = list(tips or ())
        self.setAcceptHoverEvents(bool(self._tips))
        self.update()

    def hoverMoveEvent(self, ev) -> None:  # noqa: N802
        x = ev.pos().x()
        tip = next((tip for (x0, x1, _, _), tip in zip(self._bands, self._tips) if x0 <= x <= x1), "")
        if tip != self.toolTip():
            self.setToolTip(tip)

    def set_end(self, index: int, end: float) -> None:
        x0, _, brush, pen = self._bands[index]
        self._bands[index] = (x0, end, brush, pen)
        self.update()

    def spans(self) -> list[tuple[float, float]]:
        return [(a, b) for a, b, _, _ in self._bands]

    def boundingRect(self) -> QRectF:  # noqa: N802
        vr = self.viewRect()
        return QRectF() if vr is None else vr

    def viewRangeChanged(self) -> None:  # noqa: N802
        self.prepareGeometryChange()

    def dataBounds(self, axis, frac=1.0, orthoRange=None):  # noqa: N802
        return None

    @staticmethod
    def _major(axis: pg.AxisItem, lo: float, hi: float, size: float) -> np.ndarray:
        """The axis's major tick positions, from its own spacing rule (``tickSpacing``),
        without ``tickValues`` (which costs a millisecond a call)."""
        if not hi > lo or size <= 0:
            return np.zeros(0)
        try:
            levels = axis.tickSpacing(lo, hi, size)
        except Exception:   # noqa: BLE001 - a degenerate range
            return np.zeros(0)
        if not levels:
            return np.zeros(0)
        step, offset = levels[0]
        if not step > 0 or (hi - lo) / step > 200:
            return np.zeros(0)
        first = math.ceil((lo - offset) / step) * step + offset
        return np.arange(first, hi + step * 1e-9, step)

    def paint(self, painter, *args) -> None:
        vr = self.viewRect()
        vb = self.plot.vb
        if vr is None or vb is None:
            return
        left, right = vr.left(), vr.right()
        top, bottom = min(vr.top(), vr.bottom()), max(vr.top(), vr.bottom())
        xs = self._major(self.time_axis, left, right, vb.width()) if self.grid else ()
        ys = self._major(self.plot.getAxis("left"), top, bottom, vb.height()) if self.grid else ()
        # Draw in whole device pixels: the raster engine's fast path (a fill in data
        # coordinates, scaled by a million, costs ten times as much).
        tr = painter.transform()
        sx, dx, sy, dy = tr.m11(), tr.dx(), tr.m22(), tr.dy()
        if tr.m12() or tr.m21():
            return                                  # never rotated in a plot
        x_lo, x_hi = sorted((left * sx + dx, right * sx + dx))
        y_lo, y_hi = sorted((top * sy + dy, bottom * sy + dy))
        px_left, px_right = int(math.floor(x_lo)), int(math.ceil(x_hi))
        px_top, px_bottom = int(math.floor(y_lo)), int(math.ceil(y_hi))
        painter.save()
        painter.resetTransform()
        try:
            lines = [QLine(int(round(x * sx + dx)), px_top, int(round(x * sx + dx)), px_bottom) for x in xs]
            lines += [QLine(px_left, int(round(y * sy + dy)), px_right, int(round(y * sy + dy))) for y in ys]
            for x0, x1, brush, pen in self._bands:
                if x1 < left or x0 > right:
                    continue
                a = int(round(max(x0, left) * sx + dx))
                b = int(round(min(x1, right) * sx + dx))
                a, b = min(a, b), max(a, b)
                if b > a:
                    painter.fillRect(QRect(a, px_top, b - a, px_bottom - px_top), brush)
                painter.setPen(pen)
                for edge in (x0, x1):
                    if left <= edge <= right:
                        e = int(round(edge * sx + dx))
                        painter.drawLine(e, px_top, e, px_bottom)
            if lines:
                painter.setPen(self.grid_pen)
                painter.drawLines(lines)
        finally:
            painter.restore()
