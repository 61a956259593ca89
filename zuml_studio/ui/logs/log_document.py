"""One log as a document: the plot, the readout under it, and beside it the totals, the curves
shown (each can be hidden; remembered per log format, ``HiddenCurves``), two cursors with what
the log says between them, and the logs laid over it (other files, or the log's own cycles)."""
from __future__ import annotations

import html
from dataclasses import dataclass
from pathlib import Path

from PySide6.QtCore import QEvent, QSettings, Qt, Signal
from PySide6.QtWidgets import (QCheckBox, QFrame, QHBoxLayout, QLabel, QListWidget, QListWidgetItem, QPushButton,
                               QScrollArea, QSizePolicy, QVBoxLayout, QWidget)

from ...i18n import N_, _, ngettext
from ...logs import Log
from ...logs.model import Phase, charge_check_text, time_order_text
from ...logs.cycles import split_cycles
from ...logs.summary import summarize
from ...logs.window_stats import Between, between
from ..base import theme
from ..base.timefmt import duration, hmmss
from .log_plot import STATE_WORDS, LogPlot

SIDE_WIDTH = 250
SIDE_MAX_WIDTH = 400        # the side never takes the plot's width (its tables wrap below that)


def totals_html(name: str, info: dict, key_colour: str) -> str:
    """The side panel's summary of a log (``logs.summary``), as a small table, its names in ``key_colour``."""
    def num(value, fmt: str, unit: str) -> str:
        return "–" if value is None else f"{format(value, fmt)} {unit}"

    bad = info["bad_records"]
    rows = [(_("charger"), html.escape(info["device"])), (_("format"), info["format"]),
            (_("samples"), f"{info['samples']}" + (" " + _("({n} bad)").format(n=bad) if bad else "")),
            (_("length"), duration(info["duration_s"])),
            (_("voltage"), f"{num(info['v_min'], '.3f', '')}– {num(info['v_max'], '.3f', 'V')}"),
            (_("current max"), num(info["i_max_a"], ".2f", "A")),
            (_("charged"), num(info["charge_in_mah"], ".0f", "mAh")),
            (_("discharged"), num(info["charge_out_mah"], ".0f", "mAh"))]
    if info["t_max_c"] is not None:
        rows.append((_("temperature"), f"{info['t_min_c']:.1f} – {info['t_max_c']:.1f} °C"))
    else:
        rows.append((_("temperature"), _("no temperature in this log")))
    if info["cells"]:
        rows.append((_("cells"), str(info["cells"])))
    if "battery" in info:
        rows.append((_("battery"), html.escape(str(info["battery"]))))
    if "resistance" in info:
        r = info["resistance"]
        pack = "–" if r["last_pack_mohm"] is None else f"{r['last_pack_mohm']:.1f} mΩ"
        rows.append((_("resistance"), _("pack {pack}, cells {cells}").format(
            pack=pack, cells=" ".join(f"{c:.1f}" for c in r["last_cells_mohm"]))))
    rows.append((_("phases"), str(len(info["phases"]))))
    if info.get("record_sets"):
        rows.append((_("record sets"), str(len(info["record_sets"]))))
    body = "".join(f"<tr><td style='color:{key_colour}; padding-right:8px'>{k}</td><td>{v}</td></tr>" for k, v in rows)
    # What the figures above cannot say by themselves: the counter's disagreement, units assumed, time going back.
    notes = ([charge_check_text(info["charge_check"])] if "charge_check" in info else []) + \
        [_("assumed: {what}").format(what=line) for line in info.get("csv_assumed", ())] + \
        ([time_order_text(info["time_order"])] if "time_order" in info else [])
    said = "".join(f"<p>⚠ {html.escape(note)}</p>" for note in notes)
    return f"<b>{html.escape(name)}</b><table cellspacing='0' cellpadding='1'>{body}</table>{said}"


class HiddenCurves:
    """The curves a user hid, per log format (``curve_key``s), in the settings when there are
    any (else for this session)."""

    def __init__(self, settings: QSettings | None = None):
        self.settings = settings
        self._session: dict[str, set[str]] = {}

    def get(self, fmt: str) -> set[str]:
        if self.settings is None:
            return set(self._session.get(fmt, ()))
        value = self.settings.value(f"hiddenCurves/{fmt}")
        return {v for v in str(value).split(",") if v} if value else set()

    def put(self, fmt: str, keys: set[str]) -> None:
        if self.settings is None:
            self._session[fmt] = set(keys)
        else:
            self.settings.setValue(f"hiddenCurves/{fmt}", ",".join(sorted(keys)))


def _num(value: float | None, fmt: str, unit: str = "") -> str:
    return "–" if value is None else f"{format(value, fmt)}{unit}"


CURVE_UNITS = {"voltage": ("V", ".3f"), "current": ("A", ".3f"), "temp": ("°C", ".1f"), "heatsink": ("°C", ".1f"),
               "deviation": ("mV", ".0f")}


def between_html(b: Between, key_colour: str) -> str:
    """Cursors A and B: the differences and means, then per curve min, max and mean, charge, energy, time."""
    def row(key: str, value: str, mean: str) -> str:
        # a value without a mean takes both columns
        value_cell = (f"<td colspan='2' style='white-space:nowrap'>{value}</td>" if not mean else
                      f"<td style='padding-right:6px; white-space:nowrap'>{value}</td>")
        return (f"<tr><td style='color:{key_colour}; padding-right:6px'>{key}</td>{value_cell}"
                + (f"<td>{mean}</td>" if mean else "") + "</tr>")

    rows = [row(_("A → B"), f"{hmmss(b.start_s)} – {hmmss(b.end_s)}", ""),
            row("Δt", duration(b.time_s), ""),
            row("ΔV", _num(b.delta("voltage"), "+.3f", " V"), ""),
            row("ΔI", _num(b.delta("current"), "+.3f", " A"), ""),
            row("Δ mAh", _num(b.delta("net_mah"), "+.0f"), ""),
            row(_("charge"), _("in {into} / out {out} mAh").format(into=_num(b.charge_in_mah, ".0f"),
                                                                   out=_num(b.charge_out_mah, ".0f")), ""),
            row(_("energy"), _("in {into} / out {out} Wh").format(into=_num(b.energy_in_wh, ".2f"),
                                                                  out=_num(b.energy_out_wh, ".2f")), ""),
            row("", "<i>" + _("min – max") + "</i>", "<i>" + _("mean") + "</i>")]
    names = {"voltage": _("pack"), "current": _("current"), "temp": _("battery"), "heatsink": _("charger"),
             "deviation": _("deviation")}
    for name, st in b.curves.items():
        unit, fmt = CURVE_UNITS.get(name, ("V", ".3f"))
        label = names.get(name) or _("cell {n}").format(n=name.split()[1])
        rows.append(row(label, f"{format(st.min, fmt)} – {format(st.max, fmt)} {unit}", f"{format(st.mean, fmt)}"))
    note = "<p>" + _("a cursor is where the log has no data") + "</p>" if b.a is None or b.b is None else ""
    return f"<table cellspacing='0' cellpadding='0'>{''.join(rows)}</table>{note}"


@dataclass(frozen=True)
class Prepared:
    """What a document needs of its log besides drawing it, worked out off the GUI thread."""
    log: Log
    cycles: list[tuple[Phase, Log]]
    summary: dict


def prepare(log: Log) -> Prepared:
    """The slow, Qt-free part of opening a log (a 78 000-sample log takes about a second):
    its columns, phases, cycles and totals."""
    log.arrays()
    log.phases()
    cycles = split_cycles(log)
    for _phase, piece in cycles:
        piece.arrays()
    return Prepared(log, cycles, summarize(log))


class LogDocument(QWidget):
    addRequested = Signal()          # the user wants to lay another log file over this one

    def __init__(self, prepared: Prepared, path: str, parent=None, hidden: HiddenCurves | None = None):
        super().__init__(parent)
        self.hidden_store = hidden or HiddenCurves()
        self.setObjectName("logDocument")
        self.log = log = prepared.log
        self.path = path
        self.name = Path(path).name
        self.overlays: list[tuple[str, Log]] = []
        # Each cycle by its state and number in the user's language ("charge 2", "заряд 2").
        self.cycles = [(f"{_(STATE_WORDS[p.state])} {p.index}", piece) for p, piece in prepared.cycles]

        self.plot = LogPlot()
        self.readout = QLabel(_("move the mouse over the plot to read the log"))
        self.readout.setObjectName("logReadout")
        self.readout.setTextInteractionFlags(Qt.TextInteractionFlag.TextSelectableByMouse)
        self.readout.setStyleSheet("padding:2px 6px;")      # the palette's text colour: readable when dark too
        # A long readout (many cells, overlays) is cut at the window's edge, never widens it.
        self.readout.setSizePolicy(QSizePolicy.Policy.Ignored, QSizePolicy.Policy.Preferred)
        self.plot.cursorMoved.connect(lambda text: self.readout.setText(text or " "))

        self.totals = QLabel()
        self.totals.setObjectName("logTotals")
        self.totals.setWordWrap(True)
        self.totals.setAlignment(Qt.AlignmentFlag.AlignTop)
        self.totals.setTextInteractionFlags(Qt.TextInteractionFlag.TextSelectableByMouse)
        self.layer_list = QListWidget()
        self.layer_list.setObjectName("logLayers")
        self.layer_list.itemChanged.connect(lambda _item: self.redraw())
        if self.cycles:
            state = prepared.cycles[0][0].state
            text = ngettext("its {n} {state} phase, each from 0", "its {n} {state} phases, each from 0",
                            len(self.cycles)).format(n=len(self.cycles), state=_(STATE_WORDS.get(state, state)))
        else:
            text = _("its cycles, each from 0")
        self.cycles_box = QCheckBox(text)
        self.cycles_box.setEnabled(bool(self.cycles))
        self.cycles_box.setToolTip(_("each phase from time 0") if self.cycles else
                                   _("this log has fewer than two charge or discharge phases"))
        self.cycles_box.toggled.connect(lambda _on: self.redraw())
        add = QPushButton(_("Add a log to compare…"))
        add.clicked.connect(self.addRequested)
        self.curve_list = QListWidget()
        self.curve_list.setObjectName("logCurves")
        self.curve_list.setToolTip(_("untick a curve to hide it (kept for logs of this format)"))
        self.curve_list.itemChanged.connect(self._curve_ticked)
        self.cursors_box = QCheckBox(_("two cursors A and B"))
        self.cursors_box.setToolTip(_("drag the dashed lines A and B: what the log says between them"))
        self.cursors_box.toggled.connect(self._cursors_toggled)
        self.between = QLabel()
        self.between.setObjectName("logBetween")
        self.between.setWordWrap(True)
        self.between.setTextInteractionFlags(Qt.TextInteractionFlag.TextSelectableByMouse)
        self.between.setVisible(False)
        self.plot.cursorsMoved.connect(self._cursors_moved)

        side = QVBoxLayout()
        side.setContentsMargins(6, 4, 6, 4)
        side.addWidget(self.totals)
        side.addSpacing(6)
        side.addWidget(QLabel("<b>" + _("curves") + "</b>"))
        side.addWidget(self.curve_list, 1)
        side.addWidget(self.cursors_box)
        side.addWidget(self.between)
        side.addSpacing(6)
        side.addWidget(QLabel("<b>" + _("laid over") + "</b>"))
        side.addWidget(self.cycles_box)
        side.addWidget(self.layer_list, 1)
        side.addWidget(add)
        inner = QWidget()
        inner.setLayout(side)
        # The side scrolls when its figures are taller than the window: they never make it grow.
        panel = QScrollArea()
        panel.setWidget(inner)
        panel.setWidgetResizable(True)
        panel.setFrameShape(QFrame.Shape.NoFrame)
        panel.setHorizontalScrollBarPolicy(Qt.ScrollBarPolicy.ScrollBarAlwaysOff)
        # As wide as its figures need (Russian words run longer: a fixed 250 px cut them on the right).
        panel.setFixedWidth(min(max(SIDE_WIDTH, inner.sizeHint().width()), SIDE_MAX_WIDTH)
                            + panel.verticalScrollBar().sizeHint().width())
        panel.setSizePolicy(QSizePolicy.Policy.Fixed, QSizePolicy.Policy.Expanding)
        left = QVBoxLayout()
        left.setContentsMargins(0, 0, 0, 0)
        left.setSpacing(0)
        left.addWidget(self.plot, 1)
        left.addWidget(self.readout)
        row = QHBoxLayout(self)
        row.setContentsMargins(0, 0, 0, 0)
        row.addLayout(left, 1)
        row.addWidget(panel)
        self.summary = prepared.summary
        self._show_totals()
        self.plot.hidden = self.hidden_store.get(log.format)
        self.redraw()
        self._fill_curve_list()

    def _show_totals(self) -> None:
        self.totals.setText(totals_html(self.name, self.summary, theme.colours(self.palette()).key_text))

    def changeEvent(self, event) -> None:  # noqa: N802
        super().changeEvent(event)
        if event.type() == QEvent.Type.PaletteChange and hasattr(self, "summary"):
            self._show_totals()

    def add_overlay(self, name: str, log: Log) -> None:
        self.overlays.append((name, log))
        item = QListWidgetItem(name)
        item.setFlags(item.flags() | Qt.ItemFlag.ItemIsUserCheckable)
        item.setCheckState(Qt.CheckState.Checked)
        self.layer_list.addItem(item)      # itemChanged is not emitted for a new item
        self.redraw()

    def layers(self) -> list[tuple[str, Log]]:
        if self.cycles_box.isChecked():
            base = list(self.cycles)
        else:
            base = [(self.name, self.log)]
        for k, overlay in enumerate(self.overlays):
            item = self.layer_list.item(k)
            if item is not None and item.checkState() == Qt.CheckState.Checked:
                base.append(overlay)
        return base

    def redraw(self) -> None:
        cycles = self.cycles_box.isChecked()
        self.plot.show_layers(self.layers(), bands=not cycles and not self.overlays_shown())
        if self.cursors_box.isChecked():
            self.plot.show_cursors(True)

    # -- curves shown ------------------------------------------------------------------------
    def _fill_curve_list(self) -> None:
        self.curve_list.blockSignals(True)
        self.curve_list.clear()
        for key, name in self.plot.curve_keys():
            item = QListWidgetItem(name)
            item.setData(Qt.ItemDataRole.UserRole, key)
            item.setFlags(item.flags() | Qt.ItemFlag.ItemIsUserCheckable)
            item.setCheckState(Qt.CheckState.Unchecked if key in self.plot.hidden else Qt.CheckState.Checked)
            self.curve_list.addItem(item)
        self.curve_list.blockSignals(False)

    def set_curve_shown(self, key: str, shown: bool) -> None:
        for k in range(self.curve_list.count()):
            item = self.curve_list.item(k)
            if item.data(Qt.ItemDataRole.UserRole) == key:
                item.setCheckState(Qt.CheckState.Checked if shown else Qt.CheckState.Unchecked)

    def _curve_ticked(self, _item) -> None:
        hidden = {self.curve_list.item(k).data(Qt.ItemDataRole.UserRole) for k in range(self.curve_list.count())
                  if self.curve_list.item(k).checkState() != Qt.CheckState.Checked}
        self.plot.set_hidden(hidden)
        self.hidden_store.put(self.log.format, hidden)

    # -- cursors -----------------------------------------------------------------------------
    def _cursors_toggled(self, on: bool) -> None:
        self.between.setVisible(on)
        self.plot.show_cursors(on)

    def _cursors_moved(self, a: float, b: float) -> None:
        self.between.setText(between_html(between(self.log, a, b), theme.colours(self.palette()).key_text))

    def overlays_shown(self) -> bool:
        return any(self.layer_list.item(k).checkState() == Qt.CheckState.Checked
                   for k in range(self.layer_list.count()))
