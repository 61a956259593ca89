"""The compiled record, one row per field or command, linked both ways with the
source: the rows of the cursor's line are selected, and activating a row moves
the cursor to its line. Two modes over the same rows: bytes (offset, raw bytes,
what they are) and the dis-style listing (line, offset, bytes, mnemonic, operands)."""
from __future__ import annotations

from PySide6.QtCore import QEvent, Qt, Signal
from PySide6.QtGui import QColor, QFontDatabase
from PySide6.QtWidgets import (QAbstractItemView, QButtonGroup, QHBoxLayout, QHeaderView, QLabel, QRadioButton,
                               QTreeWidget, QTreeWidgetItem, QVBoxLayout, QWidget)

from ...i18n import N_, _, ngettext
from ...lang.compiler import CompileResult
from ...lang.listing import Row, listing_rows
from ...lang.record import MAX_RECORD
from ..base import theme

_LINE = Qt.ItemDataRole.UserRole

# The record's own parts (not opcodes): named in the user's language in the view; the CLI's
# listing keeps their upper-case codes.
RECORD_PARTS = {"LENGTH": N_("Length"), "PROGRAM": N_("Program"), "CHARGE": N_("Charge"),
                "CONCLUSION": N_("Conclusion"), "NAME": N_("Name"), "CHECK": N_("Check")}
_COLUMNS = [N_("Line"), N_("Offset"), N_("Bytes"), N_("Instruction"), N_("Operands")]


class HexView(QWidget):
    lineActivated = Signal(int)             # a row was activated: move the editor to this source line
    rowsSelected = Signal(object)           # set of source lines whose bytes are selected

    def __init__(self, parent=None):
        super().__init__(parent)
        self.setObjectName("hexView")
        self._rows: list[Row] = []
        self._stale = False
        self._syncing = False

        self.banner = QLabel(_("The text has errors: these are the bytes of the last valid version."))
        self.banner.setObjectName("hexBanner")
        self.banner.setWordWrap(True)
        self.banner.setStyleSheet("background:#fff4d6; color:#6b4a00; padding:4px 6px; border:1px solid #e8c872;")
        self.banner.hide()
        self.summary = QLabel(_("No bytes yet"))
        self.summary.setObjectName("hexSummary")

        self.mode_bytes = QRadioButton(_("Bytes"))
        self.mode_listing = QRadioButton(_("Listing"))
        self.mode_bytes.setChecked(True)
        group = QButtonGroup(self)
        group.addButton(self.mode_bytes)
        group.addButton(self.mode_listing)
        self.mode_listing.toggled.connect(self._apply_mode)

        self.tree = QTreeWidget()
        self.tree.setObjectName("hexTree")
        self.tree.setColumnCount(len(_COLUMNS))
        self.tree.setHeaderLabels([_(c) for c in _COLUMNS])
        self.tree.setRootIsDecorated(False)
        self.tree.setUniformRowHeights(True)
        self.tree.setSelectionMode(QAbstractItemView.SelectionMode.ExtendedSelection)
        font = QFontDatabase.systemFont(QFontDatabase.SystemFont.FixedFont)
        self.tree.setFont(font)
        header = self.tree.header()
        header.setStretchLastSection(True)
        for col in range(4):
            header.setSectionResizeMode(col, QHeaderView.ResizeMode.ResizeToContents)
        self.tree.itemActivated.connect(self._activated)
        self.tree.itemClicked.connect(self._activated)
        self.tree.itemSelectionChanged.connect(self._selection_changed)

        top = QHBoxLayout()
        top.addWidget(self.summary, 1)
        top.addWidget(self.mode_bytes)
        top.addWidget(self.mode_listing)
        layout = QVBoxLayout(self)
        layout.setContentsMargins(4, 4, 4, 4)
        layout.addLayout(top)
        layout.addWidget(self.banner)
        layout.addWidget(self.tree, 1)
        self._apply_mode()

    # -- content ------------------------------------------------------------------------
    def show_result(self, result: CompileResult, last_valid: CompileResult | None) -> None:
        """The result of the latest check; while it has errors the last valid bytes stay, greyed."""
        shown = result if result.ok else last_valid
        self._stale = not result.ok
        self.banner.setVisible(self._stale and shown is not None)
        if shown is None:
            self._rows = []
            self.tree.clear()
            self.summary.setText(_("No bytes: the macro has errors"))
            return
        enc = shown.encoded
        self._rows = listing_rows(enc.record, enc.instructions, enc.nodes)
        self._fill()
        record = enc.record
        self.summary.setText(_("{size} of {max} bytes · check byte {check}").format(
            size=len(record), max=MAX_RECORD, check=f"0x{record[-1]:02x}"))

    def record_hex(self) -> str:
        return " ".join(r.hex for r in self._rows)

    def _fill(self) -> None:
        self.tree.clear()
        scheme = theme.colours(self.palette())      # the tree resolves its palette after this widget
        grey = QColor(scheme.stale_text)
        kind_colours = {"header": scheme.header_row, "name": scheme.header_row, "check": scheme.check_row}
        items = []
        for r in self._rows:
            label = r.mnemonic if r.kind == "instruction" else _(RECORD_PARTS.get(r.mnemonic, r.mnemonic))
            item = QTreeWidgetItem([str(r.line or ""), f"{r.offset:3d}", r.hex, label, r.detail])
            item.setData(0, _LINE, r.line)
            item.setToolTip(2, ngettext("offset {offset}, {n} byte", "offset {offset}, {n} bytes", len(r.data)).format(
                offset=r.offset, n=len(r.data)))
            if r.kind in kind_colours:
                for col in range(len(_COLUMNS)):
                    item.setBackground(col, QColor(kind_colours[r.kind]))
            if self._stale:
                for col in range(len(_COLUMNS)):
                    item.setForeground(col, grey)
            items.append(item)
        self.tree.addTopLevelItems(items)

    def changeEvent(self, event) -> None:  # noqa: N802
        super().changeEvent(event)
        if event.type() == QEvent.Type.PaletteChange and self._rows:
            self._fill()             # the labelled rows' tints follow a light or dark palette

    def _apply_mode(self) -> None:
        listing = self.mode_listing.isChecked()
        self.tree.setColumnHidden(0, not listing)
        self.tree.setColumnHidden(4, False)

    # -- linking ------------------------------------------------------------------------
    def select_line(self, line: int) -> None:
        """Select the rows compiled from this source line (the cursor moved there)."""
        self._syncing = True
        try:
            self.tree.clearSelection()
            first = None
            for i in range(self.tree.topLevelItemCount()):
                item = self.tree.topLevelItem(i)
                if item.data(0, _LINE) == line:
                    item.setSelected(True)
                    first = first or item
            if first is not None:
                self.tree.scrollToItem(first)
        finally:
            self._syncing = False

    def selected_offsets(self) -> list[int]:
        return sorted(int(item.text(1)) for item in self.tree.selectedItems())

    def _activated(self, item: QTreeWidgetItem, _column: int = 0) -> None:
        line = item.data(0, _LINE)
        if line:
            self.lineActivated.emit(line)

    def _selection_changed(self) -> None:
        if not self._syncing:
            lines = {item.data(0, _LINE) for item in self.tree.selectedItems()} - {None}
            self.rowsSelected.emit(lines)
