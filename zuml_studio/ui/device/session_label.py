"""The session CSV (``logs.session_log``: every frame and event the charger sent, written by
the reader thread) and the line under the plot that names it, its rows and its trouble."""
from __future__ import annotations

from pathlib import Path

from PySide6.QtCore import Qt
from PySide6.QtWidgets import QWidget

from ...logs.session_log import IDLE_LOG_S, SessionLog, display_path, session_path
from ...i18n import _, ngettext
from .device_style import ElidedLabel, tint


class SessionLabel(ElidedLabel):
    def __init__(self, folder: Path, parent: QWidget | None = None):
        super().__init__("", parent, mode=Qt.TextElideMode.ElideMiddle)
        self.setObjectName("sessionLabel")
        tint(self, "info")
        self.setAlignment(Qt.AlignmentFlag.AlignRight | Qt.AlignmentFlag.AlignVCenter)
        self.folder = Path(folder)
        self.log: SessionLog | None = None
        self.path: Path | None = None           # the CSV written last (kept after it is closed)
        self._error_said = False

    def open(self, cells: int | None = 0, idle_s: float = IDLE_LOG_S) -> None:
        """A new CSV in the folder (``cells``: None for a monitor-only charger's columns)."""
        self.close()
        try:
            self.log = SessionLog(session_path(self.folder), cells=cells, idle_s=idle_s)
        except OSError as exc:
            self.log = None
            self.set_full_text(_("no session CSV: cannot write in {folder}: {error}").format(
                folder=self.folder, error=exc.strerror or exc))
            return
        self.path = self.log.path
        self._error_said = False
        self.set_full_text(self._text(self.log))

    def close(self, discard_empty: bool = False) -> None:
        logger, self.log = self.log, None
        if logger is None:
            return
        logger.close()
        if discard_empty and logger.rows == 0:
            try:
                logger.path.unlink()
            except OSError:
                pass
            self.set_full_text("")
            self.path = None
        else:
            self.set_full_text(self._text(logger))

    # -- the reader thread (no Qt) ------------------------------------------------------------
    def add_telemetry(self, tel) -> None:
        logger = self.log
        if logger is not None:
            logger.add_telemetry(tel)

    def add_event(self, ev) -> None:
        logger = self.log
        if logger is not None:
            logger.add_event(ev)

    # -- the GUI thread -----------------------------------------------------------------------
    def update_text(self) -> str:
        """Show the rows written so far; returns the write error to say, once ("" else)."""
        logger = self.log
        if logger is None:
            return ""
        self.set_full_text(self._text(logger))
        if logger.error and not self._error_said:
            self._error_said = True
            return _("Session CSV: {error}. The plot goes on; the CSV ends here.").format(error=logger.error)
        return ""

    @staticmethod
    def _text(logger: SessionLog) -> str:
        rows = (" · " + ngettext("{n} row", "{n} rows", logger.rows).format(n=logger.rows)) if logger.rows else ""
        err = f" · ⚠ {logger.error}" if logger.error else ""
        return _("Session: {path}").format(path=display_path(logger.path)) + rows + err
