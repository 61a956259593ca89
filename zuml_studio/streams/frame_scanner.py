"""Resynchronising scan over a byte stream of framed records (binary or ASCII frames).

``FrameDecoder.feed`` keeps the unread bytes, looks for a start byte, asks the subclass
``frame(buf, at) -> (length, reading | None | SKIP) | None`` (None: need more bytes), and
moves on one byte after a start that is not a valid frame. A run of junk between frames
counts once in ``bad``; filler bytes (``filler``, e.g. HID zero padding) are dropped quietly.
"""
from __future__ import annotations

import re

from ..protocol.messages import Telemetry
from .stream_decoder import StreamDecoder

SKIP = object()          # a valid frame without a measurement
INVALID = -1


class FrameDecoder(StreamDecoder):
    starts: bytes = b""
    filler: bytes = b""
    # Where a frame may start, as a regular expression (default: any of ``starts``); a start byte
    # near the end of the bytes read must still match (``\Z``): the rest may come in the next piece.
    start_pattern: bytes = b""

    def __init__(self) -> None:
        super().__init__()
        self._buf = bytearray()
        self._in_junk = False
        # A run of bytes that start no frame is passed in one search, not byte by byte: a capture of
        # another charger is megabytes of it (reading a day-long capture tries every driver).
        self._start = re.compile(self.start_pattern or (
                b"[" + b"".join(re.escape(bytes((c,))) for c in self.starts) + b"]" if self.starts else b"(?!)"))

    def frame(self, buf: bytearray, at: int) -> tuple[int, object] | None:
        """At a start byte: (INVALID, None) if no frame starts here; None if more bytes are
        needed; else (length, Reading | SKIP)."""
        raise NotImplementedError

    def feed(self, data: bytes) -> list[Telemetry]:
        out: list[Telemetry] = []
        buf = self._buf
        buf += data
        at = 0
        n = len(buf)
        while at < n:
            b = buf[at]
            if b in self.filler:
                at += 1
                continue
            if b not in self.starts or (self.start_pattern and not self._start.match(buf, at)):
                found = self._start.search(buf, at + 1)
                end = found.start() if found else n
                if buf[at:end].translate(None, self.filler):    # not only filler between
                    self._junk()
                at = end
                continue
            try:
                got = self.frame(buf, at)
            except (ValueError, IndexError):
                got = (INVALID, None)
            if got is None:
                if n - at > self.max_record:        # cannot be a frame any more
                    self._junk()
                    at += 1
                    continue
                break
            length, reading = got
            if length == INVALID:
                self._junk()
                at += 1
                continue
            self._in_junk = False
            at += length
            if reading is SKIP:
                self.skipped += 1
            else:
                self.good += 1
                out.append(self.sample(reading))          # type: ignore[arg-type]
        del buf[:at]                     # what is left is at most one partial frame (max_record)
        return out

    def _junk(self) -> None:
        if not self._in_junk:
            self.bad += 1
            self._in_junk = True

