"""Play a recording onto a serial port (a pty) at its recorded pace × speed, so a charger's
stream can be watched without the charger.

``load_recording`` turns a file's bytes into records with their times: whatever
``drivers.decode_recording`` reads (raw serial captures, HID report dumps, DUO/X text logs,
the text forms of the shared samples). The record times are those the driver's decoder
gives (the line's own clock, or its fixed step).

``ReplayDevice`` has the byte interface ``transport.serve_pty`` drives for the virtual
charger. pyserial empties a port's input when it opens it (after setting the line up), so the
replay starts only once a reader has opened the pty and emptied its input: the pty's master is in
packet mode, where the reader's flush arrives as a status byte. Whatever the machine's load, no
record is sent before that flush and lost in it. A reader that sets the line up but never flushes
(a terminal program) gets the recording after FLUSH_WAIT_S.
"""
from __future__ import annotations

import fcntl
import random
import struct
import termios
import threading
import time
from dataclasses import dataclass
from typing import Callable

from ..streams.drivers import DRIVERS, decode_recording
from .virtual_charger import Faults
from ..i18n import _

MAX_GAP_S = 60.0                 # a longer pause in a recording (a restart, a joined file) plays as this
FLUSH_WAIT_S = 2.0               # after the reader set the line up, the longest wait for its flush
# how a driver's stream splits into records
_SPLIT = {"cheali": b"\n", "icharger": b"\n", "imaxb6": b"}", "ultramat": b"\r"}


@dataclass(frozen=True)
class Recording:
    driver: str
    records: tuple[tuple[float, bytes], ...]       # (seconds from the first record, bytes)
    bad: int

    @property
    def duration_s(self) -> float:
        return self.records[-1][0] if self.records else 0.0


def _split(driver: str, stream: bytes) -> list[bytes]:
    sep = _SPLIT.get(driver)
    if sep is None:                                 # HID reports
        return [stream[i:i + 64] for i in range(0, len(stream), 64)]
    parts = stream.split(sep)
    out = [p + sep for p in parts[:-1]]
    if parts[-1]:
        out.append(parts[-1])
    return out


def load_recording(data: bytes, as_format: str | None = None) -> Recording:
    """Raises CaptureError when no driver reads the data."""
    capture = decode_recording(data, as_format)
    stream, name, bad = capture.stream, capture.driver, capture.bad
    dec = DRIVERS[name].decoder()
    records: list[tuple[float, bytes]] = []
    t0 = last = None
    clock = 0.0
    for chunk in _split(name, stream):
        got = dec.feed(chunk)
        if got:
            t = got[-1].time_s
            if t0 is None:
                t0 = last = t
            clock += min(MAX_GAP_S, max(0.0, t - last))
            last = t
        records.append((clock, chunk))
    return Recording(name, tuple(records), bad)


class ReplayDevice:
    """Plays ``recording`` at ``speed`` × its pace through a transport link."""

    def __init__(self, recording: Recording, speed: float = 1.0, wait_for_reader: bool = True):
        if not speed > 0:
            raise ValueError(_("speed must be > 0"))
        self.recording = recording
        self.speed = float(speed)
        self.wait_for_reader = wait_for_reader
        self.faults = Faults()
        self.rng = random.Random(0)
        self._disconnect_spent = False
        self._out = threading.Condition()
        self._pending = bytearray()
        self._stop = threading.Event()
        self._slave: int | None = None
        self._armed = threading.Event()
        self._flushed = threading.Event()
        self.sent_records = 0
        self.finished = threading.Event()
        self._thread = threading.Thread(target=self._play, name="replay", daemon=True)

    # -- what a transport link calls -------------------------------------------------------
    rx_pending = 0

    def attach(self) -> None:
        self._thread.start()

    def detach(self) -> None:
        self._stop.set()
        self._armed.set()
        self._flushed.set()

    def reset_link(self) -> None:
        pass

    def receive(self, data: bytes) -> None:
        # Monitor-only chargers ignore what the host sends. In packet mode each read of the master
        # starts with a status byte: 0 before data, else what happened to the line.
        if data and data[0] & termios.TIOCPKT_FLUSHREAD:
            self._flushed.set()

    def line_idle(self) -> None:
        pass

    def read_output(self, max_bytes: int, timeout: float | None = None) -> bytes:
        with self._out:
            if not self._pending and timeout:
                self._out.wait(timeout)
            out = bytes(self._pending[:max_bytes])
            del self._pending[:max_bytes]
            return out

    # -- playing -------------------------------------------------------------------------------
    def watch_reader(self, slave_fd: int | None, master_fd: int | None = None) -> None:
        """Start once a reader has set up the pty whose slave is ``slave_fd`` (None: now) and, where
        the ``master_fd`` is given, emptied its input. Call before anyone can know the port: the line
        is marked here, so no reader's set-up or flush is missed."""
        self._slave = slave_fd
        if master_fd is not None and self.wait_for_reader:
            fcntl.ioctl(master_fd, termios.TIOCPKT, struct.pack("i", 1))
        else:
            self._flushed.set()
        if slave_fd is not None and self.wait_for_reader:
            attrs = termios.tcgetattr(slave_fd)
            attrs[4] = attrs[5] = termios.B50      # a speed no reader asks for: any open changes it
            termios.tcsetattr(slave_fd, termios.TCSANOW, attrs)
            self._marked = termios.tcgetattr(slave_fd)    # as the pty keeps them
        self._armed.set()

    def _await_reader(self) -> None:
        fd = self._slave
        if fd is None or not self.wait_for_reader:
            return
        while not self._stop.is_set():
            if termios.tcgetattr(fd) != self._marked:
                self._flushed.wait(FLUSH_WAIT_S)
                return
            self._stop.wait(0.01)

    def _play(self) -> None:
        self._armed.wait()
        try:
            self._await_reader()
        except termios.error:
            return
        start = time.monotonic()
        for t, chunk in self.recording.records:
            delay = start + t / self.speed - time.monotonic()
            if delay > 0 and self._stop.wait(delay):
                return
            if self._stop.is_set():
                return
            with self._out:
                self._pending += chunk
                self._out.notify_all()
            self.sent_records += 1
        self.finished.set()


def serve_replay(recording: Recording, speed: float = 1.0) -> tuple[str, Callable[[], None], ReplayDevice]:
    """Serve the recording on a new pty: (port path, stop function, device)."""
    from .transport import serve_pty
    device = ReplayDevice(recording, speed)
    port, stop = serve_pty(device, None)          # type: ignore[arg-type]  # the same byte interface
    device.watch_reader(stop.link.slave, stop.link.master)      # type: ignore[attr-defined]
    return port, stop, device
