"""The spin boxes of the parameter forms (simulator start values, device panel): right-aligned,
one change per typed number rather than per digit, growing with the form up to a width."""
from __future__ import annotations

from PySide6.QtCore import Qt
from PySide6.QtWidgets import QAbstractSpinBox, QDoubleSpinBox, QSizePolicy, QSpinBox, QWidget


def form_field(widget: QWidget, max_width: int | None = None, min_width: int | None = None) -> QWidget:
    if max_width is not None:
        widget.setMaximumWidth(max_width)
    if min_width is not None:
        widget.setMinimumWidth(min_width)
    widget.setSizePolicy(QSizePolicy.Policy.Expanding, QSizePolicy.Policy.Fixed)
    if isinstance(widget, QAbstractSpinBox):
        widget.setKeyboardTracking(False)       # one change per typed number, not per digit
        widget.setAlignment(Qt.AlignmentFlag.AlignRight)
    return widget


def spin_box(lo: int, hi: int, value: int, suffix: str, tip: str) -> QSpinBox:
    box = QSpinBox()
    box.setRange(lo, hi)
    box.setValue(value)
    box.setSuffix(suffix)
    box.setToolTip(tip)
    return box


def double_spin_box(lo: float, hi: float, value: float, suffix: str, decimals: int, step: float,
                    tip: str) -> QDoubleSpinBox:
    box = QDoubleSpinBox()
    box.setDecimals(decimals)
    box.setRange(lo, hi)
    box.setSingleStep(step)
    box.setValue(value)
    box.setSuffix(suffix)
    box.setToolTip(tip)
    return box
