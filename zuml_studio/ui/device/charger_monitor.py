"""The device panel's link to a monitor-only charger: ``device.links.monitor_link.MonitorLink`` (a
reader thread) with its status and end turned into Qt signals and the messages that say them.
Samples go straight from the reader thread to ``on_sample`` (the live series and the session
CSV are thread-safe), as with the ZUML connection's telemetry. A recording replayed onto a pty
in this process is served here too, and stopped with the link."""
from __future__ import annotations

from pathlib import Path
from typing import Callable

from PySide6.QtCore import QObject, Signal

from ...streams.drivers import AUTO, DRIVERS, LISTEN
from ...device.errors import DeviceLinkError
from ...device.links.monitor_link import MonitorLink
from ...file_errors import FileReadError, read_file_bytes
from ...i18n import _
from ...logs import LogFormatError, lov
from ...logs.model import connected_cells


def monitor_reason(title: str) -> str:
    """Why Flash and Start are off for the charger named ``title``."""
    if title == _(DRIVERS[LISTEN].title):
        return _("{title}: nothing reaches it from here (it has no receive line): its macros start from its "
                 "buttons and go in through the ISP programmer").format(title=title)
    return _("{title} cannot run ZUML macros: it is monitor-only").format(title=title)


class ChargerMonitor(QObject):
    status = Signal(str)
    closed = Signal(str)               # "" when the user closed it, else what went wrong
    message = Signal(str, str)         # text, kind
    placeholder = Signal(str)          # what the empty plot says
    ended = Signal(str, str)           # the link is gone: error ("" if asked for), its counts
    lcdChanged = Signal(str, str)      # the charger's display, where its stream carries it (zuml-tx)

    def __init__(self, on_sample: Callable, parent: QObject | None = None, on_event: Callable | None = None):
        super().__init__(parent)
        self._on_sample = on_sample
        self._on_event = on_event or (lambda event: None)
        self.link: MonitorLink | None = None
        self._stop_replay: Callable | None = None     # stops the in-process replay behind the port
        self.status.connect(self._said)
        self.closed.connect(self._closed)

    def open(self, port: str, driver: str, baud: int | None) -> str:
        """Open and start reading; returns "" or why it could not open."""
        try:
            self.link = MonitorLink(port, driver, baud, on_sample=self._on_sample, on_status=self.status.emit,
                                    on_closed=lambda error: self.closed.emit(error or ""), on_extra=self._extra,
                                    give_up=False)
        except DeviceLinkError as exc:
            self.link = None
            return str(exc)
        self.link.start()
        return ""

    def watch(self, port: str, driver: str, chosen_baud: int, baud: int | None = None, fallback: bool = False) -> bool:
        """Read a monitor-only charger on ``port`` (``driver`` "auto": recognise it) at ``baud``
        (None: ``chosen_baud`` if the driver takes it, else the driver's own); says how it went.
        ``fallback``: no ZUML charger answered there."""
        if baud is None:
            bauds = (DRIVERS[driver].baud,) + DRIVERS[driver].bauds if driver in DRIVERS else ()
            baud = chosen_baud if driver == AUTO or chosen_baud in bauds else None
        error = self.open(port, driver, baud)
        if error:
            self.message.emit(_("Cannot watch {port}: {error}").format(port=port, error=error), "error")
            return False
        if fallback:
            self.message.emit(_("No ZUML charger answered on {port}: listening for a monitor-only charger "
                                "({drivers}) instead…").format(port=port, drivers=", ".join(DRIVERS)), "info")
        elif self.link.driver is None:
            self.message.emit(_("Listening on {port} for a monitor-only charger ({drivers})…").format(
                port=port, drivers=", ".join(DRIVERS)), "info")
        if self.link.driver is None:
            self.placeholder.emit(_("listening: a charger sends while a program runs"))
        return True

    def _extra(self, kind: str, item) -> None:
        """On the reader thread: an event goes where a ZUML charger's go (no Qt), the display as a signal."""
        if kind == "event":
            self._on_event(item)
        elif kind == "lcd":
            self.lcdChanged.emit(*item)

    def is_monitoring(self) -> bool:
        """A monitor-only charger's link is open (or still being recognised)."""
        return self.link is not None

    def close(self) -> None:
        link = self.link
        if link is not None:
            link.close()

    def reason(self) -> str:
        """Why Flash and Start are off while watching ("" when not watching)."""
        if self.link is None:
            return ""
        title = _(self.link.driver.title) if self.link.driver else _("this charger")
        return _("{why}: Flash and Start are off").format(why=monitor_reason(title))

    def _said(self, text: str) -> None:
        link = self.link
        if link is None:
            return
        if link.driver is not None:
            self.placeholder.emit(_("monitoring: waiting for the charger's first record"))
            self.message.emit(_("{status} on {port}. {why}.").format(
                status=text[:1].upper() + text[1:], port=link.port, why=monitor_reason(_(link.driver.title))), "ok")
        else:
            # A sweep of every baud that found nothing names the port first, in any language
            # (streams.autodetect); "listening at …" does not.
            self.message.emit(text, "warn" if text.startswith(f"{link.port}:") else "info")

    def _closed(self, error: str) -> None:
        link, self.link = self.link, None
        self.stop_replay()
        counts = " " + _("{good} records, {bad} bad.").format(good=link.good, bad=link.bad) if link else ""
        self.ended.emit(error, counts)

    def shutdown(self) -> None:
        self.closed.disconnect(self._closed)
        self.close()
        self.link = None
        self.stop_replay()

    # -- replaying a recording ----------------------------------------------------------------
    def serve_replay(self, path: Path, speed: float):
        """Play the recording at ``path`` onto a pty at ``speed`` × its pace; returns (port, the
        recording), or None after saying why not."""
        from ...streams.drivers import CaptureError
        from ...virtual.replay import load_recording, serve_replay
        try:
            data = read_file_bytes(path)
            if lov.sniff(data[:64], path.name):        # a LogView file: the charger's records in it
                data = lov.charger_stream(data)
            recording = load_recording(data)
            port, self._stop_replay, _device = serve_replay(recording, speed)
        except CaptureError as exc:
            self.message.emit(f"{path.name}: {exc}", "error")
            return None
        except (FileReadError, LogFormatError) as exc:
            self.message.emit(f"{path.name}: {exc}" if isinstance(exc, LogFormatError) else str(exc), "error")
            return None
        except OSError as exc:
            self.message.emit(_("Cannot replay {file}: {error}").format(file=path.name, error=exc.strerror or exc),
                              "error")
            return None
        return port, recording

    def say_replaying(self, path: Path, port: str, recording) -> None:
        self.message.emit(_("Replaying {file} ({charger}, {n} records) on {port}.").format(
            file=path.name, charger=_(DRIVERS[recording.driver].title), n=len(recording.records), port=port), "ok")

    def stop_replay(self) -> None:
        stop, self._stop_replay = self._stop_replay, None
        if stop is not None:
            stop()


def recording_cells(recording) -> int:
    """The cells a recording's samples carry (balance taps reading 0 throughout left out); 1 without any."""
    samples = DRIVERS[recording.driver].decoder().feed(b"".join(chunk for _t, chunk in recording.records))
    return connected_cells([s.cells_v for s in samples]) or 1
