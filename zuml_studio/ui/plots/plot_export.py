"""Export a plot as a PNG a report can use: a title and lines of details (the macro, the
battery, the parameters) above the plot, laid out at the size asked for (not a scaled
screen grab: text keeps its size, the plot gets the room). The header is on the plot's paper, in
its ink (a dark theme exports a dark image)."""
from __future__ import annotations

from PySide6.QtCore import QEvent, QSize, Qt
from PySide6.QtGui import QColor, QFont, QFontMetrics, QImage, QPainter
from PySide6.QtWidgets import (QApplication, QDialog, QDialogButtonBox, QFormLayout, QHBoxLayout, QLabel, QLineEdit,
                               QSpinBox, QWidget)

from ...i18n import _
from ..base import theme

MIN_SIZE, MAX_SIZE = 320, 8000
DEFAULT_SIZE = (1600, 1000)
MARGIN_PX = 12


def _fonts(base: QFont) -> tuple[QFont, QFont]:
    title = QFont(base)
    title.setPointSizeF(base.pointSizeF() + 4)
    title.setBold(True)
    return title, QFont(base)


def render_with_header(widget: QWidget, size: QSize, title: str, details: list[str]) -> QImage:
    """The widget laid out at ``size`` less the header, under the title and details, on the
    widget's paper."""
    title_font, detail_font = _fonts(widget.font())
    lines = [(title_font, title)] * bool(title) + [(detail_font, line) for line in details if line]
    header = MARGIN_PX + sum(QFontMetrics(font).lineSpacing() for font, _ in lines) + MARGIN_PX // 2 * bool(lines)
    old = widget.size()
    widget.resize(size.width(), max(size.height() - header, 100))
    QApplication.sendPostedEvents(None, QEvent.Type.LayoutRequest.value)    # lay out at this size now
    plot = widget.grab()
    widget.resize(old)
    image = QImage(size, QImage.Format.Format_RGB32)
    look = theme.colours(widget.palette()).plot
    image.fill(QColor(look.paper))
    painter = QPainter(image)
    painter.setPen(QColor(look.ink))
    y = MARGIN_PX
    for font, text in lines:
        painter.setFont(font)
        metrics = QFontMetrics(font)
        painter.drawText(MARGIN_PX, y + metrics.ascent(), metrics.elidedText(text, Qt.TextElideMode.ElideRight,
                                                                              size.width() - 2 * MARGIN_PX))
        y += metrics.lineSpacing()
    painter.drawPixmap(0, header, plot)
    painter.end()
    return image


class PlotExportDialog(QDialog):
    """The title and the size of an exported plot."""

    def __init__(self, title: str, parent: QWidget | None = None):
        super().__init__(parent)
        self.setObjectName("plotExportDialog")
        self.setWindowTitle(_("Export plot as PNG"))
        self.title = QLineEdit(title)
        self.title.setObjectName("exportTitle")
        self.width_box, self.height_box = QSpinBox(), QSpinBox()
        for box, value in zip((self.width_box, self.height_box), DEFAULT_SIZE):
            box.setRange(MIN_SIZE, MAX_SIZE)
            box.setSuffix(" px")
            box.setValue(value)
        size_row = QHBoxLayout()
        size_row.addWidget(self.width_box)
        size_row.addWidget(QLabel("×"))
        size_row.addWidget(self.height_box)
        size_row.addStretch(1)
        buttons = QDialogButtonBox(QDialogButtonBox.StandardButton.Ok | QDialogButtonBox.StandardButton.Cancel)
        buttons.accepted.connect(self.accept)
        buttons.rejected.connect(self.reject)
        form = QFormLayout(self)
        form.addRow(_("Title"), self.title)
        form.addRow(_("Size"), size_row)
        form.addRow(QLabel(_("The macro, the battery and the parameters are written under the title.")))
        form.addRow(buttons)

    def chosen(self) -> tuple[str, QSize]:
        return self.title.text(), QSize(self.width_box.value(), self.height_box.value())
