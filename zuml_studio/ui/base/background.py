"""One call off the GUI thread (a model fit, a simulation started from a dialog): the window
keeps painting while it runs, and its result or its exception arrives on the GUI thread."""
from __future__ import annotations

from collections.abc import Callable

from PySide6.QtCore import QThread, Signal


class BackgroundCall(QThread):
    """Runs ``fn()`` once; ``done(result)`` or ``failed(exception)`` follows, queued to the
    receivers' (GUI) thread. ``fn`` may call ``report(done, total)`` to say how far it is
    (``progress``, queued the same way)."""

    done = Signal(object)
    failed = Signal(object)
    progress = Signal(int, int)

    def __init__(self, fn: Callable[[], object], parent=None):
        super().__init__(parent)
        self._fn = fn

    def report(self, done: int, total: int) -> None:
        self.progress.emit(done, total)

    def run(self) -> None:
        try:
            result = self._fn()
        except Exception as exc:   # noqa: BLE001 - handed to the caller, who says it to the user
            self.failed.emit(exc)
            return
        self.done.emit(result)
