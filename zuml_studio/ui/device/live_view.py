"""The live view: the readout of the newest frame (two lines over the plot), following the last minutes, All, Clear,
the run chooser and the live plot below them; under the plot, the run's phases as the simulator lists them (the
same table: start, end, the end reason the charger's EVENT frames carry, a warning sign where a default, the
balancer or a protection ended one) and the run in one line (how it ended, the advice for a phase that warns).
It owns the runs: the current one's series (telemetry goes into it from the reader thread) and up to
``KEEP_RUNS`` earlier ones."""
from __future__ import annotations

import math

from PySide6.QtCore import QEvent, QSize, Qt, Signal
from PySide6.QtWidgets import (QCheckBox, QComboBox, QGridLayout, QHBoxLayout, QLabel, QLayout, QSizePolicy,
                               QSplitter, QStyle, QToolButton, QVBoxLayout, QWidget)

from ...i18n import N_, _
from ..base import theme
from ..plots.plot_cursor import CursorReadout
from ..plots.phase_table import COLUMNS as PHASE_COLUMNS
from ..plots.phase_table import PhaseTable, run_summary
from .device_style import ElidedCombo, field_spin
from .live_plot import DEFAULT_FOLLOW_MIN, LivePlot, LiveSeries


RUNS_TIP = N_("Each Start begins a new run, plotted from 0; earlier runs stay here to look at")
KEEP_RUNS = 10          # earlier runs kept for the run chooser (the session CSV keeps them all)
PHASE_ROWS = 3          # rows of the phase table in view at first (the splitter gives it more)
PLOT_MIN_H = 160        # the plot's height the phase table leaves it in a low dock
# Section, start, duration, mAh out, T end: left out in a narrow column (the end and its reason matter most).
NARROW_HIDDEN = tuple(PHASE_COLUMNS.index(name) for name in ("section", "start", "duration", "mAh out", "T end"))


class LiveView(QWidget):
    runChosen = Signal(int)             # index in the run chooser (the last: the current run)

    def __init__(self, parent: QWidget | None = None):
        super().__init__(parent)
        self.series = LiveSeries()
        self.runs: list[tuple[str, LiveSeries]] = []             # earlier runs, oldest first
        self._before_run: tuple[str, LiveSeries] | None = None   # the run a pending START replaced
        self.start_frames = 0               # frames of the series before the last START or STOP
        self._finished_seen = 0
        self._shown = None                  # the frame the readout shows
        self.plot = LivePlot(self.series)
        self.plot.setMinimumWidth(280)
        self.readings = QLabel("")
        self.readings.setObjectName("readings")
        self.readings.setTextInteractionFlags(Qt.TextInteractionFlag.TextSelectableByMouse)
        self.readings.setSizePolicy(QSizePolicy.Policy.Ignored, QSizePolicy.Policy.Preferred)
        self.readings.setText("<br>")      # its two lines from the start: the plot does not jump at the first frame
        self.follow = QCheckBox(_("Follow last"))
        self.follow.setObjectName("followCheck")
        self.follow.setChecked(True)
        self.follow.setToolTip(_("Keep the newest minutes in view; zooming or panning the plot turns this off"))
        self.follow_minutes = field_spin(1, 24 * 60, DEFAULT_FOLLOW_MIN, " min",
                                         _("how much of the run to keep in view"))
        self.follow_minutes.setMaximumWidth(80)
        self.all_button = QToolButton()
        self.all_button.setText(_("All"))
        self.all_button.setToolTip(_("Show the whole session (stops following)"))
        self.clear_button = QToolButton()
        self.clear_button.setText(_("Clear"))
        self.clear_button.setToolTip(_("Forget the plotted session (the session CSV keeps everything)"))
        self.run_choice = ElidedCombo()
        self.run_choice.setObjectName("runChoice")
        self.run_choice.setToolTip(_(RUNS_TIP))
        # Narrow (the readout needs the room); the list shows the runs' whole names.
        self.run_choice.setSizeAdjustPolicy(QComboBox.SizeAdjustPolicy.AdjustToMinimumContentsLengthWithIcon)
        self.run_choice.setMinimumContentsLength(6)
        self.run_choice.setVisible(False)
        self.run_choice.activated.connect(self.runChosen)
        self.run_choice.currentTextChanged.connect(lambda text: self.run_choice.setToolTip(f"{text}\n{_(RUNS_TIP)}"))
        # The readings and the plot's controls share one row where the width allows (the height is
        # the plot's), else the controls go on a row of their own below (_place_controls).
        self.controls = QWidget()
        controls = QHBoxLayout(self.controls)
        controls.setContentsMargins(4, 0, 0, 0)
        controls.setSpacing(4)
        for widget in (self.run_choice, self.follow, self.follow_minutes, self.all_button, self.clear_button):
            controls.addWidget(widget)
        self.readings.setContentsMargins(4, 2, 4, 0)
        self._top = QGridLayout()
        self._top.setContentsMargins(0, 0, 0, 0)
        self._top.setSpacing(0)
        self._top.setColumnStretch(0, 1)
        self._top.addWidget(self.readings, 0, 0)
        self._one_row = True
        self._top.addWidget(self.controls, 0, 1, Qt.AlignmentFlag.AlignBottom | Qt.AlignmentFlag.AlignRight)
        pv = QVBoxLayout(self)
        pv.setContentsMargins(0, 0, 0, 0)
        pv.setSpacing(0)
        pv.addLayout(self._top)
        self._phases_layout()
        pv.addWidget(self.body, 1)
        self.readout = CursorReadout(self.plot, self._cursor_samples, lambda: self.plot.gap_s)
        self.follow.toggled.connect(lambda on: self.plot.set_follow(on, self.follow_minutes.value()))
        self.follow_minutes.valueChanged.connect(lambda v: self.plot.set_follow(self.plot.follow, v))
        self.plot.followChanged.connect(self._plot_follow_changed)
        self.all_button.clicked.connect(self._show_all)
        self.runChosen.connect(self._run_chosen)

    def _phases_layout(self) -> None:
        """The plot over the run's phases and its summary, in a splitter the user may move."""
        self.phase_table = LivePhaseTable()
        self.phase_table.setObjectName("livePhaseTable")
        self.phase_table.setToolTip(_("The run's phases as the charger reports them: why each ended (⚠: a default, "
                                      "the balancer or a protection, not the macro). Double-click a phase to show "
                                      "its FAZE in the editor"))
        self.phase_table.phaseActivated.connect(self.plot.phaseActivated)
        self.summary = QLabel("")
        self.summary.setObjectName("liveSummary")
        self.summary.setWordWrap(True)
        self.summary.setTextInteractionFlags(Qt.TextInteractionFlag.TextSelectableByMouse)
        self.summary.setSizePolicy(QSizePolicy.Policy.Ignored, QSizePolicy.Policy.Preferred)
        self.summary.setContentsMargins(4, 2, 4, 0)
        box = QWidget()
        box.setObjectName("livePhases")
        layout = QVBoxLayout(box)
        # Under the plot it asks for no height of its own: the panel's minimum stays the plot's (a low dock).
        layout.setSizeConstraint(QLayout.SizeConstraint.SetNoConstraint)
        box.setMinimumHeight(1)
        layout.setContentsMargins(0, 0, 0, 0)
        layout.setSpacing(2)
        layout.addWidget(self.summary)
        layout.addWidget(self.phase_table, 1)
        self.phase_table.setMinimumHeight(self.phase_table.verticalHeader().defaultSectionSize() * 2)
        self.phase_box = box
        self.body = QSplitter(Qt.Orientation.Vertical)
        self.body.setObjectName("liveSplitter")
        self.body.setChildrenCollapsible(False)
        self.body.addWidget(self.plot)
        self.body.addWidget(box)
        self.body.setStretchFactor(0, 1)
        self.body.setStretchFactor(1, 0)
        self.body.setCollapsible(1, True)
        self._body_moved = False
        self.body.splitterMoved.connect(self._body_moved_by_user)
        self._phases_key = None
        self._in_column = False

    def keep_phases(self) -> None:
        """The phases under the plot again, every column shown (after ``phases_in_column``)."""
        for column in NARROW_HIDDEN:
            self.phase_table.setColumnHidden(column, False)
        self._in_column = False
        self._phases_key = None
        self.update_phases()
        self.phase_box.setMinimumHeight(1)
        self.body.addWidget(self.phase_box)
        self.body.setCollapsible(1, True)
        self._size_body()

    def phases_in_column(self) -> None:
        """The phases are going to stand in a narrow column beside the plot (the device panel's,
        when the window's height is its own): the plot has the whole height, the table fewer columns
        (each row's tooltip still has them all)."""
        for column in NARROW_HIDDEN:
            self.phase_table.setColumnHidden(column, True)
        self._in_column = True
        self._phases_key = None
        self.update_phases()
        self.phase_table.setVisible(True)
        self.phase_box.setMinimumHeight(0)          # in the column: its layout's minimum

    def _body_moved_by_user(self, *_args) -> None:
        self._body_moved = True
        self.phase_table.setVisible(True)

    def _size_body(self) -> None:
        """The phase table a few rows high under the plot, the plot keeping PLOT_MIN_H in a low dock;
        once the user moves the splitter, it is theirs."""
        total = self.body.height()
        if self._body_moved or total <= 0 or self.body.count() < 2:
            return
        rows = self.phase_table.verticalHeader().defaultSectionSize()
        wanted = (self.phase_table.horizontalHeader().sizeHint().height() + PHASE_ROWS * rows
                  + 2 * self.summary.fontMetrics().lineSpacing() + 14)
        line = (self.summary.heightForWidth(self.body.width()) if self.summary.text()
                else self.summary.fontMetrics().lineSpacing()) + 4
        useful = line + self.phase_table.horizontalHeader().sizeHint().height() + 2 * rows + 2 * scroll_bar(self)
        # A low dock: the run's line alone under the plot, or the plot alone; the table comes back as the dock
        # grows, or when the user moves the splitter.
        self.phase_table.setVisible(total - useful >= PLOT_MIN_H)
        wanted = (max(useful, min(wanted, total - PLOT_MIN_H)) if total - useful >= PLOT_MIN_H
                  else line if total - line >= PLOT_MIN_H else 0)
        self.body.blockSignals(True)
        self.body.setSizes([total - wanted, wanted])
        self.body.blockSignals(False)

    def update_phases(self) -> None:
        """The shown run's phases and summary, when the charger reported something new."""
        series = self.plot.series
        key = (id(series), series.phase_version, series.frames, series.end_reason)
        if key == self._phases_key:
            return
        self._phases_key = key
        _version, phases = series.phases_copy()
        self.phase_table.set_phases(phases, max(1, series.cell_count))
        text = live_summary(phases, series.end_reason)
        # In a narrow column the run's line alone; what to change is in its tooltip (and the flagged row's).
        shown = text.split("\n", 1)[0] if self._in_column else text
        if shown != self.summary.text():
            lines = self.summary.heightForWidth(max(1, self.summary.width()))
            self.summary.setText(shown)
            if self.summary.heightForWidth(max(1, self.summary.width())) != lines:
                self._size_body()           # it took more lines or fewer: the table's room changes
        self.summary.setToolTip(text if shown != text else "")

    def _cursor_samples(self):
        """The drawn session's samples under the cursor readout's names (the cells' too, when there are)."""
        series = self.plot.series
        _, cols = series.buffer.snapshot()
        data = {"voltage_v": cols["voltage"], "current_a": cols["current"], "temp_c": cols["temp"]}
        table, first_row, count = series.cell_table()
        if table is not None and count > 1:
            _, cells = table.snapshot()
            data.update({name: RowsFrom(cells[name], first_row) for name in table.names[1:1 + count]})
        return cols["t"], data

    def resizeEvent(self, event) -> None:  # noqa: N802
        super().resizeEvent(event)
        self._place_controls()
        self._size_body()

    def _place_controls(self) -> None:
        """The plot's controls beside the readings when both fit in the width, else below them."""
        one_row = self.width() >= self.readings.sizeHint().width() + self.controls.sizeHint().width()
        if one_row == self._one_row:
            return
        self._one_row = one_row
        self._top.removeWidget(self.controls)
        if one_row:
            self._top.addWidget(self.controls, 0, 1, Qt.AlignmentFlag.AlignBottom | Qt.AlignmentFlag.AlignRight)
        else:
            self._top.addWidget(self.controls, 1, 0, 1, 2, Qt.AlignmentFlag.AlignRight)

    def show_readings(self, tel) -> None:
        """The newest frame's values, in the plot's hues from the palette's colour set (light or dark)."""
        self._shown = tel
        hue = theme.colours(self.palette()).quantities
        t = "—" if tel.temp_c is None else f"{tel.temp_c:.1f} °C"
        tc = "—" if tel.heatsink_c is None else f"{tel.heatsink_c:.1f} °C"
        amounts = _("charged {mah_in} mAh · discharged {mah_out} mAh").format(
            mah_in=f"{tel.mah_in:.0f}", mah_out=f"{tel.mah_out:.0f}")
        self.readings.setText(
            f"<span style='color:{hue['voltage']};'><b>{tel.voltage_v:.3f} V</b></span>&nbsp;&nbsp;"
            f"<span style='color:{hue['current']};'><b>{tel.current_a:+.3f} A</b></span>&nbsp;&nbsp;"
            f"<span style='color:{hue['temp']};'>T {t}</span>&nbsp;&nbsp;"
            f"<span style='color:{hue['heatsink']};'>Tc {tc}</span><br>{amounts}")
        # Two lines, whole at 1366 px; the tooltip says what T and Tc are.
        self.readings.setToolTip(_("{v} V · {a} A · battery T {t} · heat sink Tc {tc} · {amounts}").format(
            v=f"{tel.voltage_v:.3f}", a=f"{tel.current_a:+.3f}", t=t, tc=tc, amounts=amounts))
        self._place_controls()             # the readings grew or shrank: the controls may move

    def changeEvent(self, event) -> None:  # noqa: N802
        super().changeEvent(event)
        if event.type() == QEvent.Type.PaletteChange and self._shown is not None:
            self.show_readings(self._shown)

    def set_runs(self, labels: list[str]) -> None:
        """The runs of the session, the current one last (and chosen); shown from the second run."""
        self.run_choice.blockSignals(True)
        self.run_choice.clear()
        self.run_choice.addItems(labels)
        self.run_choice.setCurrentIndex(len(labels) - 1)
        for i, label in enumerate(labels):
            self.run_choice.setItemData(i, label, Qt.ItemDataRole.ToolTipRole)
        self.run_choice.blockSignals(False)
        self.run_choice.setVisible(len(labels) > 1)
        self.run_choice.setToolTip(f"{labels[-1]}\n{_(RUNS_TIP)}" if labels else _(RUNS_TIP))

    def follow_again(self) -> None:
        if not self.plot.follow:
            self.follow.setChecked(True)

    def _plot_follow_changed(self, on: bool) -> None:
        if self.follow.isChecked() != on:
            self.follow.blockSignals(True)
            self.follow.setChecked(on)
            self.follow.blockSignals(False)

    def _show_all(self) -> None:
        self.follow.setChecked(False)
        self.plot.show_all()

    # -- runs ---------------------------------------------------------------------------------
    def new_run(self, current_name: str) -> None:
        """A START makes a new session of the plot (its axis from 0); the run before it (of the
        macro ``current_name``) is kept."""
        if len(self.series) == 0 and not self.series.events:
            return
        self._before_run = (current_name, self.series)
        self.runs = (self.runs + [self._before_run])[-KEEP_RUNS:]
        self.series = LiveSeries()
        self._finished_seen = 0
        self.start_frames = 0
        self.plot.set_series(self.series)
        self._show_runs(current_name)

    def undo_new_run(self) -> str | None:
        """START did not start: show the run before it again, as the current one; returns its
        macro's name (None: nothing to undo)."""
        before, self._before_run = self._before_run, None
        if before is None or len(self.series):
            return None
        self.runs = [r for r in self.runs if r is not before]
        name, self.series = before
        self._finished_seen = len(self.series.events)
        self.start_frames = self.series.frames
        self.plot.set_series(self.series)
        self._show_runs(name)
        return name

    def run_started(self, name: str, cells: int) -> None:
        self._before_run = None
        self.mark_start()
        self._show_runs(name)
        self.plot.set_series_count(cells)
        self.follow_again()

    def mark_start(self) -> None:
        """Frames from now on tell whether the macro runs (older ones may still say it does)."""
        self.start_frames = self.series.frames

    def fresh_telemetry(self):
        """The newest frame if it came after the last START or STOP, else None."""
        tel = self.series.last_telemetry
        return tel if tel is not None and self.series.frames > self.start_frames else None

    def new_finishes(self) -> list:
        """The run's finish events not asked for before, each with the phase that ended last before
        it (None: no phase ran): its end reason is the rule that ended the run."""
        with self.series.lock:
            events = self.series.events[self._finished_seen:]
            self._finished_seen = len(self.series.events)
        finishes = [(x, ev) for x, ev in events if ev.kind == "finish"]
        if not finishes:
            return []
        _version, phases = self.series.phases_copy()
        return [(ev, next((p for p in reversed(phases) if p.start_s <= x), None)) for x, ev in finishes]

    def _show_runs(self, current_name: str) -> None:
        labels = [_("Run {n}: {name}").format(n=i + 1, name=name or "?") for i, (name, _s) in enumerate(self.runs)]
        labels.append(_("Run {n}: {name} (now)").format(n=len(self.runs) + 1, name=current_name or "?"))
        self.set_runs(labels)

    def _run_chosen(self, index: int) -> None:
        series = self.runs[index][1] if index < len(self.runs) else self.series
        if series is not self.plot.series:
            self.plot.set_series(series)
            if series is not self.series:
                self.follow.setChecked(False)
                self.plot.show_all()
            self.update_phases()


def scroll_bar(widget: QWidget) -> int:
    return widget.style().pixelMetric(QStyle.PixelMetric.PM_ScrollBarExtent, None, widget)


class LivePhaseTable(PhaseTable):
    """The simulator's phase table asking for PHASE_ROWS rows (a table view asks for 192 px whatever it
    holds): a column that stands in a scroll area gets no scroll bar from it, and takes more as there is."""

    def __init__(self, parent: QWidget | None = None):
        super().__init__(parent)
        self.phases.set_header_tips({
            "V end": _("pack voltage at the phase's last telemetry frame"),
            "T end": _("battery temperature at the phase's last telemetry frame (— without a sensor)"),
            "notes": _("heat-sink pauses, how long the balancer bled each cell")})

    def sizeHint(self) -> QSize:  # noqa: N802
        hint = super().sizeHint()
        rows = self.verticalHeader().defaultSectionSize() * PHASE_ROWS
        scroll = self.horizontalScrollBar().sizeHint().height()
        return QSize(hint.width(), self.horizontalHeader().sizeHint().height() + rows + scroll + 2 * self.frameWidth())


def live_summary(phases: list, end_reason: str) -> str:
    """A charger's run in one line, as the simulator says a run: from its first phase's start to
    its last phase's end, what went in and out, how it ended (running: the phase now)."""
    if not phases:
        return ""
    end = end_reason or _("(running)")
    return run_summary(phases[-1].end_s - phases[0].start_s, sum(p.mah_in for p in phases),
                       sum(p.mah_out for p in phases), end, phases)


class RowsFrom:
    """A column of the cells' table read by the row of the session's table: its first row stands
    beside row ``first`` there; earlier rows had no cells (NaN)."""

    def __init__(self, column, first: int):
        self.column, self.first = column, first

    def __getitem__(self, row: int) -> float:
        k = row - self.first
        return float(self.column[k]) if 0 <= k < len(self.column) else math.nan
