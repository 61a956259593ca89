"""Completion by context, read from the opcode table.

At a line's start every statement form is one insertion up to where the user's own value
starts (``CONSTANT_I=``, ``CHARGE_EX(``, ``IF(V>``, ``FAZE``); after ``KEYWORD=`` or inside
``KEYWORD(`` the words that operand accepts (``INPUT``, ``LiPo``, ``STOP``…); inside ``IF(`` the
variables, after ``IF(…)`` the outcomes. The popup filters case-insensitively on the word
before the cursor; accepting replaces the whole word the cursor stands in, without doubling
an ``=`` or ``(`` already written after it.
"""
from __future__ import annotations

import re
from typing import NamedTuple

from PySide6.QtCore import QModelIndex, Qt
from PySide6.QtGui import QStandardItem, QStandardItemModel, QTextCursor
from PySide6.QtWidgets import QCompleter, QPlainTextEdit

from ...i18n import _
from ...lang import opcodes, operands
from ...lang.opcodes import Form
from .highlighter import SYMBOLIC_VALUES

MIN_PREFIX = 2          # letters typed before the popup opens by itself
DETAIL_ROLE = Qt.ItemDataRole.ToolTipRole


class CompletionItem(NamedTuple):
    text: str           # what is inserted
    detail: str         # signature and help, shown as the item's tooltip


def _is_word_char(ch: str) -> bool:
    return ch.isalnum() or ch == "_"


def word_before(text: str, column: int) -> str:
    """The word ending at 0-based ``column`` of a line, '' when there is none or when it is the
    unit of a number (the ``C`` of ``1C``) or the cursor is in a comment."""
    if "//" in text[:column]:
        return ""
    start = column
    while start > 0 and _is_word_char(text[start - 1]):
        start -= 1
    word = text[start:column]
    if not word or not (word[0].isalpha() or word[0] == "_"):
        return ""
    if start > 0 and text[start - 1] == ".":
        return ""
    return word


def word_after(text: str, column: int) -> str:
    """The rest of the word the cursor stands in (what completion replaces with the prefix)."""
    end = column
    while end < len(text) and _is_word_char(text[end]):
        end += 1
    return text[column:end]


# -- context: what may stand where the word is being typed ---------------------------------------

_ASSIGNED = re.compile(r"\s*([A-Za-z_]\w*)\s*=\s*$")
_IF_OPEN = re.compile(r"\s*IF\s*\(\s*$", re.IGNORECASE)
_IF_CLOSED = re.compile(r"\s*IF\s*\(.*\)\s*$", re.IGNORECASE)
_CALL_ARGS = re.compile(r"\s*([A-Za-z_]\w*)\s*\(([^()]*)$")


def _operand_values(operand: opcodes.Operand) -> list[str]:
    """The words an operand accepts besides numbers, canonically spelt (INPUT, AUTO, LiPo, STOP…)."""
    out = []
    for word in SYMBOLIC_VALUES.values():
        try:
            operand.kind.parse(word, operand.lo, operand.hi)
        except operands.ValueProblem:
            continue
        out.append(word)
    return out


def _statement_items() -> list[CompletionItem]:
    items: list[CompletionItem] = []
    for op in opcodes.OPCODES:
        detail = f"{op.signature()}\n{op.help}"
        if op.condition:
            c = op.condition
            items.append(CompletionItem(f"IF({c.variables[0]}{c.comparison}", detail))
        elif op.form is Form.ASSIGN:
            items.append(CompletionItem(f"{op.keyword}=", detail))
        elif op.form is Form.CALL:
            items.append(CompletionItem(f"{op.keyword}(", detail))
        else:
            items.append(CompletionItem(op.keyword, detail))
    return items


def _condition_items() -> list[CompletionItem]:
    """Inside ``IF(``: the variable and its comparison."""
    return [CompletionItem(f"{op.condition.variables[0]}{op.condition.comparison}", f"{op.signature()}\n{op.help}")
            for op in opcodes.CONDITIONS]


def _outcome_items() -> list[CompletionItem]:
    out = []
    for outcome in sorted(opcodes.CONDITION_OUTCOMES):
        ops = [op for op in opcodes.CONDITIONS if op.condition.outcome == outcome]
        out.append(CompletionItem(outcome, _("Outcome of {commands}").format(
            commands=", ".join(op.signature() for op in ops))))
    return out


def _value_items(op: opcodes.Op | None, index: int) -> list[CompletionItem]:
    if op is None or not 0 <= index < len(op.operands):
        return []
    operand = op.operands[index]
    detail = _("{operand} of {command}: {what}").format(operand=operand.name, command=op.signature(),
                                                      what=operand.kind.what)
    return [CompletionItem(word, detail) for word in _operand_values(operand)]


def items_at(text: str, column: int) -> list[CompletionItem]:
    """What may be written at 0-based ``column`` of a line, given the text before the word
    there: statements at the line start, the operand's words after ``KEYWORD=`` or inside
    ``KEYWORD(``, a variable inside ``IF(``, an outcome after ``IF(…)``; nothing elsewhere
    (after ``MACRO``, in a number, in a comment)."""
    if "//" in text[:column]:
        return []
    start = column - len(word_before(text, column))
    before = text[:start]
    if not before.strip():
        return _dedupe(_statement_items())
    if _IF_OPEN.match(before):
        return _condition_items()
    if _IF_CLOSED.match(before):
        return _outcome_items()
    m = _ASSIGNED.match(before)
    if m:
        return _value_items(opcodes.BY_KEYWORD.get(m.group(1).upper()), 0)
    m = _CALL_ARGS.match(before)
    if m and m.group(1).upper() != "IF":
        return _value_items(opcodes.BY_KEYWORD.get(m.group(1).upper()), m.group(2).count(","))
    return []


def _dedupe(items: list[CompletionItem]) -> list[CompletionItem]:
    seen: set[str] = set()
    out = []
    for item in items:
        if item.text.upper() not in seen:
            seen.add(item.text.upper())
            out.append(item)
    return out


def completion_items() -> list[CompletionItem]:
    """Every item any context offers: statement forms in table order, condition variables,
    outcomes, then symbolic values."""
    values = [CompletionItem(word, "value") for word in SYMBOLIC_VALUES.values()]
    return _dedupe(_statement_items() + _condition_items() + _outcome_items() + values)


class ZumlCompleter(QCompleter):
    """A popup completer bound to one QPlainTextEdit. The editor forwards its key presses:
    ``handle_key`` before its own handling, ``after_key`` after it."""

    def __init__(self, editor: QPlainTextEdit):
        self._model = QStandardItemModel(editor)
        super().__init__(self._model, editor)
        self.setObjectName("editorCompleter")
        self.editor = editor
        self._shown: list[CompletionItem] = []
        self.setWidget(editor)
        self.setCompletionMode(QCompleter.CompletionMode.PopupCompletion)
        self.setCaseSensitivity(Qt.CaseSensitivity.CaseInsensitive)
        self.setMaxVisibleItems(10)
        self.popup().setFont(editor.font())
        self.activated[QModelIndex].connect(self._activated)
        self._explicit = False

    def _offer(self, items: list[CompletionItem]) -> None:
        """Fill the model with this context's items (unchanged items keep the popup's state)."""
        if items == self._shown:
            return
        self._shown = items
        self._model.clear()
        for item in items:
            row = QStandardItem(item.text)
            row.setData(item.detail, DETAIL_ROLE)
            row.setEditable(False)
            self._model.appendRow(row)

    # -- queries --------------------------------------------------------------------------
    def items(self) -> list[str]:
        model = self.model()
        return [model.index(r, 0).data() for r in range(model.rowCount())]

    def is_open(self) -> bool:
        return self.popup().isVisible()

    def current_text(self) -> str | None:
        index = self.popup().currentIndex()
        if not index.isValid():
            index = self.completionModel().index(0, 0)
        return index.data() if index.isValid() else None

    def _prefix_at_cursor(self) -> str:
        cursor = self.editor.textCursor()
        return word_before(cursor.block().text(), cursor.positionInBlock())

    # -- opening and filtering --------------------------------------------------------------
    def open(self, explicit: bool = True) -> bool:
        """Show the popup for the word before the cursor (Ctrl+Space: even for no word)."""
        self._explicit = explicit
        return self._refresh()

    def _refresh(self) -> bool:
        prefix = self._prefix_at_cursor()
        if not self._explicit and len(prefix) < MIN_PREFIX:
            self.close()
            return False
        cursor = self.editor.textCursor()
        self._offer(items_at(cursor.block().text(), cursor.positionInBlock()))
        self.setCompletionPrefix(prefix)
        count = self.completionCount()
        model = self.completionModel()
        exact_only = count == 1 and model.index(0, 0).data().upper() == prefix.upper()
        if count == 0 or (exact_only and not self._explicit):
            self.close()
            return False
        # The word as typed, when it is an item, is the current one (so Return ends the line).
        row = next((r for r in range(count) if model.index(r, 0).data().upper() == prefix.upper()), 0)
        popup = self.popup()
        popup.setCurrentIndex(model.index(row, 0))
        rect = self.editor.cursorRect()
        rect.translate(self.editor.viewport().pos())
        rect.moveLeft(rect.left() - self.editor.fontMetrics().horizontalAdvance(prefix))
        rect.setWidth(popup.sizeHintForColumn(0) + popup.verticalScrollBar().sizeHint().width() + 16)
        self.complete(rect)
        return True

    def close(self) -> None:
        self._explicit = False
        if self.popup().isVisible():
            self.popup().hide()

    # -- keys ---------------------------------------------------------------------------
    def handle_key(self, key: int, modifiers) -> bool:
        """A key pressed while the popup is open; True when the popup used it."""
        if not self.is_open():
            return False
        Key = Qt.Key
        if key in (Key.Key_Return, Key.Key_Enter, Key.Key_Tab):
            chosen = self.current_text()
            if key != Key.Key_Tab and chosen is not None and chosen.upper() == self._prefix_at_cursor().upper():
                self.close()             # the word is already complete: Return is a new line
                return False
            if chosen is not None:
                self.insert(chosen)
            self.close()
            return True
        if key == Key.Key_Escape:
            self.close()
            return True
        if key in (Key.Key_Up, Key.Key_Down, Key.Key_PageUp, Key.Key_PageDown):
            popup = self.popup()
            rows = self.completionModel().rowCount()
            row = popup.currentIndex().row()
            step = {Key.Key_Up: -1, Key.Key_Down: 1, Key.Key_PageUp: -self.maxVisibleItems(),
                    Key.Key_PageDown: self.maxVisibleItems()}[key]
            row = min(max(0, row + step), rows - 1)
            popup.setCurrentIndex(self.completionModel().index(row, 0))
            return True
        return False

    def after_key(self, key: int, text: str) -> None:
        """The editor handled a key: open, filter or close the popup."""
        if text and _is_word_char(text):
            self._refresh() if self.is_open() else self.open(explicit=False)
        elif key in (Qt.Key.Key_Backspace, Qt.Key.Key_Delete) and self.is_open():
            self._refresh()
        elif key not in (Qt.Key.Key_Shift, Qt.Key.Key_Control, Qt.Key.Key_Alt, Qt.Key.Key_Meta):
            self.close()

    # -- accepting ------------------------------------------------------------------------
    def insert(self, text: str) -> None:
        """Replace the word the cursor stands in with ``text`` (one undo step); an ``=``, ``(``
        or comparison that ``text`` ends with and the line already has next is not doubled."""
        cursor = self.editor.textCursor()
        line, column = cursor.block().text(), cursor.positionInBlock()
        prefix = word_before(line, column)
        rest = word_after(line, column)
        tail = text[len(text.rstrip("=(<>")):]
        following = line[column + len(rest):]
        while tail and not following.startswith(tail):
            tail = tail[1:]
        cursor.beginEditBlock()
        cursor.clearSelection()
        cursor.movePosition(QTextCursor.MoveOperation.Left, QTextCursor.MoveMode.MoveAnchor, len(prefix))
        cursor.movePosition(QTextCursor.MoveOperation.Right, QTextCursor.MoveMode.KeepAnchor,
                            len(prefix) + len(rest))
        cursor.insertText(text[:len(text) - len(tail)] if tail else text)
        cursor.endEditBlock()
        cursor.movePosition(QTextCursor.MoveOperation.Right, QTextCursor.MoveMode.MoveAnchor, len(tail))
        self.editor.setTextCursor(cursor)

    def _activated(self, index: QModelIndex) -> None:
        """Chosen with the mouse (keys are handled in handle_key)."""
        if index.isValid():
            self.insert(index.data())
        self.close()

