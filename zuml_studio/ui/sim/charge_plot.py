"""The simulated run as a charger's display would draw it, only better: voltage,
current and temperature stacked over one h:mm time axis, with the phases as shaded
bands labelled by what ended them, and the heat-sink pauses as grey bands over them
(the look is ``ui/plots/stacked_plot.py``'s).

The GUI thread's share stays small whatever the run's length: the worker hands over the
run with its arrays and min/max envelopes ready (``plot_data.py``), each view is drawn
from about two points per pixel of them, and all bands of a plot are one item
(``plot_backdrop.py``)."""
from __future__ import annotations

import math
from functools import partial
from typing import Callable

import numpy as np
import pyqtgraph as pg
from PySide6.QtCore import Qt, QTimer, Signal
from PySide6.QtGui import QPainter, QPicture

from ...i18n import _
from ...logs import gaps
from ..plots.cell_curves import CellCurves
from ..plots.plot_backdrop import BackdropItem
from ..plots.plot_cursor import CursorReadout
from ..plots.stacked_plot import StackedPlot, band_label, band_warns, curve_pen
from ..base.timefmt import hmmss
from ..plots.plot_data import CLOCK, CURVES, HIGHEST, LOWEST, PlotData

LABELS_PER_TURN = 8


class ChargePlot(StackedPlot):
    phaseActivated = Signal(int)        # FAZE byte offset of a Ctrl+double-clicked band
    # A min and a max per pixel column is a line, not an overdrawn band: it keeps its full width.
    DENSE_PER_PX = 2.5
    phaseClicked = Signal(int)          # row (phase run - 1) of a clicked band, -1 outside bands

    def __init__(self, parent=None):
        super().__init__("simPlot", _("no simulation yet: Simulate (F5)"), grid=False, parent=parent)
        self._t = np.zeros(0)
        self._v = np.zeros(0)
        self._run: PlotData | None = None
        self._selected = -1
        self._strengths: list[int] = []    # per band: which of the two alternating strengths
        self.level = 0                  # the envelope level drawn (0: the samples themselves)
        self._batch = False             # show_result is moving the view: no drawing until it is done
        self.curves = {
            "voltage": self._curve(self.vplot, "voltage", _("pack voltage")),
            "current": self._curve(self.iplot, "current", _("+ charge, − discharge")),
            "temp": self._curve(self.tplot, "temp", _("battery")),
            "heatsink": self._curve(self.tplot, "heatsink", _("heat sink")),
        }
        self.cells = CellCurves(self)
        self._cell_bounds: tuple = ()      # (t, y) of the lowest and the highest cell as drawn: the y range takes them
        self.band_items = [BackdropItem(plot, self.time_axis, self.colours.plot.grid) for plot in self.plots]
        self.pause_items = [BackdropItem(plot, self.time_axis) for plot in self.plots]
        for plot, item, pauses in zip(self.plots, self.band_items, self.pause_items):
            plot.addItem(item, ignoreBounds=True)
            pauses.setZValue(-15)
            plot.addItem(pauses, ignoreBounds=True)
            plot.disableAutoRange(axis="x")          # the view is set here; the curves follow it
        self.placeholder.setPos(0.5, 0.5)
        for legend in self.legends.values():
            legend.setVisible(False)                # until there is something to explain
        for plot in (self.iplot, self.tplot):      # their y auto-range is applied lazily, before painting
            plot.sigYRangeChanged.connect(self._place_legends)
        self.vplot.sigXRangeChanged.connect(self._view_changed)
        self.vplot.vb.sigResized.connect(self._view_changed)
        self.scene().sigMouseClicked.connect(self._scene_clicked)
        self.readout = CursorReadout(self, lambda: (self._t, self.data))

    # -- construction ------------------------------------------------------------------------
    def _curve(self, plot: pg.PlotItem, quantity: str, name: str, **kw) -> pg.PlotDataItem:
        self.legends[plot].add(name, self.hue(quantity))
        curve = plot.plot([], [], pen=curve_pen(self.hue(quantity)), name=name, antialias=False, skipFiniteCheck=True,
                          **kw)
        # The envelope hands over the view's points already clipped and decimated.
        curve.setClipToView(False)
        curve.setDownsampling(ds=1, auto=False)
        return curve

    # -- data --------------------------------------------------------------------------------
    @property
    def data(self) -> dict[str, np.ndarray]:
        """The shown run's sample columns (empty before any)."""
        return self._run.data if self._run is not None else {}

    def show_result(self, run: PlotData) -> None:
        """Draw a run prepared by ``plot_data.prepare_plot``: samples, phase bands, labels, the per-cell axis."""
        self.show_run(run)
        self.show_bands()

    def show_run(self, run: PlotData, *, place: bool = True) -> None:
        """The run's curves, cells and view; its phases' bands and labels stay those of the run before
        until ``show_bands`` (the panel gives each its own turn of the event loop). ``place`` False
        leaves the curves' display data and the overlays to ``place_view``, a turn of its own."""
        result = run.result
        t = run.data[CLOCK]
        self._run, self._t, self._v = run, t, run.data["voltage_v"]
        self.set_sensor(result.interpreter.params.sensor)
        self.set_series_count(result.series or 1)
        self.cells.set_layout(run.cell_curves, result.series or 1)
        self._cell_bounds = tuple((t, run.data[c] * self.cells.scale) for c in (LOWEST, HIGHEST)) if run.cells else ()
        self.placeholder.setVisible(len(t) == 0)
        for legend in self.legends.values():
            legend.setVisible(len(t) > 0)
        end = max(float(t[-1]) if len(t) else 0.0, 60.0)
        self._batch = True          # the limits and the range each move the view: draw it once, after both
        try:
            for plot in self.plots:
                plot.setLimits(xMin=-0.05 * end, xMax=end * 1.05, minXRange=min(30.0, end / 2))
            self.tplot.setXRange(0.0, end, padding=0.01)
        finally:
            self._batch = False
        if place:
            self._view_changed()

    def place_view(self) -> None:
        """The curves' display data for the view, the voltage's y range and the labels and legends
        (``show_run``'s last part)."""
        self._view_changed()

    def place_steps(self) -> list[Callable[[], None]]:
        """``place_view`` in two steps (the panel gives each a turn of the event loop of its own): the
        curves' display data, then the voltage's range, the labels and the legends."""
        return [self._set_view_curves, self._place_overlays]

    def _set_view_curves(self) -> None:
        self._set_curves()
        self._thin_dense_curves()

    def _place_overlays(self) -> None:
        self._fit_voltage(self._t, self._v, *self._cell_bounds)
        self._place_placeholder()
        self._place_labels()
        self._place_legends()

    def show_bands(self) -> None:
        """The shown run's phase bands, heat-sink pauses and labels."""
        for step in self.band_steps():
            step()

    def band_steps(self) -> list[Callable[[], None]]:
        """``show_bands`` in two steps: the bands and labels, then the pauses (and the voltage's y
        range, which keeps room for the labels, or no more)."""
        phases = list(self._run.result.phases) if self._run is not None else []
        had_bands = bool(self._phases)

        def pauses() -> None:
            self._set_pauses(phases)
            if bool(phases) != had_bands:
                self._view_changed()
        return [partial(self._set_bands, phases), pauses]

    def paint_steps(self) -> list[Callable[[], None]]:
        """What the next paint would do first, as steps of 1-3 ms each (a plot's whole share took up
        to 6 ms): each plot's y range, which pyqtgraph fits lazily, then each of its axes' tick
        pictures (half of a new run's paint)."""
        steps: list[Callable[[], None]] = []
        for plot in self.plots:
            steps.append(plot.vb.prepareForPaint)
            steps += [partial(self._prepare_axis_paint, plot, name) for name in ("left", "right", "bottom")]
        return steps

    @staticmethod
    def _prepare_axis_paint(plot, name: str) -> None:
        axis = plot.getAxis(name)
        if axis.isVisible() and axis.picture is None:
            scratch = QPicture()
            painter = QPainter(scratch)
            try:
                axis.paint(painter, None, None)     # makes axis.picture, which the paint then replays
            finally:
                painter.end()

    def clear_run(self) -> None:
        """No run: empty curves, no bands or labels, the placeholder (another macro was opened).
        Not ``clear``: pyqtgraph's GraphicsLayoutWidget sets that on each instance (the layout's
        own clear, which removes the plots themselves)."""
        self._run, self._t, self._v = None, np.zeros(0), np.zeros(0)
        for curve in self.curves.values():
            curve.setData([], [])
        self.cells.clear()
        self._cell_bounds = ()
        self._set_current_fill(np.zeros(0), np.zeros(0), False)
        self._set_bands([])
        self._set_pauses([])
        self.placeholder.setVisible(True)
        self._place_placeholder()
        for legend in self.legends.values():
            legend.setVisible(False)

    def _set_curves(self) -> None:
        if self._run is None:
            return
        (x0, x1), width = self.vplot.vb.viewRange()[0], self.vplot.vb.width()
        pixels = max(100, int(width))
        self.level, x, ys = self._run.envelope.view(x0, x1, bins=pixels)
        for name, column in CURVES.items():
            # The envelope's level has one to four bins a pixel: down to a min and a max per pixel
            # column (the log viewer's), which is all a pixel shows. A run samples every tick: no gaps.
            self.curves[name].setData(*gaps.envelope(x, ys[column], x0, x1, pixels, math.inf))
        self.cells.set_data(x, ys)          # the envelope's level as it is: eight cells cost too much to thin
        self._set_current_fill(x, ys["current_a"], self.level > 0)

    def _set_bands(self, phases: list) -> None:
        """One item per plot draws every band; the labels are kept and reused."""
        while len(self.labels) > len(phases):
            self.vplot.removeItem(self.labels.pop())
        self._phases = phases
        self._selected = -1
        parity = {"charge": 0, "discharge": 0}
        self._strengths = []
        for p in phases:
            self._strengths.append(parity.get(p.section, 0) % 2)
            parity[p.section] = parity.get(p.section, 0) + 1
        self._draw_bands()
        self._add_labels()

    def _add_labels(self) -> None:
        """Labels for the phases, at most LABELS_PER_TURN new ones per turn of the event loop
        (a label costs about a millisecond to make; a long training has hundreds of phases)."""
        for _ in range(min(LABELS_PER_TURN, len(self._phases) - len(self.labels))):
            self._new_label()
        self._colour_labels()
        self._place_labels()
        if len(self.labels) < len(self._phases):
            QTimer.singleShot(0, self, self._add_labels)

    def _colour_labels(self) -> None:
        for p, label in zip(self._phases, self.labels):
            label.setColor(self.label_colour(band_warns(p)))

    def _set_pauses(self, phases: list) -> None:
        """The heat-sink pauses, a translucent grey over the phase bands: one more item per plot."""
        spans, tips = [], []
        brush = pg.mkBrush(*self.colours.plot.pause)
        for p in phases:
            for start, end in p.pauses:
                spans.append((start, max(end, start), brush, pg.mkPen(None)))
                tips.append(_("heat-sink pause {start}–{end}: the power stage was too hot (Tc)").format(
                    start=hmmss(start), end=hmmss(end)))
        for item in self.pause_items:
            item.set_bands(spans, tips)

    def _draw_bands(self) -> None:
        spans, tips = [], []
        look = self.colours.plot
        for row, (p, strength) in enumerate(zip(self._phases, self._strengths)):
            end = p.end_s if p.reason else max(p.end_s, p.start_s)
            alpha = look.selected_alpha if row == self._selected else look.band_alpha[strength]
            spans.append((p.start_s, end, *self.band_looks(p.section, alpha)))
            tips.append(band_label(p) + "\n" + _("Ctrl+double-click: show the FAZE in the editor"))
        for item in self.band_items:
            item.set_bands(spans, tips)

    def highlight(self, row: int) -> None:
        """Make one phase's bands stand out (the table's selection); -1 for none."""
        if row == self._selected:
            return
        self._selected = row
        self._draw_bands()

    def _recolour(self) -> None:
        self._recolour_curves()
        self.cells.recolour()
        for item in self.band_items:
            item.set_grid_colour(self.colours.plot.grid)
        self._draw_bands()
        self._set_pauses(self._phases)
        self._colour_labels()

    # -- view --------------------------------------------------------------------------------
    def _view_changed(self, *_) -> None:
        if self._batch:
            return
        self._set_view_curves()
        self._place_overlays()

    def _display(self, name: str) -> tuple[np.ndarray, np.ndarray]:
        x, y = self.curves[name].getData()
        return (np.zeros(0), np.zeros(0)) if x is None else (x, y)

    def _place_legends(self, *_) -> None:
        if not len(self._t):
            return
        room = self._label_height_px() if self._phases else 0.0
        self.legends[self.vplot].place([self._display("voltage"), *self.cells.displayed()], reserved_top_px=room)
        self.legends[self.iplot].place([self._display("current")])
        self.legends[self.tplot].place([self._display("temp"), self._display("heatsink")])

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
                if ev.double():       # a plain double-click maximises the plot (ui/window/plot_focus.py)
                    if row >= 0 and ev.modifiers() & Qt.KeyboardModifier.ControlModifier:
                        self.phaseActivated.emit(self._phases[row].offset)
                else:
                    self.phaseClicked.emit(row)
                return

