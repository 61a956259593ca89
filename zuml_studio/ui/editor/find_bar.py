"""The inline find / replace bar under the editor (Ctrl+F, Ctrl+H; Esc closes)."""
from __future__ import annotations

from typing import TYPE_CHECKING

from PySide6.QtCore import QEvent, Qt, QTimer, Signal
from PySide6.QtGui import QKeySequence, QTextCursor, QTextDocument
from PySide6.QtWidgets import (QCheckBox, QGridLayout, QHBoxLayout, QLabel, QLineEdit, QPushButton, QToolButton,
                               QWidget)

from ...i18n import _

if TYPE_CHECKING:
    from .code_editor import CodeEditor

MAX_HIGHLIGHTED = 2000
FIELD_PADDING_PX = 28       # the frame and the text margins (the clear button shows only over a typed text)


class FindBar(QWidget):
    closed = Signal()

    def __init__(self, editor: "CodeEditor", parent: QWidget | None = None):
        super().__init__(parent)
        self.setObjectName("findBar")
        self.editor = editor

        self.find_edit = QLineEdit()
        self.find_edit.setObjectName("findEdit")
        self.find_edit.setPlaceholderText(_("Find"))
        self.find_edit.setClearButtonEnabled(True)
        self.replace_edit = QLineEdit()
        self.replace_edit.setObjectName("replaceEdit")
        self.replace_edit.setPlaceholderText(_("Replace with"))
        self.match_case = QCheckBox(_("Match case"))
        self.match_case.setObjectName("findMatchCase")
        self.status = QLabel("")
        self.status.setObjectName("findStatus")
        self.status.setMinimumWidth(70)

        self.prev_button = self._tool("▲", _("Previous match (Shift+Enter)"), lambda: self.find_next(backward=True))
        self.next_button = self._tool("▼", _("Next match (Enter)"), lambda: self.find_next())
        self.close_button = self._tool("✕", _("Close (Esc)"), self.close_bar)
        self.replace_button = QPushButton(_("Replace"))
        self.replace_button.clicked.connect(self.replace)
        self.replace_all_button = QPushButton(_("Replace All"))
        self.replace_all_button.clicked.connect(self.replace_all)

        grid = QGridLayout(self)
        grid.setContentsMargins(6, 4, 6, 4)
        grid.setHorizontalSpacing(6)
        grid.setVerticalSpacing(3)
        grid.addWidget(self.find_edit, 0, 0)
        row0 = QHBoxLayout()
        for w in (self.prev_button, self.next_button, self.match_case, self.status):
            row0.addWidget(w)
        row0.addStretch(1)
        row0.addWidget(self.close_button)
        grid.addLayout(row0, 0, 1)
        grid.addWidget(self.replace_edit, 1, 0)
        row1 = QHBoxLayout()
        row1.addWidget(self.replace_button)
        row1.addWidget(self.replace_all_button)
        row1.addStretch(1)
        grid.addLayout(row1, 1, 1)
        grid.setColumnStretch(0, 2)
        grid.setColumnStretch(1, 3)
        for edit in (self.find_edit, self.replace_edit):     # never squeezed below what they say they are for
            edit.setMinimumWidth(edit.fontMetrics().horizontalAdvance(edit.placeholderText()) + FIELD_PADDING_PX)
        self._replace_row = (self.replace_edit, self.replace_button, self.replace_all_button)

        self.find_edit.textChanged.connect(self._query_changed)
        self.match_case.toggled.connect(self._query_changed)
        # Enter in the fields: an event filter, since QLineEdit passes Return on to its parent too.
        self.find_edit.installEventFilter(self)
        self.replace_edit.installEventFilter(self)
        # The matches are re-marked a moment after the text changes while the bar is open.
        self._rescan = QTimer(self, singleShot=True, interval=200)
        self._rescan.timeout.connect(self._highlight_all)
        editor.textChanged.connect(lambda: self.isVisible() and self._rescan.start())
        self.hide()

    def _tool(self, text: str, tip: str, slot) -> QToolButton:
        button = QToolButton()
        button.setText(text)
        button.setToolTip(tip)
        button.setAutoRaise(True)
        button.clicked.connect(slot)
        return button

    # -- showing ------------------------------------------------------------------------
    def open(self, replace: bool = False) -> None:
        """Show the bar (with the replace row for Ctrl+H), seeded with the selected text."""
        for w in self._replace_row:
            w.setVisible(replace)
        selected = self.editor.textCursor().selectedText()
        if selected and "\u2029" not in selected:
            self.find_edit.setText(selected)
        self.show()
        self.find_edit.setFocus()
        self.find_edit.selectAll()
        self._highlight_all()

    def close_bar(self) -> None:
        self.hide()
        self.editor.set_find_matches([])
        self.editor.setFocus()
        self.closed.emit()

    def eventFilter(self, watched, event) -> bool:
        if event.type() == QEvent.Type.KeyPress and event.key() in (Qt.Key.Key_Return, Qt.Key.Key_Enter):
            if watched is self.replace_edit:
                self.replace()
            else:
                self.find_next(backward=bool(event.modifiers() & Qt.KeyboardModifier.ShiftModifier))
            return True
        return super().eventFilter(watched, event)

    def keyPressEvent(self, event) -> None:
        if event.key() == Qt.Key.Key_Escape:
            self.close_bar()
            return
        if event.matches(QKeySequence.StandardKey.FindNext):
            self.find_next()
            return
        if event.matches(QKeySequence.StandardKey.FindPrevious):
            self.find_next(backward=True)
            return
        super().keyPressEvent(event)

    # -- searching ----------------------------------------------------------------------
    def _flags(self, backward: bool = False) -> QTextDocument.FindFlag:
        flags = QTextDocument.FindFlag(0)
        if self.match_case.isChecked():
            flags |= QTextDocument.FindFlag.FindCaseSensitively
        if backward:
            flags |= QTextDocument.FindFlag.FindBackward
        return flags

    def _matches(self) -> list[QTextCursor]:
        text = self.find_edit.text()
        doc = self.editor.document()
        found: list[QTextCursor] = []
        if not text:
            return found
        cursor = QTextCursor(doc)
        flags = self._flags()
        while len(found) < MAX_HIGHLIGHTED:
            cursor = doc.find(text, cursor, flags)
            if cursor.isNull():
                break
            found.append(cursor)
        return found

    def _highlight_all(self) -> None:
        if not self.isVisible():
            return
        matches = self._matches()
        self.editor.set_find_matches(matches)
        self._show_count(matches)

    def _show_count(self, matches: list[QTextCursor] | None = None) -> None:
        if not self.find_edit.text():
            self.status.setText("")
            return
        matches = self._matches() if matches is None else matches
        if not matches:
            self.status.setText(_("No results"))
            self.status.setStyleSheet("color:#c5221f;")
            return
        self.status.setStyleSheet("")
        here = self.editor.textCursor()
        index = next((i for i, m in enumerate(matches)
                      if m.selectionStart() == here.selectionStart() and m.selectionEnd() == here.selectionEnd()), None)
        self.status.setText(_("{n} of {total}").format(n=index + 1, total=len(matches)) if index is not None
                            else _("{total} found").format(total=len(matches)))

    def _query_changed(self) -> None:
        """Incremental search: the first match from where the current selection starts."""
        text = self.find_edit.text()
        if text:
            cursor = self.editor.textCursor()
            cursor.setPosition(cursor.selectionStart())
            self._find_from(cursor, backward=False)
        self._highlight_all()

    def _find_from(self, cursor: QTextCursor, backward: bool) -> bool:
        text = self.find_edit.text()
        if not text:
            return False
        doc = self.editor.document()
        found = doc.find(text, cursor, self._flags(backward))
        if found.isNull():                  # wrap around
            start = QTextCursor(doc)
            if backward:
                start.movePosition(QTextCursor.MoveOperation.End)
            found = doc.find(text, start, self._flags(backward))
        if found.isNull():
            return False
        self.editor.setTextCursor(found)
        self.editor.ensureCursorVisible()
        return True

    def find_next(self, backward: bool = False) -> bool:
        """Select the next (or previous) match, wrapping around; False when there is none."""
        ok = self._find_from(self.editor.textCursor(), backward)
        self._show_count()
        return ok

    def _selection_matches(self) -> bool:
        selected = self.editor.textCursor().selectedText()
        text = self.find_edit.text()
        if not selected or not text:
            return False
        return selected == text if self.match_case.isChecked() else selected.lower() == text.lower()

    def replace(self) -> bool:
        """Replace the selected match and select the next one (or just find the next one)."""
        if self._selection_matches():
            cursor = self.editor.textCursor()
            cursor.insertText(self.replace_edit.text())     # one undo step
            self.editor.setTextCursor(cursor)
        return self.find_next()

    def replace_all(self) -> int:
        """Replace every match as one undo step; the number replaced."""
        text = self.find_edit.text()
        if not text:
            return 0
        doc = self.editor.document()
        replacement = self.replace_edit.text()
        flags = self._flags()
        edit = QTextCursor(doc)
        count = 0
        edit.beginEditBlock()
        found = doc.find(text, 0, flags)
        while not found.isNull():
            found.insertText(replacement)
            count += 1
            found = doc.find(text, found.position(), flags)
        edit.endEditBlock()
        self._highlight_all()
        self.status.setStyleSheet("")
        self.status.setText(_("{n} replaced").format(n=count))
        return count
