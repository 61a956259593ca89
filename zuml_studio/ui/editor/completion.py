"""Completion of statement forms and symbolic values, read from the opcode table.

Every statement form becomes one insertion up to where the user's own value starts:
``CONSTANT_I=``, ``CHARGE_EX(``, ``IF(V>``, ``FAZE``, ``STOP_FAZE``; then the symbolic values
(``INPUT``, ``AUTO``, ``LiPo``, ``STOP``, ``FAST``…). The popup filters case-insensitively on the
word before the cursor and replaces that word with the chosen item.
"""
from __future__ import annotations

from typing import NamedTuple

from PySide6.QtCore import QModelIndex, Qt
from PySide6.QtGui import QStandardItem, QStandardItemModel, QTextCursor
from PySide6.QtWidgets import QCompleter, QPlainTextEdit

from ...lang import opcodes
from ...lang.opcodes import Form
from .highlighter import SYMBOLIC_VALUES

MIN_PREFIX = 2          # letters typed before the popup opens by itself
DETAIL_ROLE = Qt.ItemDataRole.ToolTipRole


class CompletionItem(NamedTuple):
    text: str           # what is inserted
    detail: str         # signature and help, shown as the item's tooltip


def completion_items() -> list[CompletionItem]:
    """Statement forms in table order, the condition outcomes, then symbolic values."""
    items: list[CompletionItem] = []
    seen: set[str] = set()

    def add(text: str, detail: str) -> None:
        if text.upper() not in seen:
            seen.add(text.upper())
            items.append(CompletionItem(text, detail))

    for op in opcodes.OPCODES:
        detail = f"{op.signature()}\n{op.help}"
        if op.condition:
            c = op.condition
            add(f"IF({c.variables[0]}{c.comparison}", detail)
        elif op.form is Form.ASSIGN:
            add(f"{op.keyword}=", detail)
        elif op.form is Form.CALL:
            add(f"{op.keyword}(", detail)
        else:
            add(op.keyword, detail)
    for outcome in sorted(opcodes.CONDITION_OUTCOMES):
        ops = [op for op in opcodes.CONDITIONS if op.condition.outcome == outcome]
        add(outcome, "Outcome of " + ", ".join(op.signature() for op in ops))
    for spelling in SYMBOLIC_VALUES.values():
        add(spelling, "value")
    return items


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


class ZumlCompleter(QCompleter):
    """A popup completer bound to one QPlainTextEdit. The editor forwards its key presses:
    ``handle_key`` before its own handling, ``after_key`` after it."""

    def __init__(self, editor: QPlainTextEdit):
        model = QStandardItemModel(editor)
        for item in completion_items():
            row = QStandardItem(item.text)
            row.setData(item.detail, DETAIL_ROLE)
            row.setEditable(False)
            model.appendRow(row)
        super().__init__(model, editor)
        self.setObjectName("editorCompleter")
        self.editor = editor
        self.setWidget(editor)
        self.setCompletionMode(QCompleter.CompletionMode.PopupCompletion)
        self.setCaseSensitivity(Qt.CaseSensitivity.CaseInsensitive)
        self.setMaxVisibleItems(10)
        self.popup().setFont(editor.font())
        self.activated[QModelIndex].connect(self._activated)
        self._explicit = False

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
        """Replace the word before the cursor with ``text`` (one undo step)."""
        cursor = self.editor.textCursor()
        prefix = word_before(cursor.block().text(), cursor.positionInBlock())
        cursor.beginEditBlock()
        cursor.clearSelection()
        cursor.movePosition(QTextCursor.MoveOperation.Left, QTextCursor.MoveMode.KeepAnchor, len(prefix))
        cursor.insertText(text)
        cursor.endEditBlock()
        self.editor.setTextCursor(cursor)

    def _activated(self, index: QModelIndex) -> None:
        """Chosen with the mouse (keys are handled in handle_key)."""
        if index.isValid():
            self.insert(index.data())
        self.close()

