"""What the device panel's parts share: message colours, headings, rules and form fields."""
from __future__ import annotations

from PySide6.QtCore import Qt
from PySide6.QtWidgets import QDoubleSpinBox, QFrame, QLabel, QSizePolicy, QSpinBox, QWidget

from .. import theme
from ..number_boxes import double_spin_box, form_field, spin_box

FIELD_WIDTH = 92
DEFAULT_BATTERY = ("NiMh", 2000, 4)


def colour(widget: QWidget, kind: str) -> str:
    """A message colour ("info", "ok", "error", "warn") readable on the widget's palette."""
    c = theme.colours(widget.palette())
    return {"ok": c.ok, "error": c.error, "warn": c.warning}.get(kind, c.muted)


def heading(text: str) -> QLabel:
    label = QLabel(text)
    font = label.font()
    font.setBold(True)
    label.setFont(font)
    return label


def vline() -> QFrame:
    line = QFrame()
    line.setFrameShape(QFrame.Shape.VLine)
    line.setFrameShadow(QFrame.Shadow.Plain)
    line.setStyleSheet("color:#d8d8d8;")
    return line


def field_spin(*args) -> QSpinBox:
    return form_field(spin_box(*args), min_width=60)


def field_double(*args) -> QDoubleSpinBox:
    return form_field(double_spin_box(*args), min_width=60)


class ElidedLabel(QLabel):
    """A one-line label that elides its (plain) text to its width; the whole text is the tooltip."""

    def __init__(self, text: str = "", parent: QWidget | None = None,
                 mode: Qt.TextElideMode = Qt.TextElideMode.ElideRight):
        super().__init__(parent)
        self._full = ""
        self._mode = mode
        self.setSizePolicy(QSizePolicy.Policy.Ignored, QSizePolicy.Policy.Preferred)
        self.setMinimumWidth(40)
        self.set_full_text(text)

    def set_full_text(self, text: str) -> None:
        self._full = text
        self.setToolTip(text)
        self._elide()

    def full_text(self) -> str:
        return self._full

    def resizeEvent(self, event) -> None:  # noqa: N802
        super().resizeEvent(event)
        self._elide()

    def _elide(self) -> None:
        width = max(10, self.width() - 2)
        super().setText(self.fontMetrics().elidedText(self._full, self._mode, width))
