"""The toolbar's icons, drawn in the palette's own colours: the style's standard pixmaps are
dark grey, and nearly vanish on the dark theme's toolbar. Each icon is a few strokes in the
text colour, with the action's part (the tick, the arrow, the play triangle) in the status
or accent colour of the palette's colour set, so it reads on light and dark alike."""
from __future__ import annotations

from PySide6.QtCore import QPointF, QRectF, Qt
from PySide6.QtGui import QColor, QIcon, QPainter, QPainterPath, QPalette, QPen, QPixmap, QPolygonF

from ..base import theme

SIZE = 24           # the icon's logical size; drawn at twice that for scaled screens
SCALE = 2


def _pen(colour: QColor, width: float = 1.8) -> QPen:
    pen = QPen(colour, width)
    pen.setJoinStyle(Qt.PenJoinStyle.RoundJoin)
    pen.setCapStyle(Qt.PenCapStyle.RoundCap)
    return pen


def _page(p: QPainter, ink: QColor) -> None:
    path = QPainterPath()
    path.moveTo(6, 3)
    path.lineTo(14, 3)
    path.lineTo(19, 8)
    path.lineTo(19, 21)
    path.lineTo(6, 21)
    path.closeSubpath()
    p.setPen(_pen(ink))
    p.drawPath(path)
    p.drawPolyline(QPolygonF([QPointF(14, 3), QPointF(14, 8), QPointF(19, 8)]))


def _folder(p: QPainter, ink: QColor, accent: QColor) -> None:
    p.setPen(_pen(ink))
    p.drawPolyline(QPolygonF([QPointF(3, 19), QPointF(3, 5), QPointF(9, 5), QPointF(11, 7), QPointF(19, 7),
                              QPointF(19, 10)]))
    shape = QPolygonF([QPointF(3, 19), QPointF(6, 10), QPointF(22, 10), QPointF(19, 19)])
    p.setBrush(accent)
    p.drawPolygon(shape)


def _disk(p: QPainter, ink: QColor, accent: QColor) -> None:
    p.setPen(_pen(ink))
    p.drawRoundedRect(QRectF(4, 4, 16, 16), 2, 2)
    p.setBrush(accent)
    p.drawRect(QRectF(8, 4, 8, 5))
    p.setBrush(Qt.BrushStyle.NoBrush)
    p.drawRect(QRectF(7, 13, 10, 7))


def _tick(p: QPainter, accent: QColor) -> None:
    p.setPen(_pen(accent, 3.0))
    p.drawPolyline(QPolygonF([QPointF(4, 13), QPointF(10, 19), QPointF(20, 5)]))


def _upload(p: QPainter, ink: QColor, accent: QColor) -> None:
    p.setPen(_pen(ink, 2.2))
    p.drawLine(QPointF(4, 21), QPointF(20, 21))
    p.setPen(_pen(accent, 1.2))
    p.setBrush(accent)
    p.drawPolygon(QPolygonF([QPointF(12, 3), QPointF(20, 11), QPointF(15, 11), QPointF(15, 18), QPointF(9, 18),
                             QPointF(9, 11), QPointF(4, 11)]))


def _play(p: QPainter, accent: QColor) -> None:
    p.setPen(_pen(accent, 1.2))
    p.setBrush(accent)
    p.drawPolygon(QPolygonF([QPointF(6, 4), QPointF(20, 12), QPointF(6, 20)]))


def toolbar_icon(name: str, palette: QPalette) -> QIcon:
    """The icon ``name`` ("new", "open", "save", "verify", "upload", "simulate") for ``palette``."""
    look = theme.colours(palette)
    ink = palette.color(QPalette.ColorRole.WindowText)
    ok = QColor(look.ok)
    accent = QColor(look.quantities["voltage"])
    pixmap = QPixmap(SIZE * SCALE, SIZE * SCALE)
    pixmap.fill(Qt.GlobalColor.transparent)
    p = QPainter(pixmap)
    p.setRenderHint(QPainter.RenderHint.Antialiasing)
    p.scale(SCALE, SCALE)
    if name == "new":
        _page(p, ink)
    elif name == "open":
        _folder(p, ink, accent)
    elif name == "save":
        _disk(p, ink, accent)
    elif name == "verify":
        _tick(p, ok)
    elif name == "upload":
        _upload(p, ink, accent)
    elif name == "simulate":
        _play(p, ok)
    else:
        raise KeyError(name)
    p.end()
    pixmap.setDevicePixelRatio(SCALE)
    return QIcon(pixmap)
