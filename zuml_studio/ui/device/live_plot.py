"""The live plot of a charger's telemetry: pack voltage, signed current, battery and heat-sink
temperature stacked over one h:mm time axis, with the phases as bands from the device's
EVENT frames, in the simulator plot's look (``ui/plots/stacked_plot.py``).

Data path (ide.md §3, §7): the client's reader thread calls ``LiveSeries.add_telemetry`` /
``add_event`` (no Qt there: numpy buffers under a lock); a QTimer at about 30 Hz takes
what is new, folds it into the min/max envelopes (``envelope.py``) and redraws only when
something changed. The whole session is kept (in fixed-size chunks of float32 measurements, with
envelopes only from 64 samples a bin up: about 25 bytes a sample, ~110 MB for a day at 50 Hz) and every view
of it is drawn from about two points per pixel: the samples themselves when few are in
view, else their envelope (clip-to-view and peak downsampling, done once per sample rather
than once per frame), antialiasing off.

Per-cell voltages (``Telemetry.cells_v``, where the charger measures them at the balance port)
go to a second table, made at the first frame that has any and row for row with the first from
then on, so a session without them costs nothing; they are drawn as the simulator draws a pack's
cells (``ui/plots/cell_curves.py``).

The x axis is the macro's clock. Telemetry is plotted while a macro runs; a new run (its
clock starts again) continues after the previous one, so the session stays one
time line. Idle frames are not plotted (their clock stands still); they update the
readings only.
"""
from __future__ import annotations

import math
import threading
import time
from dataclasses import dataclass, replace

import numpy as np
import pyqtgraph as pg
from PySide6.QtCore import Qt, QTimer, Signal

from ...i18n import _
from ...logs import gaps
from ...sim.interpreter import PhaseResult
from ..plots.cell_curves import CellCurves
from ..plots.plot_backdrop import BackdropItem
from ..plots.plot_data import cell_curves
from ..plots.stacked_plot import StackedPlot, band_label, curve_pen
from ..plots.envelope import FANOUT, Envelope
from ..plots.growing_buffer import GrowingBuffer

COLUMNS = ("t", "voltage", "current", "temp", "heatsink")
REDRAW_MS = 33                     # ~30 Hz
LEGEND_MS = 500
MAX_REDRAW_SHARE = 0.35            # a slow machine redraws less often rather than freeze
DEFAULT_FOLLOW_MIN = 30
MIN_VIEW_S = 60.0
PERIOD_SAMPLES = 4097               # the first samples give the session's sample period
CELL_ABSENT_V = 0.05               # a balance-port reading below this is no cell there (chargers send 0)
PROTECTION = "protection: "        # the prefix of a protection's end reason (docs/protocol.md)


@dataclass
class LivePhase(PhaseResult):
    """One phase as the events tell it, in the simulator's terms (its end reason, what went in and
    out, the pack at the end, pauses, how long the balancer bled each cell), so the simulator's
    phase table and warnings read it as they read a simulated phase. The measurements come from the
    telemetry frames that arrive while it is open; ``end_s`` grows while it runs."""
    closed: bool = False
    v_end: float = math.nan            # no frame yet
    temp_end: float = math.nan
    base_in: float = 0.0               # the run's charge counters when the phase started
    base_out: float = 0.0
    last_x: float | None = None        # x of the phase's newest frame (for the balancer's time)

    @property
    def by_default(self) -> bool:
        # A charger's protection ends a phase too, and the user must look at it as at a default.
        return super().by_default or self.reason.startswith(PROTECTION)

    def measure(self, x: float, tel) -> None:
        """A telemetry frame of this phase."""
        self.mah_in, self.mah_out = max(0.0, tel.mah_in - self.base_in), max(0.0, tel.mah_out - self.base_out)
        self.v_end = tel.voltage_v
        self.end_s = max(self.end_s, x)     # a running phase's duration so far (its end event sets the end)
        self.temp_end = math.nan if tel.temp_c is None else tel.temp_c
        self.run = tel.run or self.run
        self.cycle_pass = tel.cycle
        cells = tuple(getattr(tel, "cells_v", ()) or ())
        if cells:
            self.cells_end = cells
        mask = getattr(tel, "balance_mask", 0)
        if self.last_x is not None and mask and cells:
            dt = max(0.0, x - self.last_x)
            bled = list(self.bled_s) + [0.0] * (len(cells) - len(self.bled_s))
            for k in range(len(cells)):
                if mask >> k & 1:
                    bled[k] += dt
            self.bled_s = tuple(bled)
        self.last_x = x


class LiveSeries:
    """The session's telemetry and phases; filled on the reader thread, read by the GUI."""

    def __init__(self):
        # The clock in float64 (bisected, exact over days); the measurements in float32: half
        # the memory, and the peak downsampling of a million values runs a third faster.
        self.buffer = GrowingBuffer(COLUMNS, dtype={name: np.float32 for name in COLUMNS[1:]})
        self.lock = threading.Lock()       # phases, events, readings
        self.phases: list[LivePhase] = []
        self.phase_version = 0
        self.events: list = []             # every DeviceEvent, with its x
        self.last_telemetry = None         # the newest frame (plotted or not)
        self.frames = 0                    # telemetry frames seen
        self._offset = 0.0                 # x of the current run's time 0
        self._run_t: float | None = None   # the current run's last clock reading
        self._last_x = 0.0
        self.cells: GrowingBuffer | None = None    # t and cell1_v … cellN_v, from row ``cells_from`` of ``buffer``
        self.cells_from = 0
        self.cell_count = 0                # cells that gave a reading (a 6-slot balance port reads 0 V in the rest)
        self.end_reason = ""               # the finish event's: how the macro ended ("" while it runs)
        self._counters = (0.0, 0.0)        # the run's charge in and out at its newest frame
        self._ended: LivePhase | None = None   # the last phase of a finished run, until the next frame

    # -- reader thread ------------------------------------------------------------------------
    def add_telemetry(self, tel) -> None:
        with self.lock:
            self.last_telemetry = tel
            self.frames += 1
            if self._ended is not None:
                # The frame after the finish has the run's last counters (the last frame of the phase
                # came up to a frame period before its end).
                self._ended.mah_in = max(self._ended.mah_in, tel.mah_in - self._ended.base_in)
                self._ended.mah_out = max(self._ended.mah_out, tel.mah_out - self._ended.base_out)
                self._ended = None
            if not tel.running:
                return
            t = float(tel.time_s)
            if self._run_t is not None and t < self._run_t - 1e-6:      # a new run: its clock starts again
                self._offset = self._last_x
            self._run_t = t
            x = self._offset + t
            self._last_x = max(self._last_x, x)
            self.buffer.append((x, tel.voltage_v, tel.current_a,
                                math.nan if tel.temp_c is None else tel.temp_c,
                                math.nan if tel.heatsink_c is None else tel.heatsink_c))
            self._add_cells(x, tuple(getattr(tel, "cells_v", ()) or ()))
            self._counters = (tel.mah_in, tel.mah_out)
            if self.phases and not self.phases[-1].closed:
                self.phases[-1].measure(x, tel)     # the bands do not change: no new phase_version

    def _add_cells(self, x: float, volts: tuple[float, ...]) -> None:
        present = [k for k, v in enumerate(volts, 1) if v is not None and v > CELL_ABSENT_V]
        if self.cells is None:
            if not present:
                return
            names = tuple(f"cell{k}_v" for k in range(1, len(volts) + 1))
            self.cells = GrowingBuffer(("t",) + names, dtype={name: np.float32 for name in names})
            self.cells_from = len(self.buffer) - 1
        width = len(self.cells.names) - 1
        row = [v if v is not None and v > CELL_ABSENT_V else math.nan for v in volts[:width]]
        self.cells.append((x, *row, *[math.nan] * (width - len(row))))
        if present:
            self.cell_count = max(self.cell_count, min(present[-1], width))

    def add_event(self, ev) -> None:
        with self.lock:
            if ev.number == 0 and self._run_t is not None:   # the first event of a new run
                self._offset = self._last_x
                self._run_t = 0.0
                self._counters = (0.0, 0.0)
            elif self._run_t is None:
                self._run_t = 0.0
            x = self._offset + float(ev.time_s)
            self.events.append((x, ev))
            if ev.kind == "phase_start":
                self._close_open(x, "")
                self.phases.append(LivePhase(
                    section=ev.section, index=ev.index, repetition=ev.repetition, cycle_pass=0, offset=ev.offset,
                    start_s=x, end_s=x, run=len(self.phases) + 1, base_in=self._counters[0],
                    base_out=self._counters[1]))
            elif ev.kind == "phase_end":
                for p in reversed(self.phases):
                    if not p.closed and p.section == ev.section and p.index == ev.index:
                        if p.last_x is None and self.last_telemetry is not None and self.last_telemetry.running:
                            p.measure(x, self.last_telemetry)      # a phase shorter than a frame: the pack now
                        self._end_pause(p, x)
                        p.end_s, p.reason, p.closed = max(x, p.start_s), ev.detail or _("ended"), True
                        break
            elif ev.kind == "finish":
                self.end_reason = ev.detail or _("finished")
                self._close_open(x, self.end_reason)
                self._ended = self.phases[-1] if self.phases else None
            elif ev.kind in ("pause", "resume") and self.phases and not self.phases[-1].closed:
                if ev.kind == "pause":
                    self.phases[-1].pauses.append([x, x])
                else:
                    self._end_pause(self.phases[-1], x)
            else:
                return
            self.phase_version += 1

    def _close_open(self, x: float, reason: str) -> None:
        for p in self.phases:
            if not p.closed:
                self._end_pause(p, x)
                p.end_s, p.closed = max(x, p.start_s), True
                p.reason = p.reason or reason

    @staticmethod
    def _end_pause(p: LivePhase, x: float) -> None:
        if p.pauses and p.pauses[-1][1] <= p.pauses[-1][0]:
            p.pauses[-1][1] = x

    # -- GUI thread ---------------------------------------------------------------------------
    def phases_copy(self) -> tuple[int, list[LivePhase]]:
        with self.lock:
            return self.phase_version, [replace(p, pauses=[list(q) for q in p.pauses]) for p in self.phases]

    def last_x(self) -> float:
        with self.lock:
            return self._last_x

    def cell_table(self) -> tuple[GrowingBuffer | None, int, int]:
        """The cells' table, the row of ``buffer`` its first row stands beside, and the cells seen."""
        with self.lock:
            return self.cells, self.cells_from, self.cell_count

    def clear(self) -> None:
        with self.lock:
            self.phases.clear()
            self.events.clear()
            self.phase_version += 1
            self._offset = 0.0
            self._run_t = None
            self._last_x = 0.0
            self.buffer.clear()
            self.cells, self.cells_from, self.cell_count = None, 0, 0
            self.end_reason, self._counters, self._ended = "", (0.0, 0.0), None

    def __len__(self) -> int:
        return len(self.buffer)


class LivePlot(StackedPlot):
    """Three x-linked plots (V, I, T) of a ``LiveSeries``, redrawn by a timer."""
    pointsAdded = Signal(int)           # points plotted so far; at most once per redraw
    followChanged = Signal(bool)        # the user zoomed or panned: following stops
    phaseActivated = Signal(int)        # FAZE byte offset of a Ctrl+double-clicked band

    def __init__(self, series: LiveSeries | None = None, parent=None):
        super().__init__("livePlot", "", grid=False, parent=parent)
        self.series = series if series is not None else LiveSeries()
        self._follow = True
        self.follow_s = DEFAULT_FOLLOW_MIN * 60.0
        self._n = 0                         # points taken from the series
        self.envelope = Envelope(COLUMNS[1:])
        self.level = 0                      # the envelope level drawn (0: the samples themselves)
        self.cells = CellCurves(self)
        self._cell_table: GrowingBuffer | None = None      # the series' cells table taken in, and its envelope
        self._cell_envelope: Envelope | None = None
        self._cell_version = -1
        self._cell_count = 0
        self._period = 0.0                  # the typical step between samples (gaps.sample_period)
        self._version = -1
        self._phase_version = -1
        self._phases: list[LivePhase] = []
        self._setting_range = False
        self._last_cost_ms = 0.0
        self._paint_ms = 0.0
        self._view_moves = 0
        self.paints = 0
        # Legends move at most twice a second (each move scans the visible samples); the
        # last view always gets its placement, even when no frame follows.
        self._legend_timer = QTimer(self, singleShot=True, interval=LEGEND_MS)
        self._legend_timer.timeout.connect(self._place_legends)
        self.redraws = 0
        self.curves = {
            "voltage": self._curve(self.vplot, "voltage", _("pack voltage")),
            "current": self._curve(self.iplot, "current", _("+ charge, − discharge")),
            "temp": self._curve(self.tplot, "temp", _("battery")),
            "heatsink": self._curve(self.tplot, "heatsink", _("heat sink")),
        }
        self.band_items = [BackdropItem(plot, self.time_axis, self.colours.plot.grid) for plot in self.plots]
        for plot, item in zip(self.plots, self.band_items):
            plot.addItem(item, ignoreBounds=True)
        self.set_placeholder(_("not connected: pick a port and Connect"))
        for legend in self.legends.values():
            legend.setVisible(False)
        for plot in self.plots:
            plot.disableAutoRange(axis="x")          # clip-to-view needs a fixed x range
        self.tplot.setXRange(0.0, MIN_VIEW_S * 10, padding=0)
        self.vplot.sigXRangeChanged.connect(self._view_changed)
        self.vplot.vb.sigResized.connect(self._view_changed)
        for plot in self.plots:
            # The y ranges follow the data after a redraw: the legends are placed again then.
            plot.sigYRangeChanged.connect(self._legends_later)
        for plot in self.plots:
            plot.vb.sigRangeChangedManually.connect(self._user_moved)
        self.scene().sigMouseClicked.connect(self._scene_clicked)

        self.timer = QTimer(self, interval=REDRAW_MS)
        self.timer.timeout.connect(self.refresh)

    # -- construction ------------------------------------------------------------------------
    def _curve(self, plot: pg.PlotItem, quantity: str, name: str, **kw) -> pg.PlotDataItem:
        # connect="finite": a NaN (no sensor, or a gap in the session) breaks the line.
        self.legends[plot].add(name, self.hue(quantity))
        curve = pg.PlotDataItem([], [], pen=curve_pen(self.hue(quantity)), name=name, antialias=False,
                                connect="finite", **kw)
        plot.addItem(curve)
        # The envelope hands over the view's points already clipped and decimated.
        curve.setClipToView(False)
        curve.setDownsampling(ds=1, auto=False)
        return curve

    # -- options -----------------------------------------------------------------------------
    def start(self) -> None:
        self.timer.start()

    def stop(self) -> None:
        self.timer.stop()

    @property
    def follow(self) -> bool:
        return self._follow

    def set_follow(self, on: bool, minutes: float | None = None) -> None:
        """Keep the last ``minutes`` in view (on), or leave the view where it is (off)."""
        if minutes is not None:
            self.follow_s = max(1.0, float(minutes)) * 60.0
        changed = bool(on) != self._follow
        self._follow = bool(on)
        if self._follow:
            self._apply_follow()
        if changed:
            self.followChanged.emit(self._follow)

    def show_all(self) -> None:
        """The whole session in view (follow stays as it is)."""
        lo, hi = self._extent()
        if hi is not None:
            self._set_x(lo, max(hi, lo + MIN_VIEW_S))

    def _extent(self) -> tuple[float, float | None]:
        """The session's first and last x: samples and phase bands (a band starts at its event,
        often before the first sample of the phase)."""
        starts = [p.start_s for p in self._phases]
        if not self._n:
            return (min(starts), max(p.end_s for p in self._phases)) if starts else (0.0, None)
        x = self.series.buffer.column("t")
        lo, hi = float(x[0]), float(x[-1])
        if starts:
            lo = min(lo, min(starts))
        return lo, hi

    def set_placeholder(self, text: str) -> None:
        self.placeholder.setText(text)
        self.placeholder.setVisible(bool(text) and self._n == 0)
        self._place_placeholder()

    def set_series(self, series: LiveSeries) -> None:
        """Draw another session (a new run, or an earlier one kept), left as it is."""
        self.series = series
        self._redraw_from_scratch()
        self.refresh()

    def clear_session(self) -> None:
        """Forget the session's data and bands. Not ``clear``: pyqtgraph's GraphicsLayoutWidget sets
        that on each instance (the layout's own, which took the three plots away)."""
        self.series.clear()
        self._redraw_from_scratch()

    def _redraw_from_scratch(self) -> None:
        self.envelope.clear()
        self._cell_table, self._cell_envelope, self._cell_version, self._cell_count = None, None, -1, 0
        self.cells.clear()
        self._period = 0.0
        for curve in self.curves.values():
            curve.setData([], [])
        self._n = 0
        self._version = -1
        self._set_bands([])
        self._phase_version = -1
        for legend in self.legends.values():
            legend.setVisible(False)
        self.placeholder.setVisible(bool(self.placeholder.toPlainText()))
        self.tplot.setXRange(0.0, MIN_VIEW_S * 10, padding=0)

    @property
    def points(self) -> int:
        return self._n

    # -- redraw ------------------------------------------------------------------------------
    def refresh(self) -> bool:
        """Take what is new from the series and redraw; True if anything changed."""
        clock = time.perf_counter()
        buf = self.series.buffer
        changed = hidden = False
        if buf.version != self._version:
            self._version = buf.version
            n, cols = buf.snapshot()
            if n != self._n or n == 0:
                first = self._n == 0 and n > 0
                # With follow off, samples that land right of the view change nothing on the
                # screen: they are drawn when the view moves there.
                hidden = (not self._follow and 0 < self._n < n
                          and float(cols["t"][self._n]) > self.vplot.vb.viewRange()[0][1])
                self.envelope.update(n, cols)
                if self._n < PERIOD_SAMPLES:         # the session's sample period, from its start
                    self._period = gaps.sample_period(np.asarray(cols["t"][:min(n, PERIOD_SAMPLES)]))
                self._n = n
                changed = True
                if first:
                    self.placeholder.setVisible(False)
                    for legend in self.legends.values():
                        legend.setVisible(True)
        changed = self._take_cells() or changed
        version, phases = self.series.phases_copy()
        last_x = float(buf.column("t")[-1]) if self._n else 0.0
        if version != self._phase_version:
            self._phase_version = version
            self._set_bands(phases)
            changed = True
        if changed:
            self._grow_open_bands(last_x)
            moves = self._view_moves
            if self._follow:
                self._apply_follow()            # a new range redraws the view (_view_changed)
            if moves == self._view_moves and not hidden:
                self._redraw_view()
            self.pointsAdded.emit(self._n)
            self.redraws += 1
        cost = (time.perf_counter() - clock) * 1000.0 + (self._paint_ms if changed else 0.0)
        self._last_cost_ms = cost
        # A machine that needs long for a redraw redraws less often instead of freezing.
        wanted = int(max(REDRAW_MS, cost / MAX_REDRAW_SHARE))
        if self.timer.interval() != wanted and abs(self.timer.interval() - wanted) > 5:
            self.timer.setInterval(wanted)
        return changed

    def _take_cells(self) -> bool:
        """What is new in the series' cells table, into their envelope; True if anything was."""
        table, _first_row, count = self.series.cell_table()
        if table is None or (table is self._cell_table and table.version == self._cell_version
                             and count == self._cell_count):
            return False
        if table is not self._cell_table:
            self._cell_table, self._cell_envelope = table, Envelope(table.names[1:])
        self._cell_version, self._cell_count = table.version, count
        n, cols = table.snapshot()
        self._cell_envelope.update(n, cols)
        if count > 1 and self.series_cells == 1:     # a run started without its cell count: the charger's
            self.set_series_count(count)
        return True

    def _set_curves(self) -> None:
        """Hand the curves the view's points: the samples, or their envelope when there are
        more than two per pixel."""
        (x0, x1), width = self.vplot.vb.viewRange()[0], self.vplot.vb.width()
        self.level, x, ys = self.envelope.view(x0, x1, bins=max(100, int(width)))
        # Bins of a level hold FANOUT ** level samples: their starts lie that many periods apart.
        gap_s = self.gap_s + (FANOUT ** self.level if self.level else 0) * self._period
        broken = gaps.broken(x, *(ys[name] for name in COLUMNS[1:]), threshold=gap_s)
        for name, y in zip(COLUMNS[1:], broken[1:]):
            self.curves[name].setData(broken[0], y)
        self._set_current_fill(x, ys["current"], self.level > 0, gap_s)
        self._set_cell_curves(x0, x1, max(100, int(width)))

    def _set_cell_curves(self, x0: float, x1: float, bins: int) -> None:
        """The cells as the simulator draws them (``cell_curves``), broken at the session's gaps."""
        if self._cell_envelope is None or self._cell_count < 2:
            return
        level, x, ys = self._cell_envelope.view(x0, x1, bins=bins)
        columns = self._cell_table.names[1:1 + self._cell_count]
        layout = cell_curves(ys, columns)
        gap_s = self.gap_s + (FANOUT ** level if level else 0) * self._period
        broken = gaps.broken(x, *(ys[c.column] for c in layout), threshold=gap_s)
        self.cells.set_layout(layout, self.series_cells)
        self.cells.set_data(broken[0], {c.column: y for c, y in zip(layout, broken[1:])})

    @property
    def gap_s(self) -> float:
        """A step between samples longer than this is a gap (``logs/gaps.py``); infinite before the
        session has a sample period."""
        return gaps.GAP_PERIODS * self._period if self._period > 0 else math.inf

    def _apply_follow(self) -> None:
        first, last = self._extent()
        if last is None:
            return
        span = max(MIN_VIEW_S, min(self.follow_s, last - first))
        hi = last + 0.03 * span
        lo = max(first, hi - self.follow_s) if last - first > self.follow_s else first
        if hi - lo < MIN_VIEW_S:
            hi = lo + MIN_VIEW_S
        self._set_x(lo, hi)

    def _set_x(self, lo: float, hi: float) -> None:
        self._setting_range = True
        try:
            self.tplot.setXRange(lo, hi, padding=0)
        finally:
            self._setting_range = False

    def _user_moved(self, *_) -> None:
        if self._setting_range:
            return
        if self._follow:
            self._follow = False
            self.followChanged.emit(False)

    # -- bands ------------------------------------------------------------------------------
    def _set_bands(self, phases: list[LivePhase]) -> None:
        """Phases only ever get added or closed (or all cleared): redo the spans, keep the
        labels that are there."""
        while len(self.labels) > len(phases):
            self.vplot.removeItem(self.labels.pop())
        spans = []
        parity: dict[str, int] = {}
        for k, p in enumerate(phases):
            alpha = self.colours.plot.band_alpha[parity.get(p.section, 0) % 2]
            parity[p.section] = parity.get(p.section, 0) + 1
            spans.append((p.start_s, p.end_s, *self.band_looks(p.section, alpha)))
            if k >= len(self.labels):
                self._new_label()
            self.labels[k].setColor(self.label_colour(p.by_default))
            self.labels[k].setToolTip(self._tip(p))
        for item in self.band_items:
            item.set_bands(spans)
        self._phases = phases

    def _recolour(self) -> None:
        self._recolour_curves()
        self.cells.recolour()
        for item in self.band_items:
            item.set_grid_colour(self.colours.plot.grid)
        self._set_bands(self._phases)

    @staticmethod
    def _tip(p: LivePhase) -> str:
        return band_label(p) if p.closed else _("{phase} (running)").format(phase=band_label(p))

    def _grow_open_bands(self, last_x: float) -> None:
        for k, p in enumerate(self._phases):
            if not p.closed and last_x > p.end_s:
                p.end_s = last_x
                for item in self.band_items:
                    item.set_end(k, last_x)

    def band_count(self) -> int:
        return len(self._phases)

    def phases(self) -> list[LivePhase]:
        return list(self._phases)

    # -- view --------------------------------------------------------------------------------
    def _view_changed(self, *_) -> None:
        """The x range or the size changed (the user, follow, a resize)."""
        self._view_moves += 1
        self._redraw_view()

    def _redraw_view(self) -> None:
        self._set_curves()
        self._thin_dense_curves()
        self._fit_live_voltage()
        self._place_labels()
        self._place_placeholder()
        self._legends_later()

    def _legends_later(self, *_) -> None:
        if not self._legend_timer.isActive():
            self._legend_timer.start()

    def _display(self, name: str) -> tuple[np.ndarray, np.ndarray]:
        x, y = self.curves[name].getData()
        if x is None:
            return np.zeros(0), np.zeros(0)
        return x, y

    def _place_legends(self) -> None:
        if not self._n:
            return
        room = self._label_height_px() if self._phases else 0.0
        self.legends[self.vplot].place([self._display("voltage"), *self.cells.displayed()], reserved_top_px=room)
        self.legends[self.iplot].place([self._display("current")])
        self.legends[self.tplot].place([self._display("temp"), self._display("heatsink")])

    def _fit_live_voltage(self) -> None:
        """The voltage axis follows the view's points, the cells' too (the envelope keeps every extreme)."""
        x, v = self._display("voltage")
        self._fit_voltage(x, v, *self.cells.displayed())

    def _label_texts(self, p: LivePhase) -> tuple[str, ...]:
        full = band_label(p) if p.closed else band_label(p, short=True) + " …"
        return full, band_label(p, short=True)

    # -- mouse -------------------------------------------------------------------------------
    def _scene_clicked(self, ev) -> None:
        if not ev.double() or not ev.modifiers() & Qt.KeyboardModifier.ControlModifier:
            return              # a plain double-click maximises the plot (ui/window/plot_focus.py)
        pos = ev.scenePos()
        for plot in self.plots:
            if plot.vb.sceneBoundingRect().contains(pos):
                x = plot.vb.mapSceneToView(pos).x()
                for p in self._phases:
                    if p.start_s <= x <= p.end_s and p.offset >= 0:
                        self.phaseActivated.emit(p.offset)
                        return
                return

    def paintEvent(self, event) -> None:  # noqa: N802
        clock = time.perf_counter()
        super().paintEvent(event)
        self._paint_ms = (time.perf_counter() - clock) * 1000.0
        self.paints += 1
