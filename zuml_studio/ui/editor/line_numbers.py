"""The gutter left of the text: line numbers and a dot on lines with an error or warning
(after the Qt for Python codeeditor example: the editor reserves the width with
``setViewportMargins`` and forwards scrolling through ``updateRequest``)."""
from __future__ import annotations

from typing import TYPE_CHECKING

from PySide6.QtCore import QEvent, QRect, QSize, Qt
from PySide6.QtGui import QColor, QPainter, QPalette
from PySide6.QtWidgets import QToolTip, QWidget

from ...lang.diagnostics import Severity

if TYPE_CHECKING:
    from .code_editor import CodeEditor

MARKER_COLOURS = {Severity.ERROR: QColor("#d93025"), Severity.WARNING: QColor("#f29900"),
                  Severity.NOTE: QColor("#1a73e8")}


class LineNumberArea(QWidget):
    MARKER_SPACE = 12       # px left of the numbers for the diagnostic dot
    RIGHT_PAD = 8

    def __init__(self, editor: "CodeEditor"):
        super().__init__(editor)
        self.setObjectName("lineNumberArea")
        self.editor = editor
        self.setMouseTracking(True)

    def area_width(self) -> int:
        digits = max(2, len(str(max(1, self.editor.blockCount()))))
        return self.MARKER_SPACE + self.editor.fontMetrics().horizontalAdvance("9") * digits + self.RIGHT_PAD

    def sizeHint(self) -> QSize:
        return QSize(self.area_width(), 0)

    def _colours(self) -> tuple[QColor, QColor, QColor, QColor]:
        """Background, separator, number, current number: derived from the palette."""
        base = self.editor.palette().color(QPalette.ColorRole.Base)
        if base.lightness() >= 128:
            return QColor("#f6f7f9"), QColor("#e3e5e8"), QColor("#9aa0a6"), QColor("#3c4043")
        return base.lighter(115), base.lighter(160), QColor("#858a90"), QColor("#e8eaed")

    def paintEvent(self, event) -> None:
        editor = self.editor
        background, separator, number, current_number = self._colours()
        painter = QPainter(self)
        painter.fillRect(event.rect(), background)
        painter.setPen(separator)
        painter.drawLine(self.width() - 1, event.rect().top(), self.width() - 1, event.rect().bottom())
        markers = editor.line_markers()
        current = editor.textCursor().blockNumber()
        font = editor.font()
        bold = editor.font()
        bold.setBold(True)
        height = editor.fontMetrics().height()
        text_width = self.width() - self.MARKER_SPACE - self.RIGHT_PAD
        painter.setRenderHint(QPainter.RenderHint.Antialiasing, True)
        for number_, top, bottom in editor.visible_blocks(event.rect().top(), event.rect().bottom()):
            is_current = number_ == current
            painter.setFont(bold if is_current else font)
            painter.setPen(current_number if is_current else number)
            painter.drawText(QRect(self.MARKER_SPACE, top, text_width, height),
                             int(Qt.AlignmentFlag.AlignRight | Qt.AlignmentFlag.AlignVCenter), str(number_ + 1))
            severity = markers.get(number_)
            if severity is not None:
                d = 7
                painter.setPen(Qt.PenStyle.NoPen)
                painter.setBrush(MARKER_COLOURS[severity])
                painter.drawEllipse((self.MARKER_SPACE - d) // 2 + 1, top + (height - d) // 2, d, d)
                painter.setBrush(Qt.BrushStyle.NoBrush)
        painter.end()

    def event(self, event) -> bool:
        if event.type() == QEvent.Type.ToolTip:
            text = self.editor.gutter_tooltip(event.pos().y())
            if text:
                QToolTip.showText(event.globalPos(), text, self)
            else:
                QToolTip.hideText()
                event.ignore()
            return True
        return super().event(event)

    def mousePressEvent(self, event) -> None:
        """A click on a number puts the cursor at the start of that line."""
        line = self.editor.line_at_y(int(event.position().y()))
        if line:
            self.editor.goto(line)
