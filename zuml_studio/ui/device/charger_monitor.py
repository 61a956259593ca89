"""The device panel's link to a monitor-only charger: ``device.monitor_link.MonitorLink`` (a
reader thread) with its status and end turned into Qt signals. Samples go straight from the
reader thread to ``on_sample`` (the live series and the session CSV are thread-safe), as with
the ZUML connection's telemetry."""
from __future__ import annotations

from typing import Callable

from PySide6.QtCore import QObject, Signal

from ...device.errors import DeviceLinkError
from ...device.monitor_link import MonitorLink


class ChargerMonitor(QObject):
    status = Signal(str)
    closed = Signal(str)               # "" when the user closed it, else what went wrong

    def __init__(self, on_sample: Callable, parent: QObject | None = None):
        super().__init__(parent)
        self._on_sample = on_sample
        self.link: MonitorLink | None = None

    def open(self, port: str, driver: str, baud: int | None) -> str:
        """Open and start reading; returns "" or why it could not open."""
        try:
            self.link = MonitorLink(port, driver, baud, on_sample=self._on_sample, on_status=self.status.emit,
                                    on_closed=lambda error: self.closed.emit(error or ""), give_up=False)
        except DeviceLinkError as exc:
            return str(exc)
        self.link.start()
        return ""

    def close(self) -> None:
        link = self.link
        if link is not None:
            link.close()
