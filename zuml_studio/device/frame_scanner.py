"""Resynchronising scan over a byte stream of framed records (binary or ASCII frames).

``FrameDecoder.feed`` keeps the unread bytes, looks for a start byte, asks the subclass
``frame(buf, at) -> (length, reading | None | SKIP) | None`` (None: need more bytes), and
moves on one byte after a start that is not a valid frame. A run of junk between frames
counts once in ``bad``; filler bytes (``filler``, e.g. HID zero padding) are dropped quietly.
"""
from __future__ import annotations

from .messages import Telemetry
from .stream_decoder import StreamDecoder

SKIP = object()          # a valid frame without a measurement
INVALID = -1


class FrameDecoder(StreamDecoder):
    starts: bytes = b""
    filler: bytes = b""

    def __init__(self) -> None:
        super().__init__()
        self._buf = bytearray()
        self._in_junk = False

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
            if b not in self.starts:
                self._junk()
                at += 1
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

