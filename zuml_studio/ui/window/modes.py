"""The window's modes: Write (the editor in front), Simulate (the simulator's plot takes the
window) and Charge (the device panel's live plot does). A mode is an arrangement of the same
docks: each mode's layout, as the user left it, is kept in the settings and comes back with
the mode; a mode never seen starts from its first layout (``docks.place``)."""
from __future__ import annotations

from collections.abc import Callable

from PySide6.QtCore import QObject, QSettings, QTimer, Signal
from PySide6.QtWidgets import QMainWindow, QWidget

from ..base.settings_values import bytes_value, text_value
from .docks import CHARGE, MODES, WRITE

MODE_KEY = "layout/mode"


def layout_key(mode: str) -> str:
    return f"layout/{mode}"


class Modes(QObject):
    """Switches the window between the modes, keeping each one's layout."""
    changed = Signal(str)

    def __init__(self, window: QMainWindow, settings: QSettings, editor: QWidget, place: Callable[[str], None],
                 version: int, readable: Callable[[], object] = lambda: None):
        super().__init__(window)
        self.window = window
        self.settings = settings
        self.editor = editor             # the central widget: only the Write mode shows it
        self.place = place
        self.readable = readable         # docks a restored layout left too small get their first size back
        self.version = version           # a saved layout of another version is ignored
        saved = text_value(settings, MODE_KEY, WRITE)
        self.current = saved if saved in MODES else WRITE

    def restore(self) -> None:
        """At start: the mode the window closed in, with its layout."""
        self._apply()

    def switch(self, mode: str) -> None:
        """Keep the present mode's layout, then arrange ``mode``'s."""
        if mode not in MODES:
            raise ValueError(f"unknown mode {mode!r}: one of {', '.join(MODES)}")
        if mode == self.current:
            self.changed.emit(mode)      # the menu's check mark follows even when nothing moves
            return
        self.save()
        self.current = mode
        self._apply()

    def reset(self) -> None:
        """The present mode back to its first layout (its saved one forgotten)."""
        self.settings.remove(layout_key(self.current))
        self._apply()

    def save(self) -> None:
        self.settings.setValue(layout_key(self.current), self.window.saveState(self.version))
        self.settings.setValue(MODE_KEY, self.current)

    def _apply(self) -> None:
        size = self.window.size()       # a layout saved on a bigger screen must not grow the window
        self.editor.setVisible(self.current == WRITE)
        # Watching a charge, the editor's status line (line, column, bytes) has nothing to say and
        # the device panel has its own message line: the live plot takes the row.
        self.window.statusBar().setVisible(self.current != CHARGE)
        device = getattr(self.window, "device_dock", None)
        if device is not None:          # the mode's one dock: its title bar says nothing either
            device.setTitleBarWidget(QWidget(device) if self.current == CHARGE else None)
        state = bytes_value(self.settings, layout_key(self.current))
        if state is None or not self.window.restoreState(state, self.version):
            self.place(self.current)
        else:                           # once the window has laid the restored docks out at its size
            QTimer.singleShot(0, self.readable)
        self.window.resize(size)
        self.changed.emit(self.current)
