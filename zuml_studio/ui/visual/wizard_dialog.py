"""The new-macro wizard: a few answers (chemistry, cells, capacity, charge rate, sensor) and a
live preview of the macro ``zuml_studio.wizard.new_macro`` writes from them. A problem with the
answers (``WizardError``) shows as one red line and keeps OK disabled."""
from __future__ import annotations

from PySide6.QtGui import QFontDatabase
from PySide6.QtWidgets import (QCheckBox, QComboBox, QDialog, QDialogButtonBox, QFormLayout, QHBoxLayout, QLabel,
                               QLineEdit, QPlainTextEdit, QSpinBox, QVBoxLayout, QWidget)

from ...i18n import _, ngettext
from ...lang.compiler import compile_source
from ...domain.chemistry import chemistry_names
from ...wizard import Answers, WizardError, choices, new_macro


def default_rate(chemistry: str) -> float:
    """The chemistry's default charge rate in C, from the package's data/templates.toml."""
    return float(choices(chemistry)["default_rate_c"])


def parse_rate(text: str) -> float | None:
    """'' -> None (the default); '0.5', '0.5C', '0,5 c' -> 0.5; WizardError otherwise."""
    text = text.strip().replace(",", ".")
    if not text:
        return None
    if text[-1] in "cC":
        text = text[:-1].strip()
    try:
        value = float(text)
    except ValueError:
        raise WizardError(_("charge rate: a number of C, like 0.5 (or leave it empty for the default)")) from None
    if value != value or value in (float("inf"), float("-inf")):
        raise WizardError(_("charge rate: a number of C, like 0.5"))
    return value


class NewMacroWizard(QDialog):
    """Asks for the answers and previews the macro; ``text()`` is the macro to open."""

    def __init__(self, parent: QWidget | None = None, chemistry: str = "LiPo"):
        super().__init__(parent)
        self.setObjectName("newMacroWizard")
        self.setWindowTitle(_("New macro"))
        self._text = ""
        self._error = ""

        self.chemistry = QComboBox()
        self.chemistry.setObjectName("wizardChemistry")
        self.chemistry.addItems(chemistry_names())
        if chemistry in chemistry_names():
            self.chemistry.setCurrentText(chemistry)
        self.cells = QSpinBox()
        self.cells.setObjectName("wizardCells")
        self.cells.setRange(1, 255)
        self.cells.setValue(3)
        self.cells.setSuffix(" " + _("in series"))
        self.capacity = QSpinBox()
        self.capacity.setObjectName("wizardCapacity")
        self.capacity.setRange(2, 65534)
        self.capacity.setSingleStep(100)
        self.capacity.setValue(2200)
        self.capacity.setSuffix(" mAh")
        self.rate = QLineEdit()
        self.rate.setObjectName("wizardRate")
        self.rate.setClearButtonEnabled(True)
        self.rate.setToolTip(_("Charge rate in C (times the capacity). Empty: the chemistry's default."))
        self.sensor = QCheckBox(_("A temperature sensor is fitted"))
        self.sensor.setObjectName("wizardSensor")

        rate_row = QHBoxLayout()
        rate_row.addWidget(self.rate, 1)
        rate_row.addWidget(QLabel("C"))
        form = QFormLayout()
        form.setFieldGrowthPolicy(QFormLayout.FieldGrowthPolicy.AllNonFixedFieldsGrow)
        form.addRow(_("Chemistry"), self.chemistry)
        form.addRow(_("Cells"), self.cells)
        form.addRow(_("Capacity"), self.capacity)
        form.addRow(_("Charge rate"), rate_row)
        form.addRow("", self.sensor)

        self.error = QLabel("")
        self.error.setObjectName("wizardError")
        self.error.setWordWrap(True)
        self.error.setStyleSheet("color:#b00020; font-weight:600;")
        self.summary = QLabel("")
        self.summary.setObjectName("wizardSummary")
        self.summary.setStyleSheet("color:#4a5563;")

        self.preview = QPlainTextEdit()
        self.preview.setObjectName("wizardPreview")
        self.preview.setReadOnly(True)
        self.preview.setFont(QFontDatabase.systemFont(QFontDatabase.SystemFont.FixedFont))
        self.preview.setLineWrapMode(QPlainTextEdit.LineWrapMode.NoWrap)
        self.preview.setMinimumWidth(420)

        self.buttons = QDialogButtonBox(QDialogButtonBox.StandardButton.Ok | QDialogButtonBox.StandardButton.Cancel)
        self.buttons.button(QDialogButtonBox.StandardButton.Ok).setText(_("Create"))
        self.buttons.accepted.connect(self.accept)
        self.buttons.rejected.connect(self.reject)

        left = QVBoxLayout()
        left.addLayout(form)
        left.addStretch(1)
        right = QVBoxLayout()
        right.addWidget(QLabel(_("Preview")))
        right.addWidget(self.preview, 1)
        right.addWidget(self.summary)
        top = QHBoxLayout()
        top.addLayout(left)
        top.addLayout(right, 1)
        layout = QVBoxLayout(self)
        layout.addLayout(top, 1)
        layout.addWidget(self.error)
        layout.addWidget(self.buttons)

        self.chemistry.currentTextChanged.connect(self._chemistry_changed)
        self.cells.valueChanged.connect(self.update_preview)
        self.capacity.valueChanged.connect(self.update_preview)
        self.rate.textChanged.connect(self.update_preview)
        self.sensor.toggled.connect(self.update_preview)
        self.resize(820, 480)
        self._chemistry_changed(self.chemistry.currentText())

    def ok_button(self):
        return self.buttons.button(QDialogButtonBox.StandardButton.Ok)

    def _chemistry_changed(self, name: str) -> None:
        rate = default_rate(name)
        self.rate.setPlaceholderText(_("default {rate}").format(rate=f"{rate:g}"))
        self.update_preview()

    def answers(self) -> Answers:
        return Answers(self.chemistry.currentText(), self.cells.value(), self.capacity.value(),
                       parse_rate(self.rate.text()), self.sensor.isChecked())

    def update_preview(self) -> None:
        try:
            text = new_macro(self.answers())
        except WizardError as exc:
            self._error = str(exc)
            self._text = ""
            self.error.setText("✖ " + self._error[:1].upper() + self._error[1:])
            self.error.show()
            self.preview.setPlainText("")
            self.summary.setText("")
            self.ok_button().setEnabled(False)
            return
        self._error = ""
        self._text = text
        self.error.setText("")
        self.error.hide()
        self.preview.setPlainText(text)
        result = compile_source(text)
        if result.ok:
            warnings = len(result.diagnostics)
            self.summary.setText("✔ " + _("valid, {size} bytes").format(size=len(result.record)) +
                                 (", " + ngettext("{n} warning", "{n} warnings", warnings).format(n=warnings)
                                  if warnings else ""))
        else:
            errors = len(result.errors)
            self.summary.setText("✖ " + ngettext("{n} error", "{n} errors", errors).format(n=errors)
                                 + f": {result.errors[0].message}")
        self.ok_button().setEnabled(result.ok)

    def text(self) -> str:
        """The macro the answers give ('' while they have a problem)."""
        return self._text
