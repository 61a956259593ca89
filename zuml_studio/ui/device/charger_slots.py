"""What is on the charger: its macros (the slot table and free bytes), Compile & Flash with
its target slot and progress, Backup and Restore. It owns the last EEPROM image read."""
from __future__ import annotations

from PySide6.QtCore import Qt
from PySide6.QtWidgets import (QAbstractItemView, QComboBox, QHBoxLayout, QHeaderView, QLabel, QProgressBar,
                               QPushButton, QTableWidget, QTableWidgetItem, QToolButton, QVBoxLayout, QWidget)

from ...lang.eeprom import Slot, slots, used_bytes
from .connection_bar import record_chemistry
from .device_style import colour, heading

FLASH_TIP = "Write the editor's macro to the charger, verify it (Ctrl+Shift+F)"


class SlotTable(QTableWidget):
    """The slot list. Its preferred height is small (a header and three rows): the column's
    layout gives it whatever room is left, and a preferred height of its own would make the
    controls scroll in a 380 px dock."""

    def sizeHint(self):  # noqa: N802
        hint = super().sizeHint()
        rows = self.verticalHeader().defaultSectionSize()
        hint.setHeight(self.horizontalHeader().sizeHint().height() + 3 * rows + 2 * self.frameWidth())
        return hint


class ChargerSlots(QWidget):
    def __init__(self, parent: QWidget | None = None):
        super().__init__(parent)
        self.setObjectName("deviceColumn")
        self.image: bytes | None = None
        self.slots: list[Slot] = []
        self.table = SlotTable(0, 5)
        self.table.setObjectName("slotTable")
        self.table.setHorizontalHeaderLabels(["#", "Macro", "Bytes", "Type", "Check"])
        self.table.verticalHeader().setVisible(False)
        self.table.verticalHeader().setDefaultSectionSize(self.fontMetrics().height() + 6)
        self.table.setEditTriggers(QAbstractItemView.EditTrigger.NoEditTriggers)
        self.table.setSelectionBehavior(QAbstractItemView.SelectionBehavior.SelectRows)
        self.table.setSelectionMode(QAbstractItemView.SelectionMode.SingleSelection)
        self.table.setAlternatingRowColors(True)
        self.table.setShowGrid(False)
        header = self.table.horizontalHeader()
        header.setSectionResizeMode(QHeaderView.ResizeMode.ResizeToContents)
        header.setSectionResizeMode(1, QHeaderView.ResizeMode.Stretch)
        header.setHighlightSections(False)
        self.table.setMinimumHeight(2 * self.table.verticalHeader().defaultSectionSize() + 26)
        self.table.setToolTip("The macros in the charger's EEPROM, in slot order; select one to run it")
        self.free_label = QLabel("")
        self.free_label.setObjectName("freeLabel")
        self.flash_slot = QComboBox()
        self.flash_slot.setObjectName("flashSlot")
        self.flash_slot.addItem("By name", None)
        self.flash_slot.setSizeAdjustPolicy(QComboBox.SizeAdjustPolicy.AdjustToMinimumContentsLengthWithIcon)
        self.flash_slot.setMinimumContentsLength(12)
        self.flash_slot.setToolTip("Where Compile & Flash puts the macro: over the one of the same name "
                                   "(else appended), or into a slot you pick")
        self.flash_button = QPushButton("Compile && Flash")
        self.flash_button.setObjectName("flashButton")
        self.flash_button.setToolTip(FLASH_TIP)
        self.progress = QProgressBar()
        self.progress.setObjectName("flashProgress")
        self.progress.setTextVisible(False)
        self.progress.setFixedHeight(6)
        self.progress.setRange(0, 1)
        self.progress.setValue(0)
        self.result_label = QLabel("")
        self.result_label.setObjectName("flashResult")
        self.result_label.setWordWrap(True)
        self.result_label.setTextInteractionFlags(Qt.TextInteractionFlag.TextSelectableByMouse)
        self.backup_button = QPushButton("Backup…")
        self.backup_button.setToolTip("Save the charger's whole EEPROM to a file")
        self.restore_button = QPushButton("Restore…")
        self.restore_button.setToolTip("Write a saved EEPROM image back (every record is checked first)")
        self.reload_button = QToolButton()
        self.reload_button.setText("⟳")
        self.reload_button.setToolTip("Read the macros on the charger again")

        a = QVBoxLayout(self)
        a.setContentsMargins(0, 0, 0, 0)
        a.setSpacing(3)
        head = QHBoxLayout()
        head.setSpacing(4)
        head.addWidget(heading("Macros on the charger"), 1)
        head.addWidget(self.reload_button)
        a.addLayout(head)
        a.addWidget(self.table, 1)
        a.addWidget(self.free_label)
        flash_row = QHBoxLayout()
        flash_row.setSpacing(4)
        flash_row.addWidget(self.flash_slot, 1)
        flash_row.addWidget(self.flash_button)
        a.addLayout(flash_row)
        a.addWidget(self.progress)
        a.addWidget(self.result_label)
        file_row = QHBoxLayout()
        file_row.setSpacing(4)
        file_row.addWidget(self.backup_button)
        file_row.addWidget(self.restore_button)
        file_row.addStretch(1)
        a.addLayout(file_row)

    # -- progress -----------------------------------------------------------------------------
    def progress_busy(self) -> None:
        self.progress.setRange(0, 0)

    def on_progress(self, stage: str, done: int, total: int) -> None:
        self.progress.setRange(0, max(1, total))
        self.progress.setValue(min(done, total))
        verbs = {"read": "reading", "write": "writing", "verify": "verifying"}
        self.progress.setToolTip(f"{verbs.get(stage, stage)} {done} of {total} bytes")

    def progress_complete(self, tip: str) -> None:
        """A flash went through: the bar stays full (until the next operation) and says what."""
        self.progress.setRange(0, 1)
        self.progress.setValue(1)
        self.progress.setToolTip(tip)

    def progress_done(self) -> None:
        self.progress.setRange(0, 1)
        self.progress.setValue(0)

    # -- the image ----------------------------------------------------------------------------
    def show_image(self, image: bytes) -> list[Slot]:
        """Show the macros in ``image``; returns them."""
        self.image = bytes(image)
        try:
            found = slots(self.image)
            used = used_bytes(self.image)
            broken = ""
        except Exception as exc:   # noqa: BLE001 - a broken record list
            found, used, broken = [], 0, str(exc)
        self.slots = found
        self.table.setRowCount(len(found))
        for row, s in enumerate(found):
            check = "ok" if s.ok else "BAD"
            values = (str(s.index), s.name, str(len(s.record)), record_chemistry(s.record) if s.ok else "?", check)
            for col, value in enumerate(values):
                item = QTableWidgetItem(value)
                if col in (0, 2):
                    item.setTextAlignment(Qt.AlignmentFlag.AlignRight | Qt.AlignmentFlag.AlignVCenter)
                if col == 4 and not s.ok:
                    item.setForeground(Qt.GlobalColor.red)
                    item.setToolTip(str(s.error.message if s.error else ""))
                self.table.setItem(row, col, item)
        size = len(self.image)
        if broken:
            self.free_label.setText(f"<span style='color:{colour(self, 'error')};'>broken record list: {broken}</span>")
        else:
            self.free_label.setText(f"{size - used} of {size} bytes free · {len(found)} macro(s)")
        keep_flash = self.flash_slot.currentData()
        self.flash_slot.clear()
        self.flash_slot.addItem("By name", None)
        for s in found:
            self.flash_slot.addItem(f"Replace slot {s.index} ({s.name})", s.index)
        self.flash_slot.addItem(f"Append as slot {len(found)}", len(found))
        k = self.flash_slot.findData(keep_flash)
        self.flash_slot.setCurrentIndex(k if k >= 0 and keep_flash is not None and keep_flash < len(found) else 0)
        return found

    def selected_row(self) -> int | None:
        rows = self.table.selectionModel().selectedRows()
        return rows[0].row() if rows else None

    def set_result(self, ok: bool, text: str) -> None:
        self.result_label.setText(text)
        self.result_label.setStyleSheet(f"color:{colour(self, 'ok' if ok else 'error')};")
