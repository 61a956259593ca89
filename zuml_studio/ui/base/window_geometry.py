"""The main window's size on a given screen: made for the screen on first start (a laptop at
1366x768 or a 1.5x-scaled desktop shows everything), a saved one kept only while it fits."""
from __future__ import annotations

import struct

from PySide6.QtCore import QPoint, QRect
from PySide6.QtGui import QGuiApplication
from PySide6.QtWidgets import QWidget

PREFERRED_W, PREFERRED_H = 1500, 950      # what the layout was drawn for
SCREEN_SHARE = 0.92                       # of the available area, when the screen is smaller
FIT_SLACK_PX = 16                         # frames and shadows may hang over the edge a little


def first_geometry(available: QRect, preferred_w: int = PREFERRED_W, preferred_h: int = PREFERRED_H) -> QRect:
    """The preferred size, shrunk to the screen's available area, centred in it."""
    width = min(preferred_w, int(available.width() * SCREEN_SHARE))
    height = min(preferred_h, int(available.height() * SCREEN_SHARE))
    rect = QRect(0, 0, width, height)
    rect.moveCenter(available.center())
    return rect


def place_on_screen(window: QWidget, preferred_w: int, preferred_h: int) -> None:
    """A window of its own at its preferred size, shrunk to the screen it opens on (its title bar
    and status line inside the screen: a 1200x760 window on a 768 px laptop hid its last lines), centred."""
    screen = window.screen() or QGuiApplication.primaryScreen()
    if screen is None:
        window.resize(preferred_w, preferred_h)
        return
    window.setGeometry(first_geometry(screen.availableGeometry(), preferred_w, preferred_h))


def fits(frame: QRect, available: QRect) -> bool:
    """Whether a window frame lies within the available area (within a few pixels)."""
    grown = available.adjusted(-FIT_SLACK_PX, -FIT_SLACK_PX, FIT_SLACK_PX, FIT_SLACK_PX)
    return grown.contains(frame)


GEOMETRY_MAGIC = 0x01D9D0CB               # QWidget::saveGeometry's first four bytes


def saved_frame(geometry: bytes) -> QRect | None:
    """The frame a saved geometry holds, as it was saved (restoreGeometry squeezes a frame into
    the screen, so a window saved on a bigger screen would seem to fit); None if unreadable."""
    if len(geometry) < 24:
        return None
    magic, _major, _minor, left, top, right, bottom = struct.unpack(">IHHiiii", geometry[:24])
    if magic != GEOMETRY_MAGIC:
        return None
    return QRect(QPoint(left, top), QPoint(right, bottom))
