"""The CSV import dialog: what ``logs.csv_import`` guessed of a CSV (separator, decimal comma,
each column's role and unit, with the first rows' values), for the user to correct. The log
window remembers the accepted columns per header (``CsvChoices``) and reads the file with them."""
from __future__ import annotations

import hashlib

from PySide6.QtCore import QSettings
from PySide6.QtWidgets import (QComboBox, QDialog, QDialogButtonBox, QLabel, QTableWidget, QTableWidgetItem,
                               QVBoxLayout, QWidget)

from ...i18n import N_, _
from ...logs import csv_import

ROLE_WORDS = {"time": N_("time"), "voltage": N_("pack voltage"), "current": N_("current"),
              "temp": N_("battery temperature"), "charge": N_("charge counter"), "cell": N_("cell voltage"),
              "-": N_("not used")}
SEPARATOR_WORDS = {";": N_("semicolon"), "\t": N_("tab"), ",": N_("comma"), "|": N_("bar")}
PREVIEW_ROWS = 3


def key_hash(key: str) -> str:
    """A CSV header as a settings key."""
    return hashlib.sha1(key.encode()).hexdigest()[:20]


class CsvChoices:
    """The columns the user accepted, per CSV header (``CsvGuess.key``), in the settings when
    there are any (else for this session)."""

    GROUP = "csvColumns"

    def __init__(self, settings: QSettings | None):
        self.settings = settings
        self._session: dict[str, str] = {}

    def snapshot(self) -> dict[str, str]:
        """key_hash -> spec of every choice, for a reader thread."""
        if self.settings is None:
            return dict(self._session)
        self.settings.beginGroup(self.GROUP)
        try:
            return {name: str(self.settings.value(name)) for name in self.settings.childKeys()}
        finally:
            self.settings.endGroup()

    def put(self, key: str, spec: str) -> None:
        if self.settings is not None:
            self.settings.setValue(f"{self.GROUP}/{key_hash(key)}", spec)
        else:
            self._session[key_hash(key)] = spec


class CsvDialog(QDialog):
    """One row per column: its name, the role and unit (combo boxes) and the first values."""

    def __init__(self, name: str, data: bytes, spec: str | None = None, parent: QWidget | None = None):
        super().__init__(parent)
        self.setObjectName("csvDialog")
        self.setWindowTitle(_("CSV columns: {name}").format(name=name))
        self.guess = csv_import.guess(data)
        assumed = self.guess.assumptions() if spec in (None, "", self.guess.spec()) else []
        if spec:
            self.guess = self.guess.with_columns(
                csv_import.parse_columns(spec, tuple(c.name for c in self.guess.columns)))
        g = self.guess
        about = _("Separator: {separator}; decimal {mark}; header on line {line}. Correct what the guess got "
                  "wrong: it is kept for CSVs with these columns.").format(
            separator=_(SEPARATOR_WORDS[g.separator]), mark=_("comma") if g.decimal_comma else _("point"),
            line=g.header_line + 1)
        if assumed:
            about += "\n" + _("Units the header does not give (check them):") + "\n" + "\n".join(
                    "  " + line for line in assumed)
        label = QLabel(about)
        label.setObjectName("csvAbout")
        label.setWordWrap(True)
        rows = csv_import.preview(data, g, PREVIEW_ROWS)
        self.table = QTableWidget(len(g.columns), 3 + len(rows))
        self.table.setObjectName("csvColumns")
        self.table.setHorizontalHeaderLabels([_("column"), _("is"), _("unit")]
                                             + [_("row {n}").format(n=k + 1) for k in range(len(rows))])
        self.roles: list[QComboBox] = []
        self.units: list[QComboBox] = []
        for k, column in enumerate(g.columns):
            self.table.setItem(k, 0, QTableWidgetItem(column.name))
            role = QComboBox()
            for value in csv_import.ROLES:
                role.addItem(_(ROLE_WORDS[value]), value)
            role.setCurrentIndex(role.findData(column.role))
            unit = QComboBox()
            self.roles.append(role)
            self.units.append(unit)
            self._fill_units(k, column.unit)
            role.currentIndexChanged.connect(lambda _i, k=k: self._fill_units(k, ""))
            self.table.setCellWidget(k, 1, role)
            self.table.setCellWidget(k, 2, unit)
            for r, row in enumerate(rows):
                self.table.setItem(k, 3 + r, QTableWidgetItem(row[k] if k < len(row) else ""))
        self.table.resizeColumnsToContents()
        self.error = QLabel()
        self.error.setObjectName("csvError")
        self.buttons = buttons = QDialogButtonBox(QDialogButtonBox.StandardButton.Ok
                                                  | QDialogButtonBox.StandardButton.Cancel)
        buttons.accepted.connect(self._accept)
        buttons.rejected.connect(self.reject)
        layout = QVBoxLayout(self)
        layout.addWidget(label)
        layout.addWidget(self.table)
        layout.addWidget(self.error)
        layout.addWidget(buttons)
        self.resize(720, 420)

    def accept_button(self):
        return self.buttons.button(QDialogButtonBox.StandardButton.Ok)

    def _fill_units(self, k: int, unit: str) -> None:
        box = self.units[k]
        box.clear()
        for value in csv_import.UNITS[self.roles[k].currentData()]:
            box.addItem(value, value)
        box.setCurrentIndex(max(0, box.findData(unit)))
        box.setEnabled(box.count() > 1)

    def spec(self) -> str:
        """The columns as chosen, in ``--columns`` form."""
        return ",".join("-" if role.currentData() == "-" else f"{role.currentData()}:{unit.currentData()}"
                        for role, unit in zip(self.roles, self.units))

    def _accept(self) -> None:
        g = self.guess.with_columns(csv_import.parse_columns(self.spec(), tuple(c.name for c in self.guess.columns)))
        try:
            csv_import.check(g)
        except csv_import.LogFormatError as exc:
            self.error.setText(str(exc))
            return
        self.accept()
