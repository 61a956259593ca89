"""The visual macro editor: the macro as cards, a VIEW of the editor's text.

It owns no model. Every check result comes in through ``show_result`` (the main window
connects the validator's ``validated`` signal); a valid result (warnings allowed) is
shown as cards, while the text has errors the cards of the last valid version stay,
greyed, under a banner, and cannot be edited.

Every change made on a card is a text edit (``zuml_studio.lang.visual_edits``) applied to the
editor's QTextDocument as ONE minimal patch through one QTextCursor inside an edit
block: the editor, the bytes and the simulator follow through the normal check, the
comments and layout elsewhere stay, and the document's one undo history covers both
views (Ctrl+Z here undoes the last card edit, as in the editor).
"""
from __future__ import annotations

from typing import Callable

from PySide6.QtCore import QEvent, Qt, QTimer, Signal
from PySide6.QtGui import QKeySequence, QPalette, QTextCursor
from PySide6.QtWidgets import (QApplication, QBoxLayout, QComboBox, QFrame, QGridLayout, QHBoxLayout, QLabel,
                               QLineEdit, QMenu, QPlainTextEdit, QScrollArea, QSizePolicy, QSpinBox, QToolButton,
                               QVBoxLayout, QWidget)

from ...lang import visual_edits as ve
from ...i18n import N_, _, ngettext
from ...lang import opcodes as ops
from ...lang.ast import Cycle, Macro, Phase, Statement
from ...lang.compiler import CompileResult, compile_source
from ...lang.operands import AKK_TYPE, CAPACITY_AUTO, CAPACITY_INPUT, DISPLAY_NAMES
from .cards import CommandChip, CycleBox, PhaseCard, SectionColumn, _label, _tool
from .fields import make_field
from .style import style_sheet

HINT = N_("Drag a card (or use ▲ ▼) to reorder · right-click for more · Ctrl+Z undoes here and in the text")
STALE_BANNER = N_("The text has errors: showing the last valid version. Fix the text to edit here.")
ADDED_PHASE = {"charge": N_("Added a charge phase"), "discharge": N_("Added a discharge phase")}
NO_MACRO = N_("The text has errors and there is no valid version to show yet. Fix the text to edit here.")


def _utf16(text: str) -> int:
    return len(text.encode("utf-16-le")) // 2


class IntroForm(QFrame):
    """The introduction: name, battery type, cells, capacity; macro-wide limits as chips."""

    def __init__(self, host, parent: QWidget | None = None):
        super().__init__(parent)
        self.host = host
        self.setObjectName("introBox")
        self._setting = False

        self.name = QLineEdit()
        self.name.setObjectName("macroName")
        self.name.setMaxLength(16)
        self.name.setMinimumWidth(90)
        self.name.setToolTip(ops.MACRO.help)
        self.name.editingFinished.connect(self._name_done)

        self.akk = QComboBox()
        self.akk.setObjectName("akkType")
        self.akk.setToolTip(ops.AKK_TYPE.help)
        self.akk.addItem("—", None)
        for key in AKK_TYPE.names:
            self.akk.addItem(DISPLAY_NAMES.get(key, key), DISPLAY_NAMES.get(key, key))
        self.akk.activated.connect(self._akk_picked)

        self.series = QSpinBox()
        self.series.setObjectName("series")
        self.series.setToolTip(ops.SERIES.help + " " + _("'at start': not declared, entered on the charger."))
        self.series.setRange(0, 255)
        self.series.setSpecialValueText(_("at start"))
        self.series.setKeyboardTracking(False)
        self.series.setMinimumWidth(78)
        self.series.editingFinished.connect(self._series_done)
        self.series.valueChanged.connect(lambda _v: self._series_stepped())
        self._series_shown = None

        self.capacity = QSpinBox()
        self.capacity.setObjectName("capacity")
        self.capacity.setToolTip(ops.CAPACITY.help)
        self.capacity.setRange(1, 65534)            # 1: not a fixed capacity, shown as "—"
        self.capacity.setSpecialValueText("—")
        self.capacity.setSuffix(" mAh")
        self.capacity.setKeyboardTracking(False)
        self.capacity.setMinimumWidth(92)
        self.capacity.editingFinished.connect(self._capacity_done)
        self.capacity.valueChanged.connect(lambda _v: self._capacity_stepped())
        self.capacity_mode = QComboBox()
        self.capacity_mode.setObjectName("capacityMode")
        for label, key, tip in ((_("fixed"), "mAh", _("a fixed capacity")),
                                ("INPUT", "INPUT", _("entered on the charger at start")),
                                ("AUTO", "AUTO", _("measured by the charger")),
                                ("—", None, _("not declared"))):
            self.capacity_mode.addItem(label, key)
            self.capacity_mode.setItemData(self.capacity_mode.count() - 1, tip, Qt.ItemDataRole.ToolTipRole)
        self.capacity_mode.activated.connect(self._capacity_mode_picked)
        self._capacity_shown = None

        grid = QGridLayout()
        grid.setHorizontalSpacing(6)
        grid.setVerticalSpacing(6)
        pairs = [(_("Macro"), self.name), (_("Battery"), self.akk), (_("Cells"), self.series)]
        col = 0
        for text, widget in pairs:
            grid.addWidget(_label(text), 0, col)
            grid.addWidget(widget, 0, col + 1)
            col += 2
        grid.addWidget(_label(_("Capacity")), 0, col)
        cap = QHBoxLayout()
        cap.setSpacing(4)
        cap.addWidget(self.capacity)
        cap.addWidget(self.capacity_mode)
        grid.addLayout(cap, 0, col + 1)
        grid.setColumnStretch(col + 2, 1)

        self.limits_row = QHBoxLayout()
        self.limits_row.setSpacing(6)
        self.limits_label = _label(_("Limits"))
        self.limits_label.setToolTip(_("Macro-wide conditions (heat-sink temperature, total time)"))
        self.add_limit = _tool("+ " + _("Limit"), _("Add a macro-wide condition"), "add", name="addLimit")
        self.add_limit.setPopupMode(QToolButton.ToolButtonPopupMode.InstantPopup)
        self.add_limit_menu = QMenu(self.add_limit)
        self.add_limit.setMenu(self.add_limit_menu)
        self.chips: list[QWidget] = []
        self.chip_box = QHBoxLayout()
        self.chip_box.setSpacing(6)
        self.limits_row.addWidget(self.limits_label)
        self.limits_row.addLayout(self.chip_box)
        self.limits_row.addWidget(self.add_limit)
        self.limits_row.addStretch(1)

        layout = QVBoxLayout(self)
        layout.setContentsMargins(10, 8, 10, 8)
        layout.setSpacing(6)
        layout.addLayout(grid)
        layout.addLayout(self.limits_row)
        self._chip_ops: tuple = ()

    # -- showing ---------------------------------------------------------------------------
    def bind(self, macro: Macro) -> None:
        self._setting = True
        try:
            if not self.name.hasFocus():
                self.name.setText(macro.name)
            akk = macro.declared(ops.AKK_TYPE)
            self.akk.setCurrentIndex(self.akk.findData(AKK_TYPE.format(akk.args[0].raw)) if akk else 0)
            series = macro.declared(ops.SERIES)
            if not self.series.hasFocus():
                self.series.setValue(series.args[0].raw if series else 0)
            self._series_shown = self.series.value()
            cap = macro.declared(ops.CAPACITY)
            raw = cap.args[0].raw if cap else None
            mode = None if raw is None else "INPUT" if raw == CAPACITY_INPUT else "AUTO" if raw == CAPACITY_AUTO \
                else "mAh"
            self.capacity_mode.setCurrentIndex(self.capacity_mode.findData(mode))
            if not self.capacity.hasFocus():
                self.capacity.setValue(raw if mode == "mAh" else 1)
            self.capacity.setVisible(mode == "mAh")
            self._capacity_shown = self.capacity.value() if mode == "mAh" else None
        finally:
            self._setting = False
        self._bind_limits(macro)

    def _bind_limits(self, macro: Macro) -> None:
        present = [(i, st) for i, st in enumerate(macro.intro) if st.op.condition]
        key = tuple((i, st.op.code) for i, st in present)
        if key != self._chip_ops:
            for chip in self.chips:
                chip.setParent(None)
                chip.deleteLater()
            self.chips = []
            for i, st in present:
                chip = QFrame()
                chip.setObjectName("conditionChip")
                chip.setToolTip(st.op.help)
                row = QHBoxLayout(chip)
                row.setContentsMargins(10, 2, 4, 2)
                row.setSpacing(4)
                words = ve.intro_condition_phrase(st)
                row.addWidget(_label(words.rsplit(" ", 2)[0] if st.op.condition.variables[0] == "Tc"
                                     else _("Stop after"), "field"))
                field = make_field(st.op.operands[0])
                field.setObjectName("limitField")
                field.committed.connect(lambda text, i=i: self.host.edit_value(("intro", i), 0, text))
                row.addWidget(field)
                remove = _tool("✕", _("Remove this limit"), "remove", name="removeLimit")
                remove.clicked.connect(lambda _=False, i=i: self.host.remove_statement(("intro", i)))
                row.addWidget(remove)
                chip.field = field
                self.chip_box.addWidget(chip)
                self.chips.append(chip)
            self._chip_ops = key
        for chip, (i, st) in zip(self.chips, present):
            if not chip.field.busy():
                chip.field.set_raw(st.args[0].raw)
        self.add_limit_menu.clear()
        have = {st.op for st in macro.intro}
        missing = [op for op in ve.intro_conditions() if op not in have]
        for op in missing:
            action = self.add_limit_menu.addAction(op.help.rstrip("."))
            action.setData(op.code)
            action.triggered.connect(lambda _=False, op=op: self.host.set_declaration(op, ve.default_value(op)))
        self.add_limit.setEnabled(bool(missing))

    # -- editing ---------------------------------------------------------------------------
    def _name_done(self) -> None:
        if self.name.isModified():
            self.name.setModified(False)
            self.host.set_name(self.name.text())

    def _akk_picked(self, index: int) -> None:
        value = self.akk.itemData(index)
        if value is None:
            self.host.remove_declaration(ops.AKK_TYPE)
        else:
            self.host.set_declaration(ops.AKK_TYPE, value)

    def _series_stepped(self) -> None:
        if not self._setting and not self.series.lineEdit().hasFocus():
            self._series_done()

    def _series_done(self) -> None:
        if self._setting or self.series.value() == self._series_shown:
            return
        self._series_shown = self.series.value()
        if self.series.value() == 0:
            self.host.remove_declaration(ops.SERIES)
        else:
            self.host.set_declaration(ops.SERIES, str(self.series.value()))

    def _capacity_stepped(self) -> None:
        if not self._setting and not self.capacity.lineEdit().hasFocus():
            self._capacity_done()

    def _capacity_done(self) -> None:
        if (self._setting or self.capacity_mode.currentData() != "mAh" or self.capacity.value() < 2
                or self.capacity.value() == self._capacity_shown):
            return
        self._capacity_shown = self.capacity.value()
        self.host.set_declaration(ops.CAPACITY, str(self.capacity.value()))

    def _capacity_mode_picked(self, index: int) -> None:
        mode = self.capacity_mode.itemData(index)
        self.capacity.setVisible(mode == "mAh")
        if mode is None:
            self.host.remove_declaration(ops.CAPACITY)
        elif mode == "mAh":
            if self.capacity.value() < 2:
                self._setting = True
                self.capacity.setValue(1000)
                self._setting = False
            self._capacity_shown = self.capacity.value()
            self.host.set_declaration(ops.CAPACITY, str(self.capacity.value()))
        else:
            self.host.set_declaration(ops.CAPACITY, mode)


def _chip_box(name: str, label: str) -> tuple[QWidget, QHBoxLayout]:
    """A labelled row of command chips (between the sections, at the end)."""
    box = QWidget()
    box.setObjectName(name)
    row = QHBoxLayout()
    row.setSpacing(6)
    inner = QHBoxLayout(box)
    inner.setContentsMargins(4, 0, 4, 0)
    inner.addWidget(_label(label))
    inner.addLayout(row)
    inner.addStretch(1)
    return box, row


class VisualEditor(QWidget):
    """Cards of the macro in ``editor``; edits go to the editor's document as text patches."""

    statusMessage = Signal(str)

    def __init__(self, editor: QPlainTextEdit, parent: QWidget | None = None):
        super().__init__(parent)
        self.setObjectName("visualEditor")
        self.setAttribute(Qt.WidgetAttribute.WA_StyledBackground, True)
        self._sheet = style_sheet(QApplication.palette())
        self.setStyleSheet(self._sheet)
        QApplication.instance().paletteChanged.connect(self._follow_palette)
        self.setFocusPolicy(Qt.FocusPolicy.ClickFocus)
        self.editor = editor
        self._valid: CompileResult | None = None      # the result the cards show
        self._stale = False
        self._shape: tuple | None = None
        self.items: dict[tuple, QWidget] = {}         # path -> card / cycle box / chip
        self._note: str | None = None                 # a rounding note from the last value edit

        self.banner = QLabel(_(STALE_BANNER))
        self.banner.setObjectName("visualBanner")
        self.banner.setWordWrap(True)
        self.banner.hide()

        self.intro = IntroForm(self)
        self.columns = {kind: SectionColumn(self, kind) for kind in ("discharge", "charge")}
        self.between_box, self.between_row = _chip_box("betweenBox", _("Between the sections"))
        self.between_chips: list[CommandChip] = []
        self.conclusion_box, self.conclusion_row = _chip_box("conclusionBox", _("At the end"))
        self.conclusion_chips: list[CommandChip] = []

        self.content = QWidget()
        self.content.setObjectName("visualContent")
        self.cols = QBoxLayout(QBoxLayout.Direction.LeftToRight)
        self.cols.setSpacing(12)
        for column in self.columns.values():
            column.setSizePolicy(QSizePolicy.Policy.Expanding, QSizePolicy.Policy.Preferred)
            self.cols.addWidget(column, 1, Qt.AlignmentFlag.AlignTop)
        body = QVBoxLayout(self.content)
        body.setContentsMargins(8, 10, 8, 10)
        body.setSpacing(10)
        body.addLayout(self.cols)
        body.addWidget(self.between_box)
        body.addWidget(self.conclusion_box)
        body.addStretch(1)

        self.scroll = QScrollArea()
        self.scroll.setObjectName("visualScroll")
        self.scroll.setWidgetResizable(True)
        self.scroll.setFrameShape(QFrame.Shape.NoFrame)
        self.scroll.setHorizontalScrollBarPolicy(Qt.ScrollBarPolicy.ScrollBarAsNeeded)
        self.scroll.setWidget(self.content)
        self.scroll.viewport().installEventFilter(self)

        self.status = QLabel(_(HINT))
        self.status.setObjectName("visualStatus")
        self.status.setWordWrap(True)

        layout = QVBoxLayout(self)
        layout.setContentsMargins(8, 8, 8, 6)
        layout.setSpacing(8)
        layout.addWidget(self.banner)
        layout.addWidget(self.intro)
        layout.addWidget(self.scroll, 1)
        layout.addWidget(self.status)
        self._set_editable(False)

    def eventFilter(self, watched, event) -> bool:
        if watched is self.scroll.viewport() and event.type() == QEvent.Type.Resize:
            self._fit_columns()
        return super().eventFilter(watched, event)

    def side_by_side_missing(self) -> int:
        """How many pixels of width the sections lack to stand side by side (0: they fit)."""
        margins = self.content.layout().contentsMargins()
        side_by_side = (sum(c.minimumSizeHint().width() for c in self.columns.values()) + self.cols.spacing()
                        + margins.left() + margins.right())
        return max(0, side_by_side - self.scroll.viewport().width())

    def _fit_columns(self) -> None:
        """The sections side by side when both fit the width, else one above the other: the
        cards never need a horizontal scroll bar (only a card wider than the whole view would)."""
        direction = (QBoxLayout.Direction.LeftToRight if not self.side_by_side_missing()
                     else QBoxLayout.Direction.TopToBottom)
        if self.cols.direction() != direction:
            self.cols.setDirection(direction)

    def _follow_palette(self, palette: QPalette) -> None:
        # Its own palette is the sheet's, so no PaletteChange tells it: the application's palette
        # (the one the theme sets) does. Compared first: applying a sheet re-polishes everything.
        sheet = style_sheet(palette)
        if sheet != self._sheet:
            self._sheet = sheet
            self.setStyleSheet(sheet)

    # -- results in --------------------------------------------------------------------------
    def show_result(self, result: CompileResult | None) -> None:
        """Show a check result: cards from a valid macro, else the last valid cards greyed."""
        if result is None:
            return
        if result.ok and result.macro is not None:
            self._valid = result
            self._stale = False
            self.banner.hide()
            self._set_editable(True)
            self._show(result.macro)
        else:
            self._stale = True
            self.banner.setText(_(STALE_BANNER) if self._valid else _(NO_MACRO))
            self.banner.show()
            self._set_editable(False)

    def macro(self) -> Macro | None:
        """The macro the cards show (the last valid one)."""
        return self._valid.macro if self._valid else None

    def is_stale(self) -> bool:
        return self._stale

    def _set_editable(self, editable: bool) -> None:
        self.content.setEnabled(editable)
        self.intro.setEnabled(editable)

    def _show(self, macro: Macro) -> None:
        new_shape = ve.shape(macro)
        if new_shape != self._shape:
            self._rebuild(macro)
            self._shape = new_shape
        self._bind(macro)

    def _rebuild(self, macro: Macro) -> None:
        focus_inside = self.content.isAncestorOf(self.focusWidget()) if self.focusWidget() else False
        scroll = self.scroll.verticalScrollBar().value()
        self.items = {}
        for kind, column in self.columns.items():
            column.clear_items()
            section = getattr(macro, kind)
            for i, item in enumerate(section.items):
                column.add_item(self._make(item, (kind, i), kind))
        self.between_chips = self._chips("between", macro.between, self.between_row, self.between_chips)
        self.between_box.setVisible(bool(macro.between))
        self.conclusion_chips = self._chips("conclusion", macro.conclusion, self.conclusion_row,
                                            self.conclusion_chips)
        self.conclusion_box.setVisible(bool(macro.conclusion))
        self._fit_columns()
        if focus_inside:
            self.setFocus()
        # Restored once the new cards are laid out; bound to the scroll bar so a view closed
        # meanwhile cancels it.
        bar = self.scroll.verticalScrollBar()
        QTimer.singleShot(0, bar, lambda: bar.setValue(scroll))

    def _chips(self, head: str, statements: list, row: QHBoxLayout, old: list) -> list:
        for chip in old:
            chip.setParent(None)
            chip.deleteLater()
        chips = []
        for i, st in enumerate(statements):
            chip = CommandChip(self, (head, i), st, movable=False)
            row.addWidget(chip)
            chips.append(chip)
            self.items[(head, i)] = chip
        return chips

    def _make(self, item, path: tuple, kind: str) -> QWidget:
        if isinstance(item, Phase):
            widget = PhaseCard(self, path, kind, item)
        elif isinstance(item, Cycle):
            widget = CycleBox(self, path, kind)
            for j, inner in enumerate(item.items):
                widget.add_item(self._make(inner, path + (j,), kind))
        else:
            widget = CommandChip(self, path, item)
        self.items[path] = widget
        return widget

    def _bind(self, macro: Macro) -> None:
        self.intro.bind(macro)
        for kind, column in self.columns.items():
            section = getattr(macro, kind)
            numbers = {id(p): n for n, p in enumerate(section.phases(), start=1)}
            self._bind_items(section.items, (kind,), numbers)
            column.set_empty_text(section.present, len(section.items), len(section.phases()))
        for head in ("between", "conclusion"):
            for i, st in enumerate(getattr(macro, head)):
                self.items[(head, i)].bind(st, True, True)

    def _bind_items(self, items: list, prefix: tuple, numbers: dict) -> None:
        for i, item in enumerate(items):
            path = prefix + (i,)
            widget = self.items[path]
            first, last = i == 0, i == len(items) - 1
            if isinstance(item, Phase):
                widget.bind(item, numbers[id(item)], first, last)
            elif isinstance(item, Cycle):
                widget.bind(item, first, last)
                self._bind_items(item.items, path, numbers)
            else:
                widget.bind(item, first, last)

    # -- the one way a card changes the text ------------------------------------------------
    def apply(self, edit: Callable[[str, Macro], str], done: str = "") -> bool:
        """Run ``edit(text, macro)`` on the editor's current text and apply the result as one
        undoable patch. Refused (with a message) while the text has errors, or when the new
        text would not be valid."""
        text = self.editor.toPlainText()
        current = compile_source(text)
        if self._stale or not current.ok:
            self.say(_("The text has errors: fix the text to edit here."), problem=True)
            return False
        try:
            new = edit(text, current.macro)
        except (ve.EditError, LookupError) as exc:
            self.say(str(exc), problem=True)
            self._bind(self._valid.macro)            # fields show the stored values again
            return False
        if new == text:
            return False
        check = compile_source(new)
        if not check.ok:
            first = check.errors[0]
            self.say(_("Not changed: {reason}").format(reason=first.message) + (f" ({first.hint})" if first.hint else ""),
                     problem=True)
            self._bind(self._valid.macro)
            return False
        self.patch_document(text, new)
        dropped = ve.dropped_comments(text, new)
        message = done
        if dropped:
            message = (message + ". " if message else "") + ngettext(
                "Removed comment: {comments}", "Removed comments: {comments}", len(dropped)).format(
                comments="; ".join(dropped))
        self.say(message, problem=False)
        self.show_result(check)
        return True

    def patch_document(self, old: str, new: str) -> None:
        """Replace only what differs between ``old`` (the document's text) and ``new``:
        one cursor, one edit block, so one undo step and the editor's cursor keeps its place."""
        start, end, insert = ve.common_patch(old, new)
        a = _utf16(old[:start])
        b = a + _utf16(old[start:end])
        cursor = QTextCursor(self.editor.document())
        cursor.beginEditBlock()
        cursor.setPosition(a)
        cursor.setPosition(b, QTextCursor.MoveMode.KeepAnchor)
        cursor.insertText(insert)
        cursor.endEditBlock()

    def say(self, message: str, problem: bool = False) -> None:
        self.status.setText(message or _(HINT))
        self.status.setProperty("problem", problem)
        self.status.style().unpolish(self.status)
        self.status.style().polish(self.status)
        if message:
            self.statusMessage.emit(message)

    # -- what the cards ask for --------------------------------------------------------------
    def edit_value(self, path: tuple, index: int, value_text: str) -> bool:
        def edit(text: str, macro: Macro) -> str:
            st: Statement = ve.node_at(macro, path)
            _raw, note = ve.parse_value(st.op.operands[index], value_text)
            self._note = note
            return ve.set_value(text, st, index, value_text)
        self._note = None
        ok = self.apply(edit)
        if ok and self._note:
            self.say(self._note)
        return ok

    def set_action(self, path: tuple, key: str) -> bool:
        return self.apply(lambda text, m: ve.set_action(text, ve.node_at(m, path), key, m, path[0]),
                          _("Action: {action}").format(action=key))

    def add_condition(self, path: tuple, op) -> bool:
        def edit(text: str, macro: Macro) -> str:
            return ve.add_condition(text, ve.node_at(macro, path), op, ve.default_value(op, macro, path[0]))
        return self.apply(edit, _("Added {command}").format(command=op.signature()))

    def remove_statement(self, path: tuple) -> bool:
        return self.apply(lambda text, m: ve.remove_statement(text, ve.node_at(m, path)), _("Removed"))

    def move_item(self, path: tuple, delta: int) -> bool:
        container_path, index = tuple(path[:-1]), path[-1]

        def edit(text: str, macro: Macro) -> str:
            container = ve.node_at(macro, container_path)
            to = index + delta
            if not 0 <= to < len(container.items):
                return text
            return ve.move_item(text, container, index, to)
        return self.apply(edit, _("Moved"))

    def drop_item(self, container_path: tuple, from_index: int, to_index: int) -> bool:
        """What a drop does: item ``from_index`` of the section or cycle goes to ``to_index``."""
        return self.apply(lambda text, m: ve.move_item(text, ve.node_at(m, tuple(container_path)), from_index,
                                                       to_index), _("Moved"))

    def wrap(self, path: tuple, count: int = 2) -> bool:
        return self.apply(lambda text, m: ve.wrap_in_cycle(text, ve.node_at(m, path), count),
                          _("Wrapped in {cycle}").format(cycle=f"CYCLE({count})"))

    def unwrap(self, path: tuple) -> bool:
        return self.apply(lambda text, m: ve.unwrap_cycle(text, ve.node_at(m, path)), _("Cycle removed"))

    def remove_from_cycle(self, path: tuple) -> bool:
        return self.apply(lambda text, m: ve.remove_from_cycle(text, ve.node_at(m, tuple(path[:-1])), path[-1]),
                          _("Taken out of the cycle"))

    def set_cycle_count(self, path: tuple, count: int) -> bool:
        return self.apply(lambda text, m: ve.set_cycle_count(text, ve.node_at(m, path), count))

    def delete_item(self, path: tuple) -> bool:
        return self.apply(lambda text, m: ve.delete_item(text, ve.node_at(m, path)), _("Deleted"))

    def add_phase(self, kind: str) -> bool:
        return self.apply(lambda text, m: ve.add_phase(text, m, kind), _(ADDED_PHASE[kind]))

    def set_declaration(self, op, value_text: str) -> bool:
        return self.apply(lambda text, m: ve.set_declaration(text, m, op, value_text))

    def remove_declaration(self, op) -> bool:
        return self.apply(lambda text, m: ve.remove_declaration(text, m, op))

    def set_name(self, name: str) -> bool:
        return self.apply(lambda text, m: ve.set_name(text, m, name))

    def goto(self, path: tuple) -> None:
        """Put the editor's cursor on the node's first line (a phase: its FAZE)."""
        result = compile_source(self.editor.toPlainText())
        try:
            node = ve.node_at(result.macro, path) if result.macro else None
        except LookupError:
            node = None
        if node is None or node.span is None:
            return
        line, column = node.span.line, node.span.column
        if hasattr(self.editor, "goto"):
            self.editor.goto(line, column)
        else:
            block = self.editor.document().findBlockByNumber(line - 1)
            cursor = QTextCursor(block)
            cursor.setPosition(block.position() + column - 1)
            self.editor.setTextCursor(cursor)

    # -- keys --------------------------------------------------------------------------------
    def keyPressEvent(self, event) -> None:
        """Ctrl+Z / Ctrl+Shift+Z here undo and redo in the document (one history for both views)."""
        if event.matches(QKeySequence.StandardKey.Undo):
            self.editor.undo()
            event.accept()
            return
        if event.matches(QKeySequence.StandardKey.Redo):
            self.editor.redo()
            event.accept()
            return
        super().keyPressEvent(event)
