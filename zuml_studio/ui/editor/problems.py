"""The problems list: every diagnostic of the open macro; activating one moves the cursor."""
from __future__ import annotations

from PySide6.QtCore import QRect, QSize, Qt, QTimer, Signal
from PySide6.QtGui import QColor, QPalette
from PySide6.QtWidgets import QHeaderView, QStyle, QStyledItemDelegate, QTreeWidget, QTreeWidgetItem

from ...i18n import _
from ...lang.diagnostics import Diagnostic, Severity
from ..base import theme

_ROLE = Qt.ItemDataRole.UserRole
MESSAGE = 2                 # the column that wraps
CELL_MARGINS_PX = 8
NARROW_PX = 220             # narrower than this, the list shows the message alone (where and code: the tooltip)


class _WrappingDelegate(QStyledItemDelegate):
    """A message's row as high as its text wrapped to the column's width (a tree view asks its
    delegate with no width, so Qt's own word wrap never grows a row)."""

    def sizeHint(self, option, index):  # noqa: N802
        hint = super().sizeHint(option, index)
        if index.column() != MESSAGE:
            return hint
        width = max(20, self.parent().header().sectionSize(MESSAGE) - CELL_MARGINS_PX)
        wrapped = option.fontMetrics.boundingRect(QRect(0, 0, width, 100_000), Qt.TextFlag.TextWordWrap,
                                                  str(index.data() or ""))
        return QSize(hint.width(), max(hint.height(), wrapped.height() + CELL_MARGINS_PX // 2))


class ProblemsView(QTreeWidget):
    problemActivated = Signal(int, int)     # line, column (1-based)

    def __init__(self, parent=None):
        super().__init__(parent)
        self.setObjectName("problems")
        self.setRootIsDecorated(False)
        # The dock is narrow (and Russian runs longer): a message wraps onto as many lines as it
        # needs instead of ending in "…"; the rows are laid out again when the column's width changes.
        self.setWordWrap(True)
        self.setUniformRowHeights(False)
        self.setTextElideMode(Qt.TextElideMode.ElideNone)
        self.setItemDelegate(_WrappingDelegate(self))
        self.setAlternatingRowColors(True)
        self.setColumnCount(4)
        self.setHeaderLabels(["", _("Line:Col"), _("Message"), _("Code")])
        header = self.header()
        header.setSectionResizeMode(0, QHeaderView.ResizeMode.ResizeToContents)
        header.setSectionResizeMode(1, QHeaderView.ResizeMode.ResizeToContents)
        header.setSectionResizeMode(MESSAGE, QHeaderView.ResizeMode.Stretch)
        header.setSectionResizeMode(3, QHeaderView.ResizeMode.ResizeToContents)
        header.setStretchLastSection(False)
        header.sectionResized.connect(lambda index, _old, _new: index == MESSAGE and self.scheduleDelayedItemsLayout())
        self._fit = QTimer(self, singleShot=True, interval=0)
        self._fit.timeout.connect(self._fit_columns)
        self.itemActivated.connect(self._activated)
        self.itemDoubleClicked.connect(self._activated)
        style = self.style()
        self._icons = {Severity.ERROR: style.standardIcon(QStyle.StandardPixmap.SP_MessageBoxCritical),
                       Severity.WARNING: style.standardIcon(QStyle.StandardPixmap.SP_MessageBoxWarning),
                       Severity.NOTE: style.standardIcon(QStyle.StandardPixmap.SP_MessageBoxInformation)}

    def set_diagnostics(self, diagnostics: list[Diagnostic], earlier: list[Diagnostic] = ()) -> None:
        """``earlier``: the warnings of the last valid version, shown greyed while the text has errors
        (the safety check reads only a macro that compiles: its warnings would vanish with a typo)."""
        self.clear()
        stale = _("(last valid version)")
        for d, old in [(d, False) for d in diagnostics] + [(d, True) for d in earlier if d.is_warning]:
            text = d.message + (f" — {d.hint}" if d.hint else "") + (f" {stale}" if old else "")
            item = QTreeWidgetItem(["", f"{d.line}:{d.column}", text, d.code])
            item.setIcon(0, self._icons[d.severity])
            tip = f"{d.line}:{d.column} {d.code}: " + (f"{d.message}\n{d.hint}" if d.hint else d.message)
            if old:
                tip += "\n" + _("Checked on the last version without errors: fix the errors to check this one.")
            for col in range(4):            # the list is narrow: the whole message on any cell
                item.setToolTip(col, tip)
            item.setData(0, _ROLE, (d.line, d.column))
            if old:
                grey = self.palette().color(QPalette.ColorGroup.Disabled, QPalette.ColorRole.Text)
                for col in range(1, 4):
                    item.setForeground(col, grey)
            elif d.is_warning:
                item.setForeground(3, QColor(theme.colours(self.palette()).warning))
            self.addTopLevelItem(item)

    def resizeEvent(self, event) -> None:  # noqa: N802
        super().resizeEvent(event)
        # Once the resize is over: a column hidden within it left the tree painting rows of the
        # old columns, and Qt crashed (a segmentation fault shrinking the window to 1100 px).
        self._fit.start()

    def _fit_columns(self) -> None:
        """Squeezed (the user narrowed the dock), the message keeps the width and reads a few words
        a line, not one: where and which code are on every row's tooltip, and the columns come back
        when the list is wide again."""
        narrow = self.viewport().width() < NARROW_PX
        for column in (1, 3):
            if self.isColumnHidden(column) != narrow:
                self.setColumnHidden(column, narrow)

    def _activated(self, item: QTreeWidgetItem, _column: int = 0) -> None:
        line, column = item.data(0, _ROLE)
        self.problemActivated.emit(line, column)
