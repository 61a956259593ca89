"""Add a pack to the register: name, chemistry, cells, rated capacity, date bought, passport serial, notes."""
from __future__ import annotations

from PySide6.QtCore import QDate
from PySide6.QtWidgets import (QCheckBox, QComboBox, QDateEdit, QDialog, QDialogButtonBox, QFormLayout, QLabel,
                               QLineEdit, QPlainTextEdit, QSpinBox)

from ...packs.db import Logbook, LogbookError
from ...packs.register import Pack, PackError, add_pack
from ..base import theme
from ...i18n import _

CHEMISTRIES = ("LiPo", "LiIon", "LiFe", "NiMh", "NiCd", "Pb")


class AddPackDialog(QDialog):
    def __init__(self, book: Logbook, parent=None, serial: str = ""):
        super().__init__(parent)
        self.book = book
        self.pack: Pack | None = None
        self.setWindowTitle(_("Add a Pack"))
        form = QFormLayout(self)
        self.name = QLineEdit()
        self.name.setPlaceholderText(_("e.g. Turnigy 4S #2"))
        self.chemistry = QComboBox()
        self.chemistry.addItems(CHEMISTRIES)
        self.cells = QSpinBox()
        self.cells.setRange(1, 32)
        self.cells.setValue(4)
        self.capacity = QSpinBox()
        self.capacity.setRange(1, 1_000_000)
        self.capacity.setSingleStep(100)
        self.capacity.setValue(2200)
        self.capacity.setSuffix(" mAh")
        self.bought_known = QCheckBox(_("known"))
        self.bought = QDateEdit(QDate.currentDate())
        self.bought.setCalendarPopup(True)
        self.bought.setDisplayFormat("yyyy-MM-dd")
        self.bought.setEnabled(False)
        self.bought_known.toggled.connect(self.bought.setEnabled)
        self.serial = QLineEdit(serial)
        self.serial.setPlaceholderText(_("the passport's serial, if the battery has one"))
        self.notes = QPlainTextEdit()
        self.notes.setFixedHeight(60)
        self.error = QLabel()
        self.error.setWordWrap(True)
        self.error.setStyleSheet(f"color: {theme.colours(self.palette()).error}")
        form.addRow(_("Name"), self.name)
        form.addRow(_("Chemistry"), self.chemistry)
        form.addRow(_("Cells in series"), self.cells)
        form.addRow(_("Rated capacity"), self.capacity)
        form.addRow(_("Bought"), self.bought)
        form.addRow("", self.bought_known)
        form.addRow(_("Serial"), self.serial)
        form.addRow(_("Notes"), self.notes)
        form.addRow(self.error)
        buttons = QDialogButtonBox(QDialogButtonBox.StandardButton.Ok | QDialogButtonBox.StandardButton.Cancel)
        buttons.accepted.connect(self.accept)
        buttons.rejected.connect(self.reject)
        form.addRow(buttons)

    def accept(self) -> None:
        """Adds the pack; a value the register refuses is shown here and the dialog stays."""
        try:
            self.pack = add_pack(
                    self.book, self.name.text().strip(), self.chemistry.currentText(), self.cells.value(),
                    float(self.capacity.value()),
                    bought=self.bought.date().toString("yyyy-MM-dd") if self.bought_known.isChecked() else None,
                    notes=self.notes.toPlainText().strip(), serial=self.serial.text().strip() or None)
        except (PackError, LogbookError) as exc:
            self.error.setText(str(exc))
            return
        super().accept()
