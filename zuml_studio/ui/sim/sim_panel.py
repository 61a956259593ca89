"""The simulator panel: parameters on the left, the run's plot in the middle and its
phases on the right. It simulates the latest valid record in a worker process,
again on every change if asked to, and keeps showing the last run while the
macro has errors."""
from __future__ import annotations

from PySide6.QtCore import QElapsedTimer, QEvent, QEventLoop, QSize, Qt, QTimer, Signal
from PySide6.QtWidgets import (QApplication, QHBoxLayout, QLabel, QScrollArea, QSizePolicy, QSplitter, QVBoxLayout,
                               QWidget)

from ...i18n import N_, _, ngettext
from ...sim.charger_model import load_charger
from ...sim.program import TASK_WORDS
from ...sim.start_check import start_warnings
from ..base import theme
from ..plots.plot_export import render_with_header
from ..base.timefmt import elapsed
from .charge_plot import ChargePlot
from .params_form import ParamsForm
from ..plots.phase_table import PhaseTable, totals_text
from .worker import SimJob, SimRequest, warm_up

DEBOUNCE_MS = 300
WARM_UP_MS = 1500      # the simulation processes' fork server starts this long after the panel is first shown
PAINT_AFTER_MS = 4      # a new run's bands, axes and paint, each in a turn of the event loop of its own
TABLE_AFTER_MS = 12     # after the plot's paint
STALE_HINT = N_("showing the last valid version (the macro has errors)")
NOTHING_YET = N_("no simulation yet: Simulate (F5) runs the macro against a battery model")
OUTDATED_HINT = N_("the macro or the parameters changed since this run: Simulate (F5)")

TALL_PX = 480      # from this height the phase table goes under the start values
TALL_SIDE_SHARE = 0.25


class SimulatorPanel(QWidget):
    simulationFinished = Signal(object)     # the SimResult of a run that reached its end
    phaseActivated = Signal(int)            # byte offset of the FAZE of a double-clicked phase

    def __init__(self, parent: QWidget | None = None):
        super().__init__(parent)
        self.setObjectName("simulatorPanel")
        self._record: bytes | None = None
        self._macro_name = ""
        self._stale = False                 # the text has errors now: what is shown is from before
        self._outdated = False              # record or parameters changed since the shown run
        self._job: SimJob | None = None
        self._result = None
        self._clock = QElapsedTimer()
        self._sized = False
        self._table_pending = None          # a run whose phases are still to be listed
        self._steps: list = []              # what is left of drawing a new run, one step a turn (_show)
        self._chain = 0                     # the newest drawing's number: an older one's steps stop
        self._message_kind = "info"

        self.form = ParamsForm()
        self.plot = ChargePlot()
        self.table = PhaseTable()
        self.run_label = QLabel("")
        self.run_label.setObjectName("simRunLabel")
        self.run_label.setSizePolicy(QSizePolicy.Policy.Ignored, QSizePolicy.Policy.Preferred)
        self.run_label.setVisible(False)
        self.message = QLabel("")
        self.message.setObjectName("simMessage")
        self.message.setWordWrap(True)
        self.message.setTextInteractionFlags(Qt.TextInteractionFlag.TextSelectableByMouse)
        self.message.setSizePolicy(QSizePolicy.Policy.Expanding, QSizePolicy.Policy.Preferred)
        self.message.setAlignment(Qt.AlignmentFlag.AlignLeft | Qt.AlignmentFlag.AlignVCenter)
        self.hint = QLabel("")
        self.hint.setObjectName("simHint")
        self.hint.setVisible(False)
        self._style_texts()
        self.totals = QLabel("")
        self.totals.setObjectName("simTotals")
        self.totals.setWordWrap(True)
        self.totals.setTextInteractionFlags(Qt.TextInteractionFlag.TextSelectableByMouse)
        self.totals.setContentsMargins(2, 2, 2, 0)

        params_scroll = QScrollArea()
        params_scroll.setWidget(self.form)
        params_scroll.setWidgetResizable(True)
        params_scroll.setFrameShape(QScrollArea.Shape.NoFrame)
        params_scroll.setHorizontalScrollBarPolicy(Qt.ScrollBarPolicy.ScrollBarAlwaysOff)
        params_scroll.setMinimumWidth(self.form.minimumSizeHint().width() + 4)
        self.params_scroll = params_scroll

        table_box = QWidget()
        table_layout = QVBoxLayout(table_box)
        table_layout.setContentsMargins(0, 0, 0, 0)
        table_layout.setSpacing(2)
        table_layout.addWidget(self.table, 1)
        table_layout.addWidget(self.totals)

        self.table_box = table_box
        self.side = QSplitter(Qt.Orientation.Vertical)      # the start values, and the phases when the panel is tall
        self.side.setObjectName("simSide")
        self.side.setChildrenCollapsible(False)
        self.side.addWidget(params_scroll)
        self.splitter = QSplitter(Qt.Orientation.Horizontal)
        self.splitter.setObjectName("simSplitter")
        self.splitter.setChildrenCollapsible(False)
        self.splitter.addWidget(self.side)
        self.splitter.addWidget(self.plot)
        self.splitter.addWidget(table_box)
        self.splitter.setStretchFactor(0, 0)
        self.splitter.setStretchFactor(1, 3)
        self.splitter.setStretchFactor(2, 2)
        self.plot.setMinimumWidth(280)
        table_box.setMinimumWidth(180)

        header_box = QWidget()
        header_box.setObjectName("simHeader")
        header_box.setMinimumHeight(self.fontMetrics().height() + 4)     # no jump when a message comes
        header = QHBoxLayout(header_box)
        header.setContentsMargins(6, 2, 6, 0)
        header.setSpacing(12)
        header.addWidget(self.run_label, 2)
        header.addWidget(self.hint, 0)
        header.addWidget(self.message, 3)
        layout = QVBoxLayout(self)
        layout.setContentsMargins(0, 0, 0, 0)
        layout.setSpacing(2)
        layout.addWidget(header_box)
        layout.addWidget(self.splitter, 1)

        self._debounce = QTimer(self, singleShot=True, interval=DEBOUNCE_MS)
        self._debounce.timeout.connect(self.simulate)
        self.form.simulateRequested.connect(self.simulate)
        self.form.cancelRequested.connect(self.cancel)
        self.form.changed.connect(self._params_changed)
        self.form.autoToggled.connect(self._auto_toggled)
        self.table.phaseActivated.connect(self.phaseActivated)
        self.plot.phaseActivated.connect(self.phaseActivated)
        self.table.phaseSelected.connect(self.plot.highlight)
        self.plot.phaseClicked.connect(self._band_clicked)
        self._show_message(_(NOTHING_YET), "info")

    # -- the interface the main window uses ------------------------------------------------
    def set_record(self, record: bytes | None, macro_name: str = "", declared: dict | None = None) -> None:
        """The latest valid compiled record, or None while the text has errors."""
        if record is None:
            self._stale = True
            self._refresh_hint()
            return
        self._stale = False
        record = bytes(record)
        new_record = record != self._record
        params_changed = self.form.apply_declared(declared)
        self._record, self._macro_name = record, macro_name or self._macro_name
        if new_record or params_changed:
            self._changed()
        else:
            self._refresh_hint()

    def new_macro(self) -> None:
        """Another macro opened (not an edit of this one): start values from the new macro, and
        nothing of the old one's run (while the new text has errors there is no "last valid
        version" of it to show)."""
        self.form.reset_start_values()
        self._drop_job()
        self._debounce.stop()
        self._record = self._result = self._table_pending = None
        self._stale = self._outdated = False
        self.plot.clear_run()
        self.table.set_result(None)
        self.totals.setText("")
        self.run_label.setVisible(False)
        self.form.progress_label.setText("")
        self._show_message(_(NOTHING_YET), "info")
        self._refresh_hint()

    def current_record(self) -> bytes | None:
        """The latest valid record (None before the macro first compiled)."""
        return self._record

    def simulate(self) -> None:
        """Start now (the previous run, if any, is dropped)."""
        self._debounce.stop()
        if self._record is None:
            self._show_message(_("nothing to simulate: the macro has not compiled yet"), "error")
            return
        try:
            setup = self.form.battery_setup()
        except ValueError as exc:
            self._show_message(_("cannot simulate: {reason}").format(reason=exc), "error")
            return
        self._drop_job()
        request = SimRequest(self._record, self.form.start_params(), setup, self._macro_name)
        warnings = start_warnings(request.record, request.params, load_charger(request.setup.charger))
        job = SimJob(request)
        worker = job.worker
        worker.progress.connect(self._on_progress)
        worker.done.connect(self._on_done)
        worker.cancelled.connect(self._on_cancelled)
        worker.failed.connect(self._on_failed)
        worker.ended.connect(self._on_ended)
        self._job = job
        self._outdated = False
        self.form.set_running(True)
        self._show_message("\n".join(f"⚠ {w}" for w in warnings), "warn")
        self._refresh_hint()
        self._clock.start()
        job.start()

    def cancel(self) -> None:
        self._debounce.stop()
        if self._job is not None:
            self._job.cancel()
            self._show_message(_("cancelling…"), "warn")

    def result(self):
        """The SimResult shown (a cancelled run's partial one included), None before any."""
        return self._result

    def export_csv(self, path: str) -> bool:
        if self._result is None:
            self._show_message(_("nothing to export: simulate first"), "error")
            return False
        try:
            with open(path, "w", encoding="utf-8", newline="") as fh:
                self._result.log.write_csv(fh)
        except OSError as exc:
            self._show_message(_("cannot write {path}: {reason}").format(path=path, reason=exc.strerror or exc), "error")
            return False
        return True

    def export_png(self, path: str, size: QSize | None = None, title: str = "") -> bool:
        """The plot as shown; with ``size``, laid out at that size under ``title`` and the run's
        details (the macro, the battery, the parameters, the totals)."""
        self.plot.readout.hide()                # the mouse's cursor is no part of a report
        if size is None:
            ok = self.plot.export_png(path)
        else:
            details = [self._describe(self._result), totals_text(self._result)] if self._result is not None else []
            ok = render_with_header(self.plot, size, title, details).save(path, "PNG")
        if not ok:
            self._show_message(_("cannot write {path}").format(path=path), "error")
        return ok

    # -- extras (tests, screenshots) -------------------------------------------------------
    def is_running(self) -> bool:
        return self._job is not None

    def wait(self, msecs: int = 30_000) -> bool:
        """Run the event loop until the current simulation has been shown; False on timeout."""
        clock = QElapsedTimer()
        clock.start()
        while (self._job is not None or self._table_pending is not None) and clock.elapsed() < msecs:
            if self._job is not None:
                self._job.thread.wait(10)
            QApplication.processEvents(QEventLoop.ProcessEventsFlag.AllEvents, 50)
        return self._job is None and self._table_pending is None

    def message_text(self) -> str:
        """The status line as the user reads it: the hint, then the message."""
        return " ".join(t for t in (self.hint.text() if self.hint.isVisibleTo(self) else "",
                                    self.message.text()) if t)

    # -- running ---------------------------------------------------------------------------
    def _drop_job(self) -> None:
        """Abandon the current job and forget it: whatever it still reports is ignored."""
        if self._job is not None:
            self._job.abandon()
            self._job = None
            self.form.set_running(False)

    def _current(self, job_id: int) -> bool:
        return self._job is not None and self._job.id == job_id

    def _on_progress(self, job_id: int, seconds: float) -> None:
        if self._current(job_id):
            self.form.set_progress(seconds)

    def _on_done(self, job_id: int, run) -> None:
        if not self._current(job_id):
            return
        result = run.result
        self._show(run, finished=True)
        self.form.progress_label.setText(_("{time} simulated in {seconds} s").format(
            time=elapsed(result.interpreter.time_s), seconds=f"{self._clock.elapsed() / 1000:.1f}"))
        self._refresh_hint()

    def _on_cancelled(self, job_id: int, run) -> None:
        if not self._current(job_id):
            return
        if run is not None:
            result = run.result
            self._show(run)
            at = elapsed(result.interpreter.time_s)
            self.form.progress_label.setText(_("cancelled after {time}").format(time=at))
            self._show_message(_("cancelled after {time} of simulated time: showing the run so far").format(time=at),
                               "warn")
        else:
            self.form.progress_label.setText(_("cancelled"))
            self._show_message(_("cancelled"), "warn")

    def _on_failed(self, job_id: int, message: str) -> None:
        if not self._current(job_id):
            return
        self.form.progress_label.setText(_("failed"))
        self._show_message(_("cannot simulate: {reason}").format(reason=message), "error")

    def _on_ended(self, job_id: int) -> None:
        if self._current(job_id):
            self._job = None
            self.form.set_running(False)
            self._refresh_hint()

    def _show(self, run, finished: bool = False) -> None:
        """A PlotData: the run, ready to draw. The plot takes its data and range now; its view's curves,
        its legends, its phase bands, its pauses, each plot's y range and each of its axes, and its paint
        each a moment later, then the phase table, its totals, and ``simulationFinished`` if the run
        reached its end: twenty slices of GUI-thread time of 0.1-2.5 ms each (thread CPU, median of a
        47 h run's), the paint 5-6 ms (all in one turn took 25-30 ms; eight slices left ones of 4-6 ms,
        which a worker holding the GIL or a loaded machine stretched past 16 ms of wall time)."""
        result = self._result = run.result
        self.plot.setUpdatesEnabled(False)
        self.plot.show_run(run, place=False)
        self._table_pending = (result, finished)
        self._steps = [*self.plot.place_steps(), *self.plot.band_steps(), *self.plot.paint_steps(), self._paint_plot]
        self._chain += 1
        chain = self._chain
        QTimer.singleShot(PAINT_AFTER_MS, self, lambda: self._next_step(chain))

    def _next_step(self, chain: int) -> None:
        if chain != self._chain or not self._steps:
            return                      # a newer run's chain has taken over
        self._steps.pop(0)()
        if self._steps:
            QTimer.singleShot(PAINT_AFTER_MS, self, lambda: self._next_step(chain))
        else:
            QTimer.singleShot(TABLE_AFTER_MS, self, self._show_table)

    def _paint_plot(self) -> None:
        self.plot.setUpdatesEnabled(True)
        self.plot.viewport().update()

    def _show_table(self) -> None:
        """The phase table, then (a turn later: the two took up to 5 ms) the totals and the run's line."""
        if self._table_pending is None:
            return
        self.table.set_result(self._table_pending[0])
        chain = self._chain
        QTimer.singleShot(PAINT_AFTER_MS, self, lambda: chain == self._chain and self._show_totals())

    def _show_totals(self) -> None:
        if self._table_pending is None:
            return
        (result, finished), self._table_pending = self._table_pending, None
        self.totals.setText(totals_text(result))
        self.totals.setToolTip(self._repetitions_tip(result))
        self.run_label.setText(self._describe(result))
        self.run_label.setVisible(True)
        self.run_label.setToolTip(self.run_label.text())
        if finished:
            self.simulationFinished.emit(result)

    def _describe(self, result) -> str:
        it = result.interpreter
        params = it.params
        task = _(TASK_WORDS[params.task]) + (f" ×{params.repetitions}" if params.task == "train" else "")
        name = it.program.name or self._macro_name
        cells = ngettext("{n} cell", "{n} cells", result.series).format(n=result.series)
        text = _("{name}: {task} · {chemistry} model {capacity} mAh × {cells} · {ambient} °C · {sensor}").format(
            name=name, task=task, chemistry=result.chemistry, capacity=f"{result.capacity_mah:.0f}", cells=cells,
            ambient=f"{it.pack.ambient_c:g}", sensor=_("sensor on") if params.sensor else _("sensor off"))
        specs = getattr(it.pack, "specs", None)
        if specs:
            caps = [c.capacity_mah for c in specs]
            text += " · " + _("cells {low}–{high} mAh").format(low=f"{min(caps):.0f}", high=f"{max(caps):.0f}")
        return text + " · " + it.charger.limits.name

    @staticmethod
    def _repetitions_tip(result) -> str:
        if result.interpreter.params.task != "train":
            return ""
        lines = [_("repetition {n}: discharged {discharged} mAh, charged {charged} mAh").format(
                 n=r["repetition"], discharged=f"{r['discharged_mah']:.1f}", charged=f"{r['charged_mah']:.1f}")
                 for r in result.repetitions()]
        return "\n".join(lines[:40] + (["…"] if len(lines) > 40 else []))

    # -- changes -----------------------------------------------------------------------------
    def _changed(self) -> None:
        if self.form.auto_resimulate():
            self._debounce.start()
        else:
            self._outdated = self._result is not None
        self._refresh_hint()

    def _params_changed(self) -> None:
        if self._record is not None:
            self._changed()

    def _auto_toggled(self, on: bool) -> None:
        if on and self._record is not None and (self._result is None or self._outdated):
            self._debounce.start()

    def _band_clicked(self, row: int) -> None:
        self.table.select_phase(row)
        self.plot.highlight(row)

    # -- messages ------------------------------------------------------------------------------
    def _show_message(self, text: str, kind: str) -> None:
        self.message.setText(text)
        self.message.setToolTip(text)
        self._message_kind = kind
        self._style_texts()
        self.message.setVisible(bool(text))

    def _style_texts(self) -> None:
        """The run line, the hint and the message in the palette's colours (light or dark)."""
        c = theme.colours(self.palette())
        colour = {"error": c.error, "warn": c.warning}.get(self._message_kind, c.muted)
        self.message.setStyleSheet(f"color:{colour};" + ("font-weight:bold;" if self._message_kind == "error" else ""))
        self.run_label.setStyleSheet(f"color:{c.muted};")
        self.hint.setStyleSheet(f"color:{c.muted}; font-style:italic;")

    def changeEvent(self, event) -> None:  # noqa: N802
        super().changeEvent(event)
        if event.type() == QEvent.Type.PaletteChange:
            self._style_texts()

    def _refresh_hint(self) -> None:
        """The grey hint: what is shown is older than the editor's text."""
        shown = self._result is not None
        text = (_(STALE_HINT) if self._stale and shown else
                _(OUTDATED_HINT) if self._outdated and shown and self._job is None else "")
        self.hint.setText(text)
        self.hint.setVisible(bool(text))

    # -- layout ------------------------------------------------------------------------------
    def showEvent(self, event) -> None:
        super().showEvent(event)
        if not self._sized:
            self._sized = True
            self._split_sizes()
            QTimer.singleShot(WARM_UP_MS, self, warm_up)

    def resizeEvent(self, event) -> None:  # noqa: N802
        super().resizeEvent(event)
        self._arrange(self.height() >= TALL_PX)

    def is_tall(self) -> bool:
        """Whether the phase table stands under the start values (the plot then has the width)."""
        return self.table_box.parentWidget() is self.side

    def _arrange(self, tall: bool) -> None:
        """A panel with the window's height to itself (the Simulate mode) puts the phase table under the
        start values, so the plot gets the width as well; a strip at the window's foot keeps the three
        side by side."""
        if tall == self.is_tall():
            return
        if tall:
            self.side.addWidget(self.table_box)
            self.side.setSizes([self.form.sizeHint().height(), max(1, self.height() - self.form.sizeHint().height())])
        else:
            self.splitter.addWidget(self.table_box)
            self.splitter.setStretchFactor(2, 2)
        self._split_sizes()

    def _split_sizes(self) -> None:
        width = max(self.width(), 800)
        params = self.params_scroll.minimumWidth() + 8
        rest = width - params
        if self.is_tall():      # the phase table shares the start values' column: a quarter of a wide panel
            side = max(params, int(width * TALL_SIDE_SHARE))
            self.splitter.setSizes([side, width - side])
        else:
            self.splitter.setSizes([params, int(rest * 0.58), rest - int(rest * 0.58)])
