"""Value fields of the cards: a number with its unit (A / C / INPUT, V / V per cell / INPUT,
s / min / h, °C), a spin box for counts and seconds, an editable list for melodies and
lights. Each shows a stored value (``set_raw``) and reports the text to write
(``committed``) when the user finishes: Enter, leaving the field, or picking a unit —
never on every keystroke."""
from __future__ import annotations

from PySide6.QtCore import Qt, Signal
from PySide6.QtWidgets import QComboBox, QHBoxLayout, QLabel, QLineEdit, QSpinBox, QWidget

from ...i18n import N_, _
from ...lang import operands as k
from ...lang.opcodes import Operand
from ...lang.operands import format_scaled

_UNITS = {
    k.CURRENT: [("A", "A"), ("C", "C"), ("INPUT", "INPUT")],
    k.VOLTAGE: [("V", "V"), ("S", "V/cell"), ("INPUT", "INPUT")],      # units: never translated
    k.TIME: [("s", "s"), ("min", "min"), ("h", "h")],
}
_SUFFIX = {k.CELSIUS: "°C"}
_UNIT_TIPS = {"C": N_("times the capacity"), "S": N_("per cell (S)"), "INPUT": N_("entered on the charger at start")}


class Field(QWidget):
    """Base: ``committed(text)`` carries the operand's new text."""

    committed = Signal(str)

    def set_raw(self, raw: int) -> None:
        raise NotImplementedError

    def value_text(self) -> str:
        raise NotImplementedError

    def busy(self) -> bool:
        """The user is typing here: a refresh must not overwrite it."""
        return False


class NumberUnitField(Field):
    """A number and its unit; INPUT leaves the number out."""

    def __init__(self, operand: Operand, parent: QWidget | None = None):
        super().__init__(parent)
        self.kind = operand.kind
        self.line = QLineEdit()
        self.line.setObjectName("valueNumber")
        self.line.setAlignment(Qt.AlignmentFlag.AlignRight)
        self.line.setFixedWidth(62)
        self.line.editingFinished.connect(self._commit)
        policy = self.line.sizePolicy()
        policy.setRetainSizeWhenHidden(True)          # INPUT hides the number; the unit stays in place
        self.line.setSizePolicy(policy)
        layout = QHBoxLayout(self)
        layout.setContentsMargins(0, 0, 0, 0)
        layout.setSpacing(4)
        layout.addWidget(self.line)
        self.unit: QComboBox | None = None
        if self.kind in _UNITS:
            self.unit = QComboBox()
            self.unit.setObjectName("valueUnit")
            for key, label in _UNITS[self.kind]:
                self.unit.addItem(label, key)
                if key in _UNIT_TIPS:
                    self.unit.setItemData(self.unit.count() - 1, _(_UNIT_TIPS[key]), Qt.ItemDataRole.ToolTipRole)
            self.unit.activated.connect(self._unit_picked)
            layout.addWidget(self.unit)
        elif self.kind in _SUFFIX:
            suffix = QLabel(_SUFFIX[self.kind])
            suffix.setProperty("role", "unit")
            layout.addWidget(suffix)
        layout.addStretch(1)
        self._shown = ""

    # -- showing ---------------------------------------------------------------------------
    def set_raw(self, raw: int) -> None:
        number, unit = self._split(raw)
        self.line.setText(number)
        self.line.setVisible(unit != "INPUT")
        self.line.setModified(False)
        if self.unit is not None:
            self.unit.setCurrentIndex(max(0, self.unit.findData(unit)))
        self._shown = self.value_text()

    def _split(self, raw: int) -> tuple[str, str]:
        if self.kind in (k.CURRENT, k.VOLTAGE):
            if raw == k.INPUT_U16:
                return "", "INPUT"
            flag = bool(raw & k.RELATIVE_FLAG)
            unit = ("C" if self.kind is k.CURRENT else "S") if flag else ("A" if self.kind is k.CURRENT else "V")
            return format_scaled(raw & 0x7FFF, 100), unit
        if self.kind is k.TIME:
            for unit, tenths in (("h", 36000), ("min", 600)):
                if raw and raw % tenths == 0:
                    return str(raw // tenths), unit
            return format_scaled(raw, 10), "s"
        return str(raw), ""

    def value_text(self) -> str:
        unit = self.unit.currentData() if self.unit is not None else ""
        if unit == "INPUT":
            return "INPUT"
        number = self.line.text().strip().replace(",", ".")
        return f"{number}{unit}"

    def busy(self) -> bool:
        return self.line.hasFocus() and self.line.isModified()

    # -- editing ---------------------------------------------------------------------------
    def _unit_picked(self, _index: int) -> None:
        is_input = self.unit.currentData() == "INPUT"
        self.line.setVisible(not is_input)
        if not is_input and not self.line.text().strip():
            self.line.setText("1")
        self._commit()

    def _commit(self) -> None:
        # Committed, the field is no longer being typed in: should the edit be refused, the refresh
        # that follows puts the stored value back although the cursor is still here.
        self.line.setModified(False)
        text = self.value_text()
        if text != self._shown:
            self._shown = text
            self.committed.emit(text)


class SpinField(Field):
    """A whole number in the operand's range (counts, seconds, measuring point)."""

    def __init__(self, operand: Operand, parent: QWidget | None = None, suffix: str = ""):
        super().__init__(parent)
        self.spin = QSpinBox()
        self.spin.setObjectName("valueSpin")
        lo, hi = operand.kind.raw_limits()
        self.spin.setRange(operand.lo if operand.lo is not None else lo, operand.hi if operand.hi is not None else hi)
        self.spin.setKeyboardTracking(False)
        self.spin.setFixedWidth(64)
        if suffix:
            self.spin.setSuffix(suffix)
        self.spin.editingFinished.connect(self._commit)
        self.spin.valueChanged.connect(self._stepped)
        self._typing = False            # digits typed and not yet committed
        self.spin.lineEdit().textEdited.connect(lambda _text: setattr(self, "_typing", True))
        layout = QHBoxLayout(self)
        layout.setContentsMargins(0, 0, 0, 0)
        layout.addWidget(self.spin)
        layout.addStretch(1)
        self._shown = None
        self._setting = False

    def set_raw(self, raw: int) -> None:
        self._setting = True
        self.spin.setValue(raw)
        self._setting = False
        self._shown = raw

    def value_text(self) -> str:
        return str(self.spin.value())

    def busy(self) -> bool:
        return self.spin.hasFocus() and self._typing

    def _stepped(self, _value: int) -> None:
        # The arrows (or the wheel) commit at once; typed digits wait for Enter / leaving.
        if not self._setting and not self.spin.lineEdit().hasFocus():
            self._commit()

    def _commit(self) -> None:
        self._typing = False
        if self.spin.value() != self._shown:
            self._shown = self.spin.value()
            self.committed.emit(str(self._shown))


class NamedField(Field):
    """A symbolic value or a number: melodies (START, STOP…) and light patterns (SLOW, FAST…)."""

    def __init__(self, operand: Operand, parent: QWidget | None = None):
        super().__init__(parent)
        self.kind = operand.kind
        self.combo = QComboBox()
        self.combo.setObjectName("valueNamed")
        self.combo.setEditable(True)
        self.combo.setInsertPolicy(QComboBox.InsertPolicy.NoInsert)
        self.combo.addItems(list(self.kind.names))
        self.combo.setMinimumContentsLength(7)
        self.combo.activated.connect(lambda _i: self._commit())
        self.combo.lineEdit().editingFinished.connect(self._commit)
        self._typing = False            # a name typed and not yet committed
        self.combo.lineEdit().textEdited.connect(lambda _text: setattr(self, "_typing", True))
        layout = QHBoxLayout(self)
        layout.setContentsMargins(0, 0, 0, 0)
        layout.addWidget(self.combo)
        self._shown = ""

    def set_raw(self, raw: int) -> None:
        self.combo.setEditText(self.kind.format(raw))
        self._shown = self.value_text()

    def value_text(self) -> str:
        return self.combo.currentText().strip()

    def busy(self) -> bool:
        return self.combo.hasFocus() and self._typing

    def _commit(self) -> None:
        self._typing = False
        text = self.value_text()
        if text and text.upper() != self._shown.upper():
            self._shown = text
            self.committed.emit(text)


def make_field(operand: Operand, parent: QWidget | None = None) -> Field:
    """The field that edits one operand, chosen by its kind."""
    if operand.kind in (k.CURRENT, k.VOLTAGE, k.TIME, k.CELSIUS):
        return NumberUnitField(operand, parent)
    if operand.kind in (k.MELODY, k.LIGHT):
        return NamedField(operand, parent)
    return SpinField(operand, parent, " s" if operand.kind is k.SECONDS else "")
