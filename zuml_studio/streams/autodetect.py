"""Which monitor-only charger is on a serial port, from what arrives.

``Detector`` feeds every serial driver's decoder the same bytes; the first that decodes a
whole record (checksum, shape and ranges) with no more bad records than good ones wins, and
its samples so far are kept (nothing is lost to detection). ``BaudSweep`` says which baud to
listen at next: every usual baud in turn (the drivers' defaults first), moving on after a burst
of junk, ``JUNK_BYTES`` without a record, or ``PER_BAUD_S`` seconds of data without a record. A
sweep with no winner ends with a message naming the drivers and bauds tried.
"""
from __future__ import annotations

import re

from .drivers import SERIAL_DRIVERS
from ..protocol.messages import Telemetry
from ..i18n import _

PER_BAUD_S = 2.5                 # an iCharger sends one line every 2 s
JUNK_BYTES = 200                 # this many bytes at one baud without a record: wrong baud
MAX_HELD = 1000                  # samples a losing candidate keeps while detection goes on
BURST_GAP_S = 0.25               # quiet that ends a burst (a line, a frame)
MIN_BURST = 8                    # a shorter burst says nothing about the baud
# The start of a record of any serial driver: a $-line, an iMAX B6 frame, an Ultramat frame, a ZUML
# firmware's unasked frame (sync, length, TELEMETRY/EVENT/LCD).
RECORD_START = re.compile(rb"\$[123];|\{[\x80-\xff]{8}|\x0c[0-9A-Fa-f]{8}|\xa5[\x0e-\xfa][\x40-\x42]")


def usual_bauds() -> tuple[int, ...]:
    out: list[int] = []
    for d in SERIAL_DRIVERS:
        if d.baud not in out:
            out.append(d.baud)
    for d in SERIAL_DRIVERS:
        for b in d.bauds:
            if b not in out:
                out.append(b)
    return tuple(out)


class Detector:
    def __init__(self) -> None:
        self.received = 0
        self.winner: str | None = None
        self.decoders = {d.name: d.decoder() for d in SERIAL_DRIVERS}
        self._held: dict[str, list[Telemetry]] = {name: [] for name in self.decoders}
        self._bad_base = {name: 0 for name in self.decoders}

    def feed(self, data: bytes) -> list[Telemetry]:
        """Samples of the winning driver (all of them since the start once it wins; empty
        until there is one)."""
        self.received += len(data)
        if self.winner is not None:
            return self.decoders[self.winner].feed(data)
        for name, dec in self.decoders.items():
            held = self._held[name]
            held += dec.feed(data)
            del held[:-MAX_HELD]
            if self.winner is None and dec.good and dec.good >= dec.bad - self._bad_base[name]:
                self.winner = name
        if self.winner is None:
            return []
        self.decoders = {self.winner: self.decoders[self.winner]}
        found, self._held = self._held[self.winner], {}
        return found

    def new_baud(self) -> None:
        """The port changed baud: bad records so far are the old baud's junk. The decoders keep
        their state (on a pty, or when the charger's baud was right after all, nothing is lost;
        a record torn by the change fails its checksum)."""
        self._bad_base = {name: dec.bad for name, dec in self.decoders.items()}

    def tried(self) -> str:
        return ", ".join(d.name for d in SERIAL_DRIVERS)


class BaudSweep:
    """The baud schedule of one detection: ``baud`` now; ``advance(now, data)`` after each read
    says whether to switch; ``done`` when every baud had its turn.

    Chargers send in bursts (a line, a frame) with pauses between. A burst read at the wrong
    baud is junk without the start of any record: once such a burst ends (``BURST_GAP_S`` of
    quiet) the sweep moves on, so a charger that sends a line every 2 s is not waited for at
    every wrong baud. A burst with a record start (a torn first line at the right baud) keeps
    the baud for up to ``PER_BAUD_S``."""

    def __init__(self, bauds: tuple[int, ...] | None = None, first: int | None = None) -> None:
        bauds = tuple(bauds or usual_bauds())
        if first in bauds:
            bauds = (first,) + tuple(b for b in bauds if b != first)
        self.bauds = bauds
        self.index = 0
        self.done = False
        self._reset()

    def _reset(self) -> None:
        self._data_since: float | None = None
        self._last_data = 0.0
        self._bytes = 0
        self._burst = bytearray()

    @property
    def baud(self) -> int:
        return self.bauds[min(self.index, len(self.bauds) - 1)]

    def advance(self, now: float, data: bytes) -> bool:
        """True when the port must switch to ``self.baud`` (a new one) now."""
        if data:
            if self._data_since is None:
                self._data_since = now
            self._last_data = now
            self._bytes += len(data)
            self._burst += data[:max(0, JUNK_BYTES - len(self._burst))]
        if self._data_since is None:
            return False
        junk_burst = (now - self._last_data >= BURST_GAP_S and len(self._burst) >= MIN_BURST
                      and not RECORD_START.search(self._burst))
        if self._burst and now - self._last_data >= BURST_GAP_S:
            self._burst.clear()
        if not junk_burst and self._bytes < JUNK_BYTES and now - self._data_since < PER_BAUD_S:
            return False
        self.index += 1
        self._reset()
        if self.index >= len(self.bauds):
            self.done = True
            return False
        return True

    def message(self, port: str, detector: Detector) -> str:
        return _("{port}: nothing recognisable in {received} bytes; tried {tried} at {bauds} baud").format(
            port=port, received=detector.received, tried=detector.tried(), bauds=", ".join(str(b) for b in self.bauds))
