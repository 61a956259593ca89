"""Which monitor-only charger is on a serial port, from what arrives.

``Detector`` feeds every serial driver's decoder the same bytes; the first that decodes a
whole record (checksum, shape and ranges) with no more bad records than good ones wins, and
its samples so far are kept (nothing is lost to detection). ``BaudSweep`` says which baud to
listen at next: every usual baud in turn (the drivers' defaults first), moving on when junk
arrives or a baud has had ``PER_BAUD_S`` seconds of data without a record. A sweep with no
winner ends with a message naming the drivers and bauds tried.
"""
from __future__ import annotations

from .drivers import SERIAL_DRIVERS
from .messages import Telemetry

PER_BAUD_S = 2.5                 # an iCharger sends one line every 2 s
JUNK_BYTES = 200                 # this many bytes at one baud without a record: wrong baud
MAX_HELD = 1000                  # samples a losing candidate keeps while detection goes on


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
    """The baud schedule of one detection: ``baud`` now; ``advance(now, received)`` after each
    read says whether to switch; ``done`` when every baud had its turn."""

    def __init__(self, bauds: tuple[int, ...] | None = None, first: int | None = None) -> None:
        bauds = tuple(bauds or usual_bauds())
        if first in bauds:
            bauds = (first,) + tuple(b for b in bauds if b != first)
        self.bauds = bauds
        self.index = 0
        self._data_since: float | None = None
        self._bytes = 0
        self.done = False

    @property
    def baud(self) -> int:
        return self.bauds[min(self.index, len(self.bauds) - 1)]

    def advance(self, now: float, received: int) -> bool:
        """True when the port must switch to ``self.baud`` (a new one) now."""
        if received and self._data_since is None:
            self._data_since = now
        self._bytes += received
        if self._data_since is None:
            return False
        if self._bytes < JUNK_BYTES and now - self._data_since < PER_BAUD_S:
            return False
        self.index += 1
        self._data_since = None
        self._bytes = 0
        if self.index >= len(self.bauds):
            self.done = True
            return False
        return True

    def message(self, port: str, detector: Detector) -> str:
        return (f"{port}: nothing recognisable in {detector.received} bytes; tried {detector.tried()} "
                f"at {', '.join(str(b) for b in self.bauds)} baud")
