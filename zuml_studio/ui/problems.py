"""The problems list: every diagnostic of the open macro; activating one moves the cursor."""
from __future__ import annotations

from PySide6.QtCore import Qt, Signal
from PySide6.QtGui import QColor
from PySide6.QtWidgets import QHeaderView, QStyle, QTreeWidget, QTreeWidgetItem

from ..i18n import _
from ..lang.diagnostics import Diagnostic, Severity
from . import theme

_ROLE = Qt.ItemDataRole.UserRole


class ProblemsView(QTreeWidget):
    problemActivated = Signal(int, int)     # line, column (1-based)

    def __init__(self, parent=None):
        super().__init__(parent)
        self.setObjectName("problems")
        self.setRootIsDecorated(False)
        self.setUniformRowHeights(True)
        self.setAlternatingRowColors(True)
        self.setColumnCount(4)
        self.setHeaderLabels(["", _("Line:Col"), _("Message"), _("Code")])
        header = self.header()
        header.setSectionResizeMode(0, QHeaderView.ResizeMode.ResizeToContents)
        header.setSectionResizeMode(1, QHeaderView.ResizeMode.ResizeToContents)
        header.setSectionResizeMode(2, QHeaderView.ResizeMode.Stretch)
        header.setSectionResizeMode(3, QHeaderView.ResizeMode.ResizeToContents)
        header.setStretchLastSection(False)
        self.itemActivated.connect(self._activated)
        self.itemDoubleClicked.connect(self._activated)
        style = self.style()
        self._icons = {Severity.ERROR: style.standardIcon(QStyle.StandardPixmap.SP_MessageBoxCritical),
                       Severity.WARNING: style.standardIcon(QStyle.StandardPixmap.SP_MessageBoxWarning),
                       Severity.NOTE: style.standardIcon(QStyle.StandardPixmap.SP_MessageBoxInformation)}

    def set_diagnostics(self, diagnostics: list[Diagnostic]) -> None:
        self.clear()
        for d in diagnostics:
            text = d.message + (f" — {d.hint}" if d.hint else "")
            item = QTreeWidgetItem(["", f"{d.line}:{d.column}", text, d.code])
            item.setIcon(0, self._icons[d.severity])
            tip = f"{d.message}\n{d.hint}" if d.hint else d.message
            for col in range(1, 4):         # the list is narrow: the whole message on any cell
                item.setToolTip(col, tip)
            item.setData(0, _ROLE, (d.line, d.column))
            if d.is_warning:
                item.setForeground(3, QColor(theme.colours(self.palette()).warning))
            self.addTopLevelItem(item)

    def _activated(self, item: QTreeWidgetItem, _column: int = 0) -> None:
        line, column = item.data(0, _ROLE)
        self.problemActivated.emit(line, column)
