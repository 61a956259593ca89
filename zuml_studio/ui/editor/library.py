"""The macro library: the standard macros shipped in the package and the user's own folder.
Each entry says its chemistry and size, read by compiling it: after the names are listed,
one file per turn of the event loop, so that neither the window's first paint nor a
folder's refresh waits for a dozen compilations."""
from __future__ import annotations

from pathlib import Path

from PySide6.QtCore import QFileSystemWatcher, Qt, QTimer, Signal
from PySide6.QtGui import QColor
from PySide6.QtWidgets import QHeaderView, QTreeWidget, QTreeWidgetItem

from ... import data
from ...i18n import _, ngettext
from ...lang import opcodes as ops
from ...lang.compiler import compile_source
from ...macro_file import EXTENSION, MacroFileError, read_macro_file

_PATH = Qt.ItemDataRole.UserRole


def describe(path: Path) -> tuple[str, str, bool]:
    """(chemistry, size text, valid) of a macro file."""
    try:
        text = read_macro_file(path).text
    except MacroFileError:
        return "?", _("unreadable"), False
    result = compile_source(text)
    akk = result.macro.declared(ops.AKK_TYPE) if result.macro else None
    chemistry = ops.AKK_TYPE.operands[0].kind.format(akk.args[0].raw) if akk else "-"
    if not result.ok:
        return chemistry, ngettext("{n} error", "{n} errors", len(result.errors)).format(n=len(result.errors)), False
    return chemistry, f"{len(result.record)} B", True


class LibraryBrowser(QTreeWidget):
    fileActivated = Signal(str)

    def __init__(self, user_dir: Path, parent=None):
        super().__init__(parent)
        self.setObjectName("libraryBrowser")
        self.user_dir = user_dir
        self.setColumnCount(3)
        self.setHeaderLabels([_("Macro"), _("Type"), _("Size")])
        header = self.header()
        header.setSectionResizeMode(0, QHeaderView.ResizeMode.Stretch)
        header.setSectionResizeMode(1, QHeaderView.ResizeMode.ResizeToContents)
        header.setSectionResizeMode(2, QHeaderView.ResizeMode.ResizeToContents)
        header.setStretchLastSection(False)
        self.itemActivated.connect(self._activated)
        self.itemDoubleClicked.connect(self._activated)
        self._watcher = QFileSystemWatcher(self)
        self._watcher.directoryChanged.connect(lambda _path: self.refresh())
        self._undescribed: list[QTreeWidgetItem] = []
        self._describer = QTimer(self, interval=0)
        self._describer.timeout.connect(self._describe_next)
        self.refresh()

    def folders(self) -> list[tuple[str, Path]]:
        return [(_("Standard macros"), data.standard_macros_dir()), (_("My macros"), self.user_dir)]

    def refresh(self) -> None:
        self.clear()
        self._undescribed = []
        for title, folder in self.folders():
            root = QTreeWidgetItem([title, "", ""])
            root.setToolTip(0, str(folder))
            self.addTopLevelItem(root)
            root.setFirstColumnSpanned(True)        # the folder's name may use the whole width
            font = root.font(0)
            font.setBold(True)
            root.setFont(0, font)
            files = sorted(folder.glob(f"*{EXTENSION}"), key=lambda p: p.name.lower()) if folder.is_dir() else []
            for path in files:
                item = QTreeWidgetItem([path.stem, "", "…"])
                item.setData(0, _PATH, str(path))
                item.setToolTip(0, str(path))
                root.addChild(item)
                self._undescribed.append(item)
            if not files:
                empty = QTreeWidgetItem([_("(no macros yet)") if folder == self.user_dir else _("(none)"), "", ""])
                empty.setForeground(0, QColor("#888888"))
                root.addChild(empty)
                empty.setFirstColumnSpanned(True)
            root.setExpanded(True)
            if folder.is_dir() and str(folder) not in self._watcher.directories():
                self._watcher.addPath(str(folder))
        self._describer.start()

    def _describe_next(self) -> None:
        if not self._undescribed:
            self._describer.stop()
            return
        item = self._undescribed.pop(0)
        chemistry, size, valid = describe(Path(item.data(0, _PATH)))
        item.setText(1, chemistry)
        item.setText(2, size)
        if not valid:
            item.setForeground(2, QColor("#b00020"))

    def described(self) -> bool:
        """Every entry's chemistry and size are shown."""
        return not self._undescribed

    def paths(self) -> list[str]:
        out = []
        for i in range(self.topLevelItemCount()):
            root = self.topLevelItem(i)
            out += [root.child(j).data(0, _PATH) for j in range(root.childCount()) if root.child(j).data(0, _PATH)]
        return out

    def _activated(self, item: QTreeWidgetItem, _column: int = 0) -> None:
        path = item.data(0, _PATH)
        if path:
            self.fileActivated.emit(path)
