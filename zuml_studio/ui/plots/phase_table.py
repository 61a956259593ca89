"""One row per phase the simulation ran: when, how long, why it ended, what went in and
out, and notes (heat-sink pauses, the charger's limits cutting the current). Phases a
default safety condition ended (not the macro), and charges a timer ended before the
capacity was in, are flagged."""
from __future__ import annotations

import math

from PySide6.QtCore import QAbstractTableModel, QEvent, QModelIndex, Qt, Signal
from PySide6.QtGui import QColor
from PySide6.QtWidgets import QAbstractItemView, QHeaderView, QStyle, QTableView

from ...i18n import N_, _, ngettext
from ...sim.reasons import end_advice, shown_reason
from ..base import theme
from ..base.timefmt import duration, hmm, hmmss

COLUMNS = ("#", N_("section"), N_("phase"), N_("start"), N_("end"), N_("duration"), N_("end reason"), N_("mAh in"),
           N_("mAh out"), N_("V end"), N_("T end"), N_("notes"))
REASON_COLUMN = COLUMNS.index("end reason")
NOTES_COLUMN = COLUMNS.index("notes")
DEFAULT_TIP = N_("ended by a default safety condition, not by the macro")
TIMER_TIP = N_("timer before full")
SECTION_WORDS = {"charge": N_("charge"), "discharge": N_("discharge")}
SECTION_TINT_ALPHA = 60          # the section cell in the plot's band hue
ALIGNMENTS = tuple(int((Qt.AlignmentFlag.AlignRight if col in (0, 3, 4, 5, 7, 8, 9, 10) else Qt.AlignmentFlag.AlignLeft)
                       | Qt.AlignmentFlag.AlignVCenter) for col in range(len(COLUMNS)))
DISPLAY, DECORATION, TOOLTIP, ALIGNMENT, BACKGROUND, FOREGROUND = (int(r) for r in (
    Qt.ItemDataRole.DisplayRole, Qt.ItemDataRole.DecorationRole, Qt.ItemDataRole.ToolTipRole,
    Qt.ItemDataRole.TextAlignmentRole, Qt.ItemDataRole.BackgroundRole, Qt.ItemDataRole.ForegroundRole))
SIZED_ROWS = 64


class PhaseModel(QAbstractTableModel):
    """The phases of a run, formatted only when a cell is shown: a new run is one reset,
    however many phases it lists (a 255-repetition training lists 510)."""

    def __init__(self, header_tips: dict[str, str], warn_icon, parent=None):
        super().__init__(parent)
        self._tips = header_tips
        self._warn_icon = warn_icon
        self._phases: list = []
        self._series = 1
        self._training = False
        self._rows: dict[int, dict[int, tuple]] = {}     # row -> role -> a value per column
        self.colours = theme.LIGHT

    def set_colours(self, colours: theme.Colours) -> None:
        """The palette's colour set for the flagged rows and the section tints."""
        self.colours = colours
        self._rows = {}
        if self._phases:
            self.dataChanged.emit(self.index(0, 0), self.index(len(self._phases) - 1, len(COLUMNS) - 1))

    def set_result(self, result) -> None:
        self.set_phases(list(result.phases) if result is not None else [], getattr(result, "series", 1) or 1)

    def set_phases(self, phases: list, series: int) -> None:
        """Phases of the simulator's kind (``PhaseResult`` or a charger's ``LivePhase``). The same
        number of phases again (a running phase that measured more) keeps the selection."""
        same = len(phases) == len(self._phases) and series == self._series
        if not same:
            self.beginResetModel()
        self._phases = phases
        self._series = series
        self._training = any(p.repetition > 1 for p in self._phases)
        self._rows = {}
        if not same:
            self.endResetModel()
        elif phases:
            self.dataChanged.emit(self.index(0, 0), self.index(len(phases) - 1, len(COLUMNS) - 1))

    def rowCount(self, parent=QModelIndex()) -> int:  # noqa: N802 - Qt's name
        return 0 if parent.isValid() else len(self._phases)

    def columnCount(self, parent=QModelIndex()) -> int:  # noqa: N802 - Qt's name
        return 0 if parent.isValid() else len(COLUMNS)

    def headerData(self, section: int, orientation, role=Qt.ItemDataRole.DisplayRole):  # noqa: N802 - Qt's name
        if orientation != Qt.Orientation.Horizontal or not 0 <= section < len(COLUMNS):
            return None
        if role == Qt.ItemDataRole.DisplayRole:
            return _(COLUMNS[section])
        if role == Qt.ItemDataRole.ToolTipRole:
            return self._tips.get(COLUMNS[section])
        return None

    def column_texts(self, rows: int) -> tuple[list[set[str]], set[int]]:
        """The distinct texts of each column in the first ``rows`` rows, and the columns that
        show an icon there."""
        texts: list[set[str]] = [set() for _ in COLUMNS]
        icons: set[int] = set()
        for row in range(min(rows, len(self._phases))):
            roles = self._rows.get(row) or self._row_roles(row)
            for column, text in zip(texts, roles[DISPLAY]):
                column.add(text)
            if DECORATION in roles:
                icons.add(REASON_COLUMN)
        return texts, icons

    def set_header_tips(self, tips: dict[str, str]) -> None:
        """Column titles' tooltips in place of the simulator's (a charger's table measures, not models)."""
        self._tips = {**self._tips, **tips}

    def phase(self, row: int):
        return self._phases[row] if 0 <= row < len(self._phases) else None

    def flag_tip(self, row: int) -> str:
        """Why the row is flagged, and what to change ("" if it is not)."""
        p = self._phases[row]
        if not p.warns:
            return ""
        return f"{_(DEFAULT_TIP) if p.by_default else _(TIMER_TIP)}: {end_advice(p)}"

    def data(self, index: QModelIndex, role: int = DISPLAY):
        # Called several times per cell for every paint and size hint: one dictionary look-up
        # into the row's roles, built the first time the row is asked for.
        roles = self._rows.get(index.row()) or self._row_roles(index.row())
        values = roles.get(role)
        return values[index.column()] if values is not None else None

    def _row_roles(self, row: int) -> dict[int, tuple]:
        if not 0 <= row < len(self._phases):
            return {}
        p = self._phases[row]
        ended = bool(p.reason)
        section = _(SECTION_WORDS.get(p.section, p.section)) + (
            " · " + _("rep {n}").format(n=p.repetition) if self._training else "")
        phase = (f"{p.index}" + (" " + _("(pass {n})").format(n=p.cycle_pass) if p.cycle_pass else "")
                 if p.index else _("default"))
        cells = (str(p.run or row + 1), section, phase, hmmss(p.start_s),
                 hmmss(p.end_s) if ended else "…", duration(p.end_s - p.start_s) if ended else "",
                 shown_reason(p.reason) or _("(running)"), f"{p.mah_in:.1f}", f"{p.mah_out:.1f}",
                 _measured(p.v_end, 3) if ended else "", _measured(p.temp_end, 1) if ended else "",
                 "; ".join(p.notes))
        flag = self.flag_tip(row)
        summary = flag or row_summary(p, self._series)      # the whole row on hover: a narrow table cuts columns off
        tips = [summary] * len(COLUMNS)
        if not flag and ended and not math.isnan(p.v_end):
            tips[4] = hmm(p.end_s)
            tips[9] = _("{pack} V pack, {cell} V per cell").format(pack=f"{p.v_end:.3f}",
                                                                  cell=f"{p.v_end / self._series:.3f}")
        tips[REASON_COLUMN] = f"{cells[REASON_COLUMN]}: {flag}" if flag else cells[REASON_COLUMN]
        tips[NOTES_COLUMN] = "\n".join(p.notes)
        n = len(COLUMNS)
        roles = {DISPLAY: cells, TOOLTIP: tuple(tips), ALIGNMENT: ALIGNMENTS}
        if flag:
            roles[FOREGROUND] = (QColor(self.colours.warning),) * n
            roles[BACKGROUND] = (QColor(self.colours.warning_row),) * n
            roles[DECORATION] = tuple(self._warn_icon if col == REASON_COLUMN else None for col in range(n))
        elif p.section in self.colours.plot.bands:
            tint = QColor(*self.colours.plot.bands[p.section], SECTION_TINT_ALPHA)
            roles[BACKGROUND] = (None, tint) + (None,) * (n - 2)
        self._rows[row] = roles
        return roles


class PhaseTable(QTableView):
    phaseActivated = Signal(int)        # byte offset of the phase's FAZE
    phaseSelected = Signal(int)         # row (= phase run - 1), -1 for none

    def __init__(self, parent=None):
        super().__init__(parent)
        self.setObjectName("phaseTable")
        tips = {"phase": _("position of the FAZE in its section (and the CYCLE pass)"),
                "end reason": _("the condition that ended the phase"), "V end": _("pack voltage at the end"),
                "T end": _("battery temperature at the end (the model's, also without a sensor)"),
                "notes": _("timer before full, heat-sink pauses, the charger's limits cutting the current")}
        warn_icon = self.style().standardIcon(QStyle.StandardPixmap.SP_MessageBoxWarning)
        self.phases = PhaseModel(tips, warn_icon, self)
        self.phases.set_colours(theme.colours(self.palette()))
        self.setModel(self.phases)
        self.setEditTriggers(QAbstractItemView.EditTrigger.NoEditTriggers)
        self.setSelectionBehavior(QAbstractItemView.SelectionBehavior.SelectRows)
        self.setSelectionMode(QAbstractItemView.SelectionMode.SingleSelection)
        self.setAlternatingRowColors(True)
        self.setWordWrap(False)
        self.setHorizontalScrollMode(QAbstractItemView.ScrollMode.ScrollPerPixel)
        font = self.font()
        font.setPointSizeF(max(7.0, font.pointSizeF() - 1))
        self.setFont(font)
        self.horizontalHeader().setFont(font)
        self.verticalHeader().setVisible(False)
        self.verticalHeader().setDefaultSectionSize(self.fontMetrics().height() + 6)
        header = self.horizontalHeader()
        header.setHighlightSections(False)
        header.setSectionsMovable(True)
        header.setSectionResizeMode(QHeaderView.ResizeMode.Interactive)
        header.setStretchLastSection(False)
        header.setDefaultAlignment(Qt.AlignmentFlag.AlignLeft | Qt.AlignmentFlag.AlignVCenter)
        self.doubleClicked.connect(self._double_clicked)
        self.selectionModel().selectionChanged.connect(self._selection_changed)
        self.setToolTip(_("Double-click a phase to show its FAZE in the editor"))

    def changeEvent(self, event) -> None:  # noqa: N802
        super().changeEvent(event)
        if event.type() == QEvent.Type.PaletteChange and theme.colours(self.palette()) is not self.phases.colours:
            self.phases.set_colours(theme.colours(self.palette()))

    def set_result(self, result) -> None:
        """Fill from a SimResult (or clear with None)."""
        self.phases.set_result(result)
        self._fit_columns()

    def set_phases(self, phases: list, series: int) -> None:
        """Fill from a charger's phases as they come (``LivePhase``); the columns fit again when a
        phase starts or ends."""
        before = [(p.reason, p.run) for p in self.phases._phases]
        self.phases.set_phases(phases, series)
        if [(p.reason, p.run) for p in phases] != before:
            self._fit_columns()

    def _fit_columns(self) -> None:
        """Each column as wide as its widest text in the first SIZED_ROWS rows, or its title.
        Measured here from the texts: the view's resizeColumnsToContents asks the model eight
        roles a cell, ~10 ms for a 32-phase run, on the GUI thread after every run."""
        texts, icons = self.phases.column_texts(SIZED_ROWS)
        metrics = self.fontMetrics()
        header = self.horizontalHeader()
        # The delegate's margins, and 2 px for the text layout's rounding up.
        margin = 2 * (self.style().pixelMetric(QStyle.PixelMetric.PM_FocusFrameHMargin, None, self) + 1) + 2
        icon = self.style().pixelMetric(QStyle.PixelMetric.PM_SmallIconSize, None, self) + margin
        for col, column in enumerate(texts):
            width = max((metrics.horizontalAdvance(text) for text in column), default=0) + margin
            width += icon if col in icons else 0
            header.resizeSection(col, min(max(width, header.sectionSizeHint(col)) + 2, 320))

    def is_flagged(self, row: int) -> bool:
        return self.phases.phase(row) is not None and bool(self.phases.flag_tip(row))

    def offset_of(self, row: int) -> int:
        p = self.phases.phase(row)
        return p.offset if p is not None else -1

    def select_phase(self, row: int) -> None:
        """Select (and show) a row without re-emitting phaseSelected."""
        self.blockSignals(True)
        self.selectionModel().blockSignals(True)
        try:
            if 0 <= row < self.phases.rowCount():
                self.selectRow(row)
                self.scrollTo(self.phases.index(row, 0))
            else:
                self.clearSelection()
        finally:
            self.selectionModel().blockSignals(False)
            self.blockSignals(False)

    def _double_clicked(self, index: QModelIndex) -> None:
        offset = self.offset_of(index.row())
        if offset >= 0:
            self.phaseActivated.emit(offset)

    def _selection_changed(self, *_args) -> None:
        rows = {i.row() for i in self.selectionModel().selectedIndexes()}
        self.phaseSelected.emit(min(rows) if rows else -1)


def row_summary(p, series: int) -> str:
    """One phase in words, for the tooltip of its row."""
    head = _("{section} phase {index}").format(section=_(SECTION_WORDS.get(p.section, p.section)),
                                               index=p.index or _("default"))
    charge = _("{charged} mAh in, {discharged} mAh out").format(charged=f"{p.mah_in:.1f}",
                                                                discharged=f"{p.mah_out:.1f}")
    if not p.reason:
        return _("{phase}: running since {start}; {charge}").format(phase=head, start=hmmss(p.start_s), charge=charge)
    return _("{phase}: {start} to {end} ({duration}), ended by {reason}\n{charge}; at the end {pack} V "
             "({cell} V per cell), {temperature} °C").format(
        phase=head, start=hmmss(p.start_s), end=hmmss(p.end_s), duration=duration(p.end_s - p.start_s),
        reason=shown_reason(p.reason), charge=charge, pack=_measured(p.v_end, 3),
        cell=_measured(p.v_end / max(series, 1), 3),
        temperature=_measured(p.temp_end, 1))


def _measured(value: float, decimals: int) -> str:
    """A measurement, or "—" where there was none (a charger without a temperature sensor)."""
    return "—" if math.isnan(value) else f"{value:.{decimals}f}"


def totals_text(result) -> str:
    """The run in one line: duration, charge in and out, how it ended; for a training the
    capacity each discharge measured."""
    if result is None:
        return ""
    t = result.totals()
    measured = []
    if result.interpreter.params.task == "train":
        measured = [r["discharged_mah"] for r in result.repetitions() if r["discharged_mah"] > 0]
    return run_summary(t["duration_s"], t["mah_in"], t["mah_out"], t["end"], result.phases, measured)


def run_summary(duration_s: float, mah_in: float, mah_out: float, end: str, phases: list,
                measured: list[float] = ()) -> str:
    """A run (simulated, or a charger's) in one line: duration, charge in and out, how it ended, the
    phases that warn; the capacity each discharge of a training measured; the advice for the first
    phase that warns."""
    parts = [_("total {time}").format(time=hmmss(duration_s)), _("in {n} mAh").format(n=f"{mah_in:.0f}"),
             _("out {n} mAh").format(n=f"{mah_out:.0f}"), _("end: {reason}").format(reason=shown_reason(end) or "—")]
    defaults = sum(1 for p in phases if p.by_default and not p.full_by_dtdt)
    if defaults:
        parts.append("⚠ " + ngettext("{n} phase ended by a default", "{n} phases ended by a default",
                                     defaults).format(n=defaults))
    short = sum(1 for p in phases if p.timer_before_full)
    if short:
        parts.append("⚠ " + ngettext("{n} charge cut by a timer before full", "{n} charges cut by a timer before full",
                                     short).format(n=short))
    pauses = sum(len(p.pauses) for p in phases)
    if pauses:
        parts.append(ngettext("{n} heat-sink pause, {minutes} min", "{n} heat-sink pauses, {minutes} min",
                              pauses).format(n=pauses, minutes=f"{sum(p.paused_s for p in phases) / 60:.0f}"))
    text = " · ".join(parts)
    if measured:
        if len(measured) <= 6:
            caps = ", ".join(f"{m:.0f}" for m in measured)
        else:
            caps = (", ".join(f"{m:.0f}" for m in measured[:3]) + ", … " + f"{measured[-1]:.0f}"
                    + " " + _("(avg {n})").format(n=f"{sum(measured) / len(measured):.0f}"))
        text += "\n" + _("measured capacity per discharge: {capacities} mAh").format(capacities=caps)
    # Which phase, why, and what to change, for the first that warns (each row's tooltip has its own).
    first = next((p for p in phases if p.warns), None)
    if first is not None:
        text += "\n" + _("phase {run}: {advice}").format(run=first.run, advice=end_advice(first))
    return text
