"""The ZUML code editor: a QPlainTextEdit with a line-number gutter, colouring from the
opcode table, diagnostics underlines, hover help, completion, auto-indent, comment
toggling and an inline find/replace bar (``EditorWithFind``).

Extra selections come in four layers that are merged into the one list Qt keeps
(``setExtraSelections`` replaces it whole): the current line, the lines linked to the
hex view, find matches, and diagnostics on top. Each layer holds QTextCursors, which
follow edits, so a keystroke rebuilds the list only when the cursor changes line.
"""
from __future__ import annotations

import html
import textwrap
from typing import Iterator

from PySide6.QtCore import QEvent, QPoint, QRect, Qt, Signal
from PySide6.QtGui import (QAction, QColor, QFontDatabase, QKeySequence, QTextCharFormat, QTextCursor, QTextDocument,
                           QTextFormat, QTextLine)
from PySide6.QtWidgets import QPlainTextDocumentLayout, QPlainTextEdit, QTextEdit, QToolTip, QVBoxLayout, QWidget

from ...i18n import _
from ...lang.diagnostics import RANK, Diagnostic, Severity
from ..base import theme
from . import indent
from .completion import ZumlCompleter
from .find_bar import FindBar
from .highlighter import ZumlHighlighter, help_text
from .line_numbers import LineNumberArea

Selection = QTextEdit.ExtraSelection
UNDERLINE_COLOURS = {Severity.ERROR: QColor("#e0201b"), Severity.WARNING: QColor("#f08c00"),
                     Severity.NOTE: QColor("#1a73e8")}
TINT_COLOURS = {Severity.ERROR: QColor(224, 32, 27, 28), Severity.WARNING: QColor(240, 140, 0, 28),
                Severity.NOTE: QColor(26, 115, 232, 0)}     # a note is underlined only
TOOLTIP_COLUMNS = 64
MIN_FONT_PT, MAX_FONT_PT = 6, 36


class _BlockLayout(QPlainTextDocumentLayout):
    """QPlainTextDocumentLayout that repaints one line when only one line changed.

    QSyntaxHighlighter reports a re-coloured line as ``(from, length, length)``; the stock
    layout adds removed and added characters, reaches into the following lines and repaints
    the whole viewport on every keystroke (about 3 ms for 50 visible lines offscreen). A change
    that, in the new text, stays inside one line with the line count unchanged is passed on
    as a change of that line alone: exactly what plain typing without a highlighter reports.
    """

    def __init__(self, document: QTextDocument):
        super().__init__(document)
        self._blocks = document.blockCount()

    def documentChanged(self, position: int, removed: int, added: int) -> None:  # noqa: N802
        doc = self.document()
        count = doc.blockCount()
        if count == self._blocks:
            block = doc.findBlock(position)
            if block.isValid() and doc.findBlock(position + max(added, 1) - 1) == block:
                super().documentChanged(position, 0, max(added, 1))
                return
        self._blocks = count
        super().documentChanged(position, removed, added)


def _full_width(cursor: QTextCursor, colour: QColor) -> Selection:
    sel = Selection()
    sel.format.setBackground(colour)
    sel.format.setProperty(QTextFormat.Property.FullWidthSelection, True)
    sel.cursor = cursor
    return sel


class CodeEditor(QPlainTextEdit):
    """ZUML source editor. Lines and columns in its API are 1-based."""

    cursorLineChanged = Signal(int)         # 1-based line, when the cursor moves to another line
    fontSizeChanged = Signal(int)           # point size, after a zoom

    def __init__(self, parent: QWidget | None = None):
        super().__init__(parent)
        self.setObjectName("editor")
        # Kept as attributes: nothing else holds the Python side of the layout, whose
        # documentChanged override C++ calls on every edit (a collected wrapper crashes).
        self._document = QTextDocument(self)
        self._document_layout = _BlockLayout(self._document)
        self._document.setDocumentLayout(self._document_layout)
        self.setDocument(self._document)
        font = QFontDatabase.systemFont(QFontDatabase.SystemFont.FixedFont)
        self.setFont(font)
        self._default_pt = round(font.pointSizeF())
        self.setTabStopDistance(self.fontMetrics().horizontalAdvance(" ") * indent.INDENT_WIDTH)
        self.setLineWrapMode(QPlainTextEdit.LineWrapMode.NoWrap)
        self.setMouseTracking(True)

        self.highlighter = ZumlHighlighter(self.document())
        self.completer = ZumlCompleter(self)
        self.find_bar: FindBar | None = None           # set by EditorWithFind

        self._line = 0                                   # block number of the cursor
        self._gutter_key: tuple = ()
        self._diagnostics: list[tuple[QTextCursor, Diagnostic]] = []
        self._linked: list[QTextCursor] = []
        self._find: list[QTextCursor] = []
        self._current_sel: list[Selection] = []
        self._diag_sels: list[Selection] = []
        self._linked_sels: list[Selection] = []
        self._find_sels: list[Selection] = []
        self._colours()

        self.line_number_area = LineNumberArea(self)
        self.blockCountChanged.connect(self._block_count_changed)
        self.updateRequest.connect(self._update_gutter)
        self.cursorPositionChanged.connect(self._cursor_moved)
        self._update_gutter_width()
        self._set_current_line()

    def _colours(self) -> None:
        scheme = theme.colours(self.palette())
        self.highlighter.set_scheme(scheme)
        self._current_colour = QColor(scheme.current_line)
        self._linked_colour = QColor(scheme.linked_line)
        self._find_colour = QColor(scheme.find_match)

    # -- public API -----------------------------------------------------------------------
    def current_line(self) -> int:
        return self.textCursor().blockNumber() + 1

    def goto(self, line: int, column: int = 1) -> None:
        """Move the cursor to ``line``:``column`` (clamped), scroll it into view, take focus."""
        doc = self.document()
        block = doc.findBlockByNumber(min(max(line, 1), doc.blockCount()) - 1)
        cursor = QTextCursor(block)
        cursor.setPosition(block.position() + min(max(column, 1) - 1, block.length() - 1))
        top = self.blockBoundingGeometry(block).translated(self.contentOffset()).top()
        off_screen = top < 0 or top + self.fontMetrics().height() > self.viewport().height()
        self.setTextCursor(cursor)
        if off_screen:
            self.centerCursor()             # a jump (problem, hex row): land mid-screen, with context
        else:
            self.ensureCursorVisible()
        self.setFocus()

    def set_diagnostics(self, diagnostics: list[Diagnostic]) -> None:
        """Underline these diagnostics (replacing the previous ones): red waves for errors,
        orange for warnings; their lines get a dot in the gutter."""
        self._diagnostics = [(self._span_cursor(d), d) for d in diagnostics]
        # Errors last, so they are drawn over warnings on the same text.
        ordered = sorted(self._diagnostics, key=lambda cd: cd[1].is_error)
        sels = []
        for cursor, d in ordered:
            sel = Selection()
            sel.format.setUnderlineStyle(QTextCharFormat.UnderlineStyle.WaveUnderline)
            sel.format.setUnderlineColor(UNDERLINE_COLOURS[d.severity])
            sel.format.setBackground(TINT_COLOURS[d.severity])    # a faint tint: easier to spot
            sel.cursor = cursor
            sels.append(sel)
        self._diag_sels = sels
        self._apply_selections()
        self.line_number_area.update()

    def diagnostics(self) -> list[Diagnostic]:
        return [d for _, d in self._diagnostics]

    def set_linked_lines(self, lines: set[int]) -> None:
        """A soft background on these 1-based lines (those whose bytes the hex view selects)."""
        doc = self.document()
        lines = {n for n in lines if isinstance(n, int) and 1 <= n <= doc.blockCount()}
        if lines == self.linked_lines():
            return
        self._linked = [QTextCursor(doc.findBlockByNumber(n - 1)) for n in sorted(lines)]
        self._linked_sels = [_full_width(c, self._linked_colour) for c in self._linked]
        self._apply_selections()

    def linked_lines(self) -> set[int]:
        return {c.blockNumber() + 1 for c in self._linked}

    def set_find_matches(self, cursors: list[QTextCursor]) -> None:
        """Mark these ranges as find matches (the find bar's)."""
        if not cursors and not self._find:
            return
        self._find = list(cursors)
        sels = []
        for cursor in self._find:
            sel = Selection()
            sel.format.setBackground(self._find_colour)
            sel.cursor = cursor
            sels.append(sel)
        self._find_sels = sels
        self._apply_selections()

    def toggle_comment(self) -> None:
        """Add ``// `` to the selected lines, or remove it when all of them are commented
        (one undo step); the selection then covers the whole lines."""
        cursor = self.textCursor()
        doc = self.document()
        first = doc.findBlock(cursor.selectionStart())
        last = doc.findBlock(cursor.selectionEnd())
        if cursor.hasSelection() and last.blockNumber() > first.blockNumber() \
                and cursor.selectionEnd() == last.position():
            last = last.previous()          # a selection ending at a line start leaves that line out
        blocks = []
        block = first
        while block.isValid() and block.blockNumber() <= last.blockNumber():
            blocks.append(block)
            block = block.next()
        edits = indent.comment_edits([b.text() for b in blocks])
        if not edits:
            return
        edit = QTextCursor(doc)
        edit.beginEditBlock()
        for i, col, removed, inserted in reversed(edits):
            pos = blocks[i].position() + col
            edit.setPosition(pos)
            edit.setPosition(pos + removed, QTextCursor.MoveMode.KeepAnchor)
            edit.insertText(inserted)
        edit.endEditBlock()
        if len(blocks) > 1 or cursor.hasSelection():
            cursor.setPosition(blocks[0].position())
            cursor.setPosition(blocks[-1].position() + blocks[-1].length() - 1, QTextCursor.MoveMode.KeepAnchor)
            self.setTextCursor(cursor)

    def default_font_size(self) -> int:
        """The system's fixed-width font size (what Reset Zoom goes back to)."""
        return self._default_pt

    def font_size(self) -> int:
        return round(self.font().pointSizeF())

    def set_font_size(self, points: int) -> None:
        """The text's size in points, within MIN_FONT_PT..MAX_FONT_PT (the gutter and the
        completion popup follow)."""
        points = min(max(int(points), MIN_FONT_PT), MAX_FONT_PT)
        if points == self.font_size():
            return
        font = self.font()
        font.setPointSize(points)
        self.setFont(font)
        self.completer.popup().setFont(font)
        self.fontSizeChanged.emit(points)

    def zoom(self, steps: int) -> None:
        """Ctrl+= / Ctrl+- / Ctrl+wheel: one point per step."""
        self.set_font_size(self.font_size() + steps)

    def wheelEvent(self, event) -> None:  # noqa: N802
        if event.modifiers() & Qt.KeyboardModifier.ControlModifier:
            steps = event.angleDelta().y() // 120
            if steps:
                self.zoom(steps)
            event.accept()
            return
        super().wheelEvent(event)

    def fix_at(self, position: int) -> tuple[QTextCursor, Diagnostic] | None:
        """The "did you mean" fix for document ``position``: of a diagnostic there, or failing
        that the first on its line; None when there is none."""
        block = self.document().findBlock(position)
        on_line = [(c, d) for c, d in self._diagnostics if d.fix and c.block() == block]
        at = [(c, d) for c, d in on_line if c.selectionStart() <= position <= c.selectionEnd()]
        return (at or on_line or [None])[0]

    def quick_fix(self, position: int | None = None) -> bool:
        """Ctrl+.: write the fix for ``position`` (the cursor's by default) over the text its
        diagnostic marks, one undo step; False when there is none."""
        found = self.fix_at(self.textCursor().position() if position is None else position)
        if found is None:
            return False
        target, d = found
        edit = QTextCursor(self.document())
        edit.setPosition(target.selectionStart())
        edit.setPosition(target.selectionEnd(), QTextCursor.MoveMode.KeepAnchor)
        edit.beginEditBlock()
        edit.insertText(d.fix)
        edit.endEditBlock()
        self.setTextCursor(edit)
        return True

    def contextMenuEvent(self, event) -> None:  # noqa: N802
        menu = self.createStandardContextMenu(event.pos())
        position = self.cursorForPosition(event.pos()).position()
        found = self.fix_at(position)
        if found is not None:
            first = menu.actions()[0] if menu.actions() else None
            action = QAction(_("Write {fix}").format(fix=found[1].fix) + " (Ctrl+.)", menu)
            action.triggered.connect(lambda: self.quick_fix(position))
            menu.insertAction(first, action)
            menu.insertSeparator(first)
        menu.exec(event.globalPos())
        menu.deleteLater()

    def show_find(self, replace: bool = False) -> None:
        """Open the find bar (with the replace row when ``replace``)."""
        if self.find_bar is not None:
            self.find_bar.open(replace)

    # -- help and tooltips ------------------------------------------------------------------
    def diagnostics_at(self, position: int) -> list[Diagnostic]:
        """Diagnostics whose underlined range holds document ``position``, errors first."""
        found = []
        for cursor, d in self._diagnostics:
            start, end = cursor.selectionStart(), cursor.selectionEnd()
            if start <= position < end or start == end == position:
                found.append(d)
        return sorted(found, key=lambda d: not d.is_error)

    def help_at(self, position: int) -> str:
        """The opcode table's signature and help for the keyword at ``position``, or ''."""
        block = self.document().findBlock(position)
        if not block.isValid():
            return ""
        return help_text(block.text(), position - block.position())

    def tooltip_at(self, position: int) -> str:
        """What hovering document ``position`` shows: its diagnostics ("message\\nhint"),
        else the help of the keyword there, else ''."""
        diags = self.diagnostics_at(position)
        if diags:
            return "\n\n".join(d.message + (f"\n{d.hint}" if d.hint else "")
                                 + ("\n" + _("Ctrl+. writes {fix}").format(fix=d.fix) if d.fix else "") for d in diags)
        return self.help_at(position)

    def tooltip_at_line_column(self, line: int, column: int) -> str:
        block = self.document().findBlockByNumber(line - 1)
        return self.tooltip_at(block.position() + column - 1) if block.isValid() else ""

    def position_at(self, point: QPoint) -> int | None:
        """Document position of the character under a viewport point, None off the text."""
        cursor = self.cursorForPosition(point)
        block = cursor.block()
        geometry = self.blockBoundingGeometry(block).translated(self.contentOffset())
        local = point - geometry.topLeft().toPoint()
        layout = block.layout()
        for i in range(layout.lineCount()):
            line = layout.lineAt(i)
            if line.y() <= local.y() < line.y() + line.height():
                if not 0 <= local.x() < line.x() + line.naturalTextWidth():
                    return None
                column = line.xToCursor(local.x(), QTextLine.CursorPosition.CursorOnCharacter)
                if column >= block.length() - 1:
                    return None
                return block.position() + column
        return None

    def viewportEvent(self, event) -> bool:  # noqa: N802
        if event.type() == QEvent.Type.ToolTip:
            position = self.position_at(event.pos())
            text = self.tooltip_at(position) if position is not None else ""
            if text:
                QToolTip.showText(event.globalPos(), _tooltip_html(text), self.viewport())
            else:
                QToolTip.hideText()
                event.ignore()
            return True
        return super().viewportEvent(event)

    # -- gutter ------------------------------------------------------------------------------
    def line_markers(self) -> dict[int, Severity]:
        """Block number -> worst severity of the diagnostics on it (they follow edits)."""
        markers: dict[int, Severity] = {}
        for cursor, d in self._diagnostics:
            n = self.document().findBlock(cursor.selectionStart()).blockNumber()
            if n not in markers or RANK[d.severity] < RANK[markers[n]]:
                markers[n] = d.severity
        return markers

    def gutter_tooltip(self, y: int) -> str:
        line = self.line_at_y(y)
        if not line:
            return ""
        texts = [d.message + (f"\n{d.hint}" if d.hint else "")
                 for cursor, d in sorted(self._diagnostics, key=lambda cd: not cd[1].is_error)
                 if self.document().findBlock(cursor.selectionStart()).blockNumber() == line - 1]
        return "\n\n".join(texts)

    def line_at_y(self, y: int) -> int | None:
        for number, top, bottom in self.visible_blocks(y, y):
            if top <= y < bottom:
                return number + 1
        return None

    def visible_blocks(self, y_from: int, y_to: int) -> Iterator[tuple[int, int, int]]:
        """(block number, top, bottom) of visible blocks overlapping y_from..y_to (viewport px)."""
        block = self.firstVisibleBlock()
        if y_from > 0:                      # start at the line under y_from, not at the top
            under = self.cursorForPosition(QPoint(0, y_from)).block()
            if under.isValid() and under.blockNumber() > block.blockNumber():
                block = under
        top = round(self.blockBoundingGeometry(block).translated(self.contentOffset()).top())
        while block.isValid() and top <= y_to:
            bottom = top + round(self.blockBoundingRect(block).height())
            if block.isVisible() and bottom >= y_from:
                yield block.blockNumber(), top, bottom
            block = block.next()
            top = bottom

    def _update_gutter_width(self, _count: int = 0) -> None:
        width = self.line_number_area.area_width()
        if width != self.viewportMargins().left():
            self.setViewportMargins(width, 0, 0, 0)

    def _block_count_changed(self, _count: int) -> None:
        self._update_gutter_width()
        self.line_number_area.update()

    def _update_gutter(self, rect: QRect, dy: int) -> None:
        """The text area was repainted or scrolled. The gutter repaints only when its numbers
        moved: typing on a line (partial updates) leaves them as they are, and a change of
        line count, cursor line or diagnostics repaints the gutter by itself."""
        area = self.line_number_area
        if dy:
            area.scroll(0, dy)
        elif rect.contains(self.viewport().rect()):
            key = (self.firstVisibleBlock().blockNumber(), self.contentOffset().y(), self.blockCount(),
                   self.document().documentLayout().documentSize().height())
            if key != self._gutter_key:
                self._gutter_key = key
                area.update()
            self._update_gutter_width()

    def resizeEvent(self, event) -> None:  # noqa: N802
        super().resizeEvent(event)
        cr = self.contentsRect()
        self.line_number_area.setGeometry(QRect(cr.left(), cr.top(), self.line_number_area.area_width(), cr.height()))

    def changeEvent(self, event) -> None:  # noqa: N802
        super().changeEvent(event)
        if not hasattr(self, "line_number_area"):
            return                          # the font set in __init__
        if event.type() in (QEvent.Type.PaletteChange, QEvent.Type.FontChange):
            self._colours()
            if event.type() == QEvent.Type.FontChange:
                self.setTabStopDistance(self.fontMetrics().horizontalAdvance(" ") * indent.INDENT_WIDTH)
                self._update_gutter_width()
            self._set_current_line()

    # -- extra selections ----------------------------------------------------------------------
    def _apply_selections(self) -> None:
        self.setExtraSelections(self._current_sel + self._linked_sels + self._find_sels + self._diag_sels)

    def _set_current_line(self) -> None:
        cursor = self.textCursor()
        cursor.clearSelection()
        self._current_sel = [_full_width(cursor, self._current_colour)]
        self._apply_selections()

    def _cursor_moved(self) -> None:
        line = self.textCursor().blockNumber()
        # The highlight's own cursor can be carried off the line by an insertion at its
        # position (setPlainText, typing at the line start): then it is set again too.
        if line != self._line or self._current_sel[0].cursor.blockNumber() != line:
            moved = line != self._line
            self._line = line
            self._set_current_line()
            if moved:
                self.line_number_area.update()
                self.cursorLineChanged.emit(line + 1)

    def _span_cursor(self, d: Diagnostic) -> QTextCursor:
        """A cursor selecting what a diagnostic marks: (line, column) to ``end``, at least one
        character (the one at the column, or the last of the line at its end)."""
        doc = self.document()
        count = doc.blockCount()
        block = doc.findBlockByNumber(min(max(d.line, 1), count) - 1)
        line_end = block.position() + block.length() - 1
        start = min(block.position() + max(d.column, 1) - 1, line_end)
        end_line, end_column = d.end
        end = start
        if (end_line, end_column) > (d.line, d.column):
            end_block = doc.findBlockByNumber(min(max(end_line, 1), count) - 1)
            end = min(end_block.position() + max(end_column, 1) - 1, end_block.position() + end_block.length() - 1)
        if end <= start:
            if start < line_end:
                end = start + 1
            elif block.length() > 1:
                start, end = line_end - 1, line_end
            else:
                end = start                  # an empty line: the gutter dot shows it
        cursor = QTextCursor(doc)
        cursor.setPosition(start)
        cursor.setPosition(end, QTextCursor.MoveMode.KeepAnchor)
        return cursor

    # -- keys -----------------------------------------------------------------------------------
    def keyPressEvent(self, event) -> None:  # noqa: N802
        key, mods = event.key(), event.modifiers()
        K, M = Qt.Key, Qt.KeyboardModifier
        if self.completer.handle_key(key, mods):
            event.accept()
            return
        plain = mods & ~(M.KeypadModifier | M.ShiftModifier) == M.NoModifier
        if key == K.Key_Space and mods & M.ControlModifier:
            self.completer.open(explicit=True)
            return
        if key == K.Key_Slash and mods & M.ControlModifier:
            self.toggle_comment()
            return
        if key == K.Key_Y and mods == M.ControlModifier:
            self.redo()                     # Ctrl+Y on every platform, not only on Windows
            return
        if key == K.Key_Period and mods & M.ControlModifier:
            self.quick_fix()
            return
        if event.matches(QKeySequence.StandardKey.Find):
            self.show_find(False)
            return
        if event.matches(QKeySequence.StandardKey.Replace) or (key == K.Key_H and mods == M.ControlModifier):
            self.show_find(True)
            return
        if key == K.Key_Escape and self.find_bar is not None and self.find_bar.isVisible():
            self.find_bar.close_bar()
            return
        if key in (K.Key_Return, K.Key_Enter) and plain:
            self._new_line()
            self.completer.close()
            return
        if key == K.Key_Tab and mods == M.NoModifier:
            self._tab()
            return
        if key == K.Key_Backtab:
            self._shift_lines(-1)
            return
        if key == K.Key_Backspace and mods == M.NoModifier and self._smart_backspace():
            self.completer.after_key(key, "")
            return
        super().keyPressEvent(event)
        text = event.text()
        if text and (text.isalnum() or text == "_") and not mods & (M.ControlModifier | M.AltModifier):
            self._dedent_closer()
        self.completer.after_key(key, text if not mods & (M.ControlModifier | M.AltModifier) else "")

    def _new_line(self) -> None:
        """Return: keep the indentation, one level more after a line opening a block."""
        cursor = self.textCursor()
        before = cursor.block().text()[: cursor.positionInBlock()]
        if cursor.hasSelection():
            start = self.document().findBlock(cursor.selectionStart())
            before = start.text()[: cursor.selectionStart() - start.position()]
        cursor.beginEditBlock()
        cursor.insertBlock()
        cursor.insertText(indent.indent_after(before))
        cursor.endEditBlock()
        self.setTextCursor(cursor)
        self.ensureCursorVisible()

    def _dedent_closer(self) -> None:
        """A closer (END_FAZE…) just typed as a line's first word moves to its opener's indent."""
        cursor = self.textCursor()
        block = cursor.block()
        text = block.text()
        word = indent.first_word(text)
        if word not in indent.CLOSERS:
            return
        current = indent.leading_indent(text)
        if cursor.positionInBlock() != len(current) + len(word):
            return

        def above() -> Iterator[str]:
            b = block.previous()
            while b.isValid():
                yield b.text()
                b = b.previous()

        wanted = indent.opener_indent(text, above())
        if wanted is None or wanted == current:
            return
        edit = QTextCursor(block)
        edit.beginEditBlock()
        edit.setPosition(block.position() + len(current), QTextCursor.MoveMode.KeepAnchor)
        edit.insertText(wanted)
        edit.endEditBlock()

    def _tab(self) -> None:
        cursor = self.textCursor()
        doc = self.document()
        if cursor.hasSelection() and doc.findBlock(cursor.selectionStart()) != doc.findBlock(cursor.selectionEnd()):
            self._shift_lines(1)
            return
        column = cursor.positionInBlock()
        if cursor.hasSelection():
            column = cursor.selectionStart() - cursor.block().position()
        cursor.insertText(" " * (indent.next_tab_column(column) - column))
        self.setTextCursor(cursor)

    def _shift_lines(self, direction: int) -> None:
        """Indent (1) or dedent (-1) the selected lines by one level, one undo step."""
        cursor = self.textCursor()
        doc = self.document()
        first = doc.findBlock(cursor.selectionStart())
        last = doc.findBlock(cursor.selectionEnd())
        if last.blockNumber() > first.blockNumber() and cursor.selectionEnd() == last.position():
            last = last.previous()
        edit = QTextCursor(doc)
        edit.beginEditBlock()
        block = first
        while block.isValid() and block.blockNumber() <= last.blockNumber():
            text = block.text()
            edit.setPosition(block.position())
            if direction > 0:
                if text.strip():
                    edit.insertText(indent.INDENT)
            else:
                spaces = len(text) - len(text.lstrip(" "))
                edit.setPosition(block.position() + min(spaces, indent.INDENT_WIDTH), QTextCursor.MoveMode.KeepAnchor)
                edit.removeSelectedText()
            block = block.next()
        edit.endEditBlock()

    def _smart_backspace(self) -> bool:
        """Backspace in leading spaces removes back to the previous multiple of 2."""
        cursor = self.textCursor()
        if cursor.hasSelection():
            return False
        column = cursor.positionInBlock()
        before = cursor.block().text()[:column]
        if not before or before.strip(" "):
            return False
        target = indent.backspace_column(column)
        cursor.setPosition(cursor.position() - (column - target), QTextCursor.MoveMode.KeepAnchor)
        cursor.removeSelectedText()
        self.setTextCursor(cursor)
        return True


def _tooltip_html(text: str) -> str:
    """Rich text for QToolTip (plain text with '<' could be taken for markup): the first line
    of each paragraph (a message, a signature) in bold."""
    out = []
    for para in text.split("\n\n"):
        # Wrapped here: QToolTip's own wrapping of rich text makes a narrow column.
        lines = [html.escape(textwrap.fill(line, TOOLTIP_COLUMNS)) for line in para.split("\n")]
        lines[0] = f"<b>{lines[0]}</b>"
        out.append("\n".join(lines))
    return "".join(f"<p style='white-space:pre'>{para}</p>" for para in out)


class EditorWithFind(QWidget):
    """The editor with its find/replace bar underneath: what the main window places."""

    def __init__(self, parent: QWidget | None = None):
        super().__init__(parent)
        self.setObjectName("editorWithFind")
        self.editor = CodeEditor(self)
        self.find_bar = FindBar(self.editor, self)
        self.editor.find_bar = self.find_bar
        layout = QVBoxLayout(self)
        layout.setContentsMargins(0, 0, 0, 0)
        layout.setSpacing(0)
        layout.addWidget(self.editor, 1)
        layout.addWidget(self.find_bar)
