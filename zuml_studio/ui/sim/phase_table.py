"""One row per phase the simulation ran: when, how long, why it ended, what went in and
out, and notes (heat-sink pauses, the charger's limits cutting the current). Phases a
default safety condition ended (not the macro), and charges a timer ended before the
capacity was in, are flagged."""
from __future__ import annotations

from PySide6.QtCore import Qt, Signal
from PySide6.QtGui import QBrush, QColor
from PySide6.QtWidgets import QAbstractItemView, QHeaderView, QStyle, QTableWidget, QTableWidgetItem

from ...i18n import N_, _, ngettext
from ..timefmt import duration, hmm, hmmss

COLUMNS = ("#", N_("section"), N_("phase"), N_("start"), N_("end"), N_("duration"), N_("end reason"), N_("mAh in"),
           N_("mAh out"), N_("V end"), N_("T end"), N_("notes"))
REASON_COLUMN = COLUMNS.index("end reason")
NOTES_COLUMN = COLUMNS.index("notes")
DEFAULT_TIP = N_("ended by a default safety condition, not by the macro")
TIMER_TIP = N_("timer before full: a timer ended this charge with less than the capacity put in")
SECTION_WORDS = {"charge": N_("charge"), "discharge": N_("discharge")}
WARN_FG = QColor("#a04000")
WARN_BG = QColor("#fff3d6")
SECTION_TINT = {"charge": QColor(74, 134, 232, 60), "discharge": QColor(232, 96, 74, 60)}   # as the plot's bands
OFFSET_ROLE = Qt.ItemDataRole.UserRole + 1


class PhaseTable(QTableWidget):
    phaseActivated = Signal(int)        # byte offset of the phase's FAZE
    phaseSelected = Signal(int)         # row (= phase run - 1), -1 for none

    def __init__(self, parent=None):
        super().__init__(0, len(COLUMNS), parent)
        self.setObjectName("phaseTable")
        self.setHorizontalHeaderLabels([_(name) for name in COLUMNS])
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
        tips = {"phase": _("position of the FAZE in its section (and the CYCLE pass)"),
                "end reason": _("the condition that ended the phase"), "V end": _("pack voltage at the end"),
                "T end": _("battery temperature at the end (the model's, also without a sensor)"),
                "notes": _("timer before full, heat-sink pauses, the charger's limits cutting the current")}
        for col, name in enumerate(COLUMNS):
            if name in tips:
                self.horizontalHeaderItem(col).setToolTip(tips[name])
        self._warn_icon = self.style().standardIcon(QStyle.StandardPixmap.SP_MessageBoxWarning)
        self.cellDoubleClicked.connect(self._double_clicked)
        self.itemSelectionChanged.connect(self._selection_changed)
        self.setToolTip(_("Double-click a phase to show its FAZE in the editor"))

    def set_result(self, result) -> None:
        """Fill from a SimResult (or clear with None)."""
        self.setSortingEnabled(False)
        self.clearContents()
        phases = list(result.phases) if result is not None else []
        series = getattr(result, "series", 1) or 1
        training = any(p.repetition > 1 for p in phases)
        self.setRowCount(len(phases))
        for row, p in enumerate(phases):
            ended = bool(p.reason)
            section = _(SECTION_WORDS.get(p.section, p.section)) + (
                " · " + _("rep {n}").format(n=p.repetition) if training else "")
            phase = (f"{p.index}" + (" " + _("(pass {n})").format(n=p.cycle_pass) if p.cycle_pass else "")
                     if p.index else _("default"))
            cells = (str(p.run or row + 1), section, phase, hmmss(p.start_s),
                     hmmss(p.end_s) if ended else "…", duration(p.end_s - p.start_s) if ended else "",
                     p.reason or _("(running)"), f"{p.mah_in:.1f}", f"{p.mah_out:.1f}",
                     f"{p.v_end:.3f}" if ended else "", f"{p.temp_end:.1f}" if ended else "",
                     "; ".join(p.notes))
            for col, text in enumerate(cells):
                item = QTableWidgetItem(text)
                item.setData(OFFSET_ROLE, p.offset)
                if col in (0, 3, 4, 5, 7, 8, 9, 10):
                    item.setTextAlignment(Qt.AlignmentFlag.AlignRight | Qt.AlignmentFlag.AlignVCenter)
                if col == 9 and ended:
                    item.setToolTip(_("{pack} V pack, {cell} V per cell").format(pack=f"{p.v_end:.3f}",
                                                                                  cell=f"{p.v_end / series:.3f}"))
                elif col == 4 and ended:
                    item.setToolTip(hmm(p.end_s))
                self.setItem(row, col, item)
            summary = row_summary(p, series)
            for col in range(len(COLUMNS)):
                item = self.item(row, col)
                if not item.toolTip():          # the whole row on hover: a narrow table cuts columns off
                    item.setToolTip(summary)
            tint = SECTION_TINT.get(p.section)
            if tint is not None:
                self.item(row, 1).setBackground(QBrush(tint))
            self.item(row, NOTES_COLUMN).setToolTip("\n".join(p.notes))
            if p.by_default:
                self._flag(row, _(DEFAULT_TIP))
            elif p.timer_before_full:
                self._flag(row, _(TIMER_TIP))
            else:
                self.item(row, REASON_COLUMN).setToolTip(p.reason)
        self.resizeColumnsToContents()
        header = self.horizontalHeader()
        for col in range(len(COLUMNS)):
            header.resizeSection(col, min(header.sectionSize(col) + 2, 320))

    def _flag(self, row: int, tip: str) -> None:
        for col in range(self.columnCount()):
            item = self.item(row, col)
            item.setForeground(QBrush(WARN_FG))
            item.setBackground(QBrush(WARN_BG))
            if col != NOTES_COLUMN:
                item.setToolTip(tip)
        reason = self.item(row, REASON_COLUMN)
        reason.setIcon(self._warn_icon)
        reason.setToolTip(f"{reason.text()}: {tip}")

    def is_flagged(self, row: int) -> bool:
        item = self.item(row, REASON_COLUMN)
        return item is not None and any(_(tip) in (item.toolTip() or "") for tip in (DEFAULT_TIP, TIMER_TIP))

    def offset_of(self, row: int) -> int:
        item = self.item(row, 0)
        return int(item.data(OFFSET_ROLE)) if item is not None else -1

    def select_phase(self, row: int) -> None:
        """Select (and show) a row without re-emitting phaseSelected."""
        self.blockSignals(True)
        try:
            if 0 <= row < self.rowCount():
                self.selectRow(row)
                self.scrollToItem(self.item(row, 0))
            else:
                self.clearSelection()
        finally:
            self.blockSignals(False)

    def _double_clicked(self, row: int, _col: int) -> None:
        offset = self.offset_of(row)
        if offset >= 0:
            self.phaseActivated.emit(offset)

    def _selection_changed(self) -> None:
        rows = {i.row() for i in self.selectedIndexes()}
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
        reason=p.reason, charge=charge, pack=f"{p.v_end:.3f}", cell=f"{p.v_end / max(series, 1):.3f}",
        temperature=f"{p.temp_end:.1f}")


def totals_text(result) -> str:
    """The run in one line: duration, charge in and out, how it ended; for a training the
    capacity each discharge measured."""
    if result is None:
        return ""
    t = result.totals()
    parts = [_("total {time}").format(time=hmmss(t["duration_s"])), _("in {n} mAh").format(n=f"{t['mah_in']:.0f}"),
             _("out {n} mAh").format(n=f"{t['mah_out']:.0f}"), _("end: {reason}").format(reason=t["end"] or "—")]
    defaults = sum(1 for p in result.phases if p.by_default)
    if defaults:
        parts.append("⚠ " + ngettext("{n} phase ended by a default", "{n} phases ended by a default",
                                     defaults).format(n=defaults))
    short = sum(1 for p in result.phases if p.timer_before_full)
    if short:
        parts.append("⚠ " + ngettext("{n} charge cut by a timer before full", "{n} charges cut by a timer before full",
                                     short).format(n=short))
    pauses = sum(len(p.pauses) for p in result.phases)
    if pauses:
        parts.append(ngettext("{n} heat-sink pause, {minutes} min", "{n} heat-sink pauses, {minutes} min",
                              pauses).format(n=pauses, minutes=f"{sum(p.paused_s for p in result.phases) / 60:.0f}"))
    text = " · ".join(parts)
    if result.interpreter.params.task == "train":
        measured = [r["discharged_mah"] for r in result.repetitions() if r["discharged_mah"] > 0]
        if measured:
            if len(measured) <= 6:
                caps = ", ".join(f"{m:.0f}" for m in measured)
            else:
                caps = (", ".join(f"{m:.0f}" for m in measured[:3]) + ", … " + f"{measured[-1]:.0f}"
                        + " " + _("(avg {n})").format(n=f"{sum(measured) / len(measured):.0f}"))
            text += "\n" + _("measured capacity per discharge: {capacities} mAh").format(capacities=caps)
    return text
