"""The simulated run as a charger's display would draw it, only better: voltage,
current and temperature stacked over one h:mm time axis, with the phases as shaded
bands labelled by what ended them, and the heat-sink pauses as grey bands over them
(the look is ``ui/stacked_plot.py``'s)."""
from __future__ import annotations

import numpy as np
import pyqtgraph as pg
from PySide6.QtCore import Signal

from ..plot_cursor import CursorReadout
from ..stacked_plot import (BAND_ALPHA, BATTERY_T_PEN, CURRENT_FILL, CURRENT_PEN, HEATSINK_T_PEN, LABEL_COLOR,
                            VOLTAGE_PEN, WARNING_COLOR, StackedPlot, band_label, band_rgb, band_warns)
from ..timefmt import hmmss

SELECTED_ALPHA = 80
PAUSE_BRUSH = (90, 90, 90, 70)


class ChargePlot(StackedPlot):
    phaseActivated = Signal(int)        # FAZE byte offset of a double-clicked band
    phaseClicked = Signal(int)          # row (phase run - 1) of a clicked band, -1 outside bands

    def __init__(self, parent=None):
        super().__init__("simPlot", "no simulation yet: Simulate (F5)", grid=True, parent=parent)
        self._t = np.zeros(0)
        self._v = np.zeros(0)
        self._data: dict[str, np.ndarray] = {}
        self._selected = -1
        self.bands: list[list[pg.LinearRegionItem]] = [[], [], []]     # per plot, one per phase
        self.pause_bands: list[list[pg.LinearRegionItem]] = [[], [], []]   # per plot, one per heat-sink pause
        self.curves = {
            "voltage": self._curve(self.vplot, VOLTAGE_PEN, "pack voltage"),
            "current": self._curve(self.iplot, CURRENT_PEN, "+ charge, − discharge",
                                   fillLevel=0.0, fillBrush=CURRENT_FILL),
            "temp": self._curve(self.tplot, BATTERY_T_PEN, "battery"),
            "heatsink": self._curve(self.tplot, HEATSINK_T_PEN, "heat sink"),
        }
        self.placeholder.setPos(0.5, 0.5)
        for legend in self.legends.values():
            legend.setVisible(False)                # until there is something to explain
        for plot in (self.iplot, self.tplot):      # their y auto-range is applied lazily, before painting
            plot.sigYRangeChanged.connect(self._place_legends)
        self.vplot.sigXRangeChanged.connect(self._view_changed)
        self.vplot.vb.sigResized.connect(self._view_changed)
        self.scene().sigMouseClicked.connect(self._scene_clicked)
        self.readout = CursorReadout(self, lambda: (self._t, self._data))

    # -- construction ------------------------------------------------------------------------
    def _curve(self, plot: pg.PlotItem, pen, name: str, **kw) -> pg.PlotDataItem:
        self.legends[plot].add(name, pen.color().name())
        curve = plot.plot([], [], pen=pen, name=name, antialias=False, skipFiniteCheck=True, **kw)
        curve.setClipToView(True)
        curve.setDownsampling(auto=True, method="peak")
        return curve

    # -- data --------------------------------------------------------------------------------
    def show_result(self, result) -> None:
        """Draw a SimResult: samples, phase bands, labels, the per-cell axis."""
        data = result.log.arrays()
        t = data["time_s"]
        self._t, self._v, self._data = t, data["voltage_v"], data
        self.curves["voltage"].setData(t, data["voltage_v"])
        self.curves["current"].setData(t, data["current_a"])
        self.curves["temp"].setData(t, data["temp_c"])
        self.curves["heatsink"].setData(t, data["heatsink_c"])
        self.set_sensor(result.interpreter.params.sensor)
        self.set_series_count(result.series or 1)
        self.placeholder.setVisible(len(t) == 0)
        for legend in self.legends.values():
            legend.setVisible(len(t) > 0)
        self._set_bands(list(result.phases))
        self._set_pauses(list(result.phases))
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
            label = self._new_label()
            label.setText(band_label(p))
            label.setColor(WARNING_COLOR if band_warns(p) else LABEL_COLOR)

    def _set_pauses(self, phases: list) -> None:
        for plot, bands in zip(self.plots, self.pause_bands):
            for band in bands:
                plot.removeItem(band)
            bands.clear()
        for p in phases:
            for start, end in p.pauses:
                tip = f"heat-sink pause {hmmss(start)}–{hmmss(end)}: the power stage was too hot (Tc)"
                for plot, bands in zip(self.plots, self.pause_bands):
                    band = pg.LinearRegionItem((start, max(end, start)), orientation="vertical", movable=False,
                                               brush=pg.mkBrush(*PAUSE_BRUSH), pen=pg.mkPen(None))
                    band.setZValue(-15)
                    band.setToolTip(tip)
                    plot.addItem(band, ignoreBounds=True)
                    bands.append(band)

    @staticmethod
    def _band_brush(p, alpha: int):
        r, g, b = band_rgb(p.section)
        return pg.mkBrush(r, g, b, alpha)

    @staticmethod
    def _band_pen(p):
        r, g, b = band_rgb(p.section)
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
        self._fit_voltage(self._t, self._v)
        self._place_placeholder()
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
