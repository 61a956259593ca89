"""Frames on the wire and an incremental parser that finds them again after noise.

    0xA5 | LEN | TYPE | SEQ | PAYLOAD (LEN bytes, 0..250) | CRC16 low, high

The CRC is CRC-16/MODBUS over LEN, TYPE, SEQ and PAYLOAD (``crc.crc16``).

``FrameParser.feed(chunk)`` takes bytes as they come (any split) and returns the whole
frames they complete. Anything that is not a frame is skipped and counted. On a bad CRC
or an impossible LEN the parser drops that one sync byte and searches again from the
next byte, so a frame that follows garbage is never lost. While it waits for the rest
of a frame whose LEN came from garbage, it also looks further ahead: a complete frame
with a good CRC later in the buffer proves the earlier candidate false.
"""
from __future__ import annotations

from .crc import INIT, TABLE, _word_table, crc16
from ..i18n import _

SYNC = 0xA5
MAX_PAYLOAD = 250
OVERHEAD = 6                      # sync, len, type, seq + 2 CRC bytes
MAX_FRAME = MAX_PAYLOAD + OVERHEAD
_SYNC_BYTES = bytes([SYNC])


class Frame:
    """One decoded frame; ``payload`` is bytes."""

    __slots__ = ("type", "seq", "payload")

    def __init__(self, type: int, seq: int, payload: bytes):
        self.type = type
        self.seq = seq
        self.payload = payload

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Frame) and (self.type, self.seq, self.payload) == (other.type, other.seq,
                                                                                     other.payload)

    def __hash__(self) -> int:
        return hash((self.type, self.seq, self.payload))

    def __repr__(self) -> str:
        return f"Frame(type=0x{self.type:02x}, seq={self.seq}, payload={self.payload.hex()})"

    def encode(self) -> bytes:
        return encode_frame(self.type, self.seq, self.payload)


def encode_frame(type: int, seq: int, payload: bytes = b"") -> bytes:
    if not 0 <= type <= 0xFF or not 0 <= seq <= 0xFF:
        raise ValueError(_("type and seq are bytes (0..255)"))
    if len(payload) > MAX_PAYLOAD:
        raise ValueError(_("a payload has at most {max_payload} bytes, not {n_payload}").format(
                max_payload=MAX_PAYLOAD, n_payload=len(payload)))
    body = bytes((len(payload), type, seq)) + bytes(payload)
    crc = crc16(body)
    return b"\xa5" + body + bytes((crc & 0xFF, crc >> 8))


class FrameParser:
    """Incremental; never raises on any input.

    Counters: ``frames`` (good frames returned), ``skipped`` (bytes that were not part of a
    good frame), ``bad_frames`` (sync candidates refused: bad CRC or impossible LEN), ``damaged``
    (of those, whole frames of a known TYPE that failed only their CRC: a device that answers
    over a noisy line).
    ``valid_types`` (optional) lets the parser refuse a candidate with an unknown TYPE at
    once instead of waiting for its CRC.
    """

    def __init__(self, valid_types: frozenset[int] | None = None):
        self._buf = b""
        self.frames = 0
        self.skipped = 0
        self.bad_frames = 0
        self.damaged = 0
        self._types = valid_types
        self._t2 = _word_table()

    def reset(self) -> None:
        self.skipped += len(self._buf)
        self._buf = b""

    @property
    def pending(self) -> int:
        """Bytes held back waiting for the rest of a frame."""
        return len(self._buf)

    def _crc_ok(self, buf: bytes, start: int, end: int) -> bool:
        """CRC over buf[start:end] equals the two bytes at buf[end:end+2]."""
        t2 = self._t2
        crc = INIT
        n = end - start
        even = start + (n & ~1)
        for w in memoryview(buf)[start:even].cast("H"):
            crc = t2[crc ^ w]
        if n & 1:
            crc = (crc >> 8) ^ TABLE[(crc ^ buf[end - 1]) & 0xFF]
        return buf[end] == (crc & 0xFF) and buf[end + 1] == (crc >> 8)

    def _candidate(self, buf: bytes, i: int, n: int) -> int:
        """At sync byte i: >0 end of a good frame; 0 need more bytes; -1 not a frame."""
        if n - i < 4:
            return 0
        ln = buf[i + 1]
        if ln > MAX_PAYLOAD or (self._types is not None and buf[i + 2] not in self._types):
            return -1
        end = i + OVERHEAD + ln
        if end > n:
            return 0
        return end if self._crc_ok(buf, i + 1, end - 2) else -1

    def _good_frame_after(self, buf: bytes, i: int, n: int) -> int:
        """The start of a complete good frame after position i, or -1."""
        j = buf.find(_SYNC_BYTES, i + 1)
        while j >= 0:
            if self._candidate(buf, j, n) > 0:
                return j
            j = buf.find(_SYNC_BYTES, j + 1)
        return -1

    def flush_stale(self) -> list[Frame]:
        """The line went quiet while a frame was incomplete: that frame's LEN was garbage.
        Drop its sync byte and parse what follows (a UART's inter-byte timeout)."""
        if not self._buf:
            return []
        buf = self._buf
        self._buf = b""
        self.bad_frames += 1
        self.skipped += 1
        return self.feed(buf[1:])

    def feed(self, data) -> list[Frame]:
        buf = self._buf + bytes(data) if self._buf else bytes(data)
        n = len(buf)
        out: list[Frame] = []
        pos = 0
        find = buf.find
        maxp = MAX_PAYLOAD
        types = self._types
        t2 = self._t2
        table = TABLE
        # The CRC runs two bytes per step over 16-bit views at even and at odd offsets, made once
        # per feed; over LEN..CRC the CRC-16/MODBUS of a good frame is 0 (its residue).
        mv = memoryview(buf)
        even = mv[:n & ~1].cast("H")
        odd = mv[1:1 + ((n - 1) & ~1)].cast("H") if n > 1 else even
        while True:
            i = find(_SYNC_BYTES, pos)
            if i < 0:
                self.skipped += n - pos
                pos = n
                break
            if i > pos:
                self.skipped += i - pos
                pos = i
            if n - i < 4:
                break
            ln = buf[i + 1]
            if ln > maxp or (types is not None and buf[i + 2] not in types):
                self.bad_frames += 1
                self.skipped += 1
                pos = i + 1
                continue
            end = i + 6 + ln
            if end > n:
                # Wait for the rest, unless a good frame further on shows this one is garbage.
                j = self._good_frame_after(buf, i, n)
                if j < 0:
                    break
                self.bad_frames += 1
                self.skipped += j - i
                pos = j
                continue
            s = i + 1
            k = s >> 1
            words = (odd if s & 1 else even)[k:k + ((ln + 5) >> 1)]
            crc = 0xFFFF
            for w in words:
                crc = t2[crc ^ w]
            if not ln & 1:      # ln + 5 bytes: odd when ln is even
                crc = (crc >> 8) ^ table[(crc ^ buf[end - 1]) & 0xFF]
            if crc == 0:
                out.append(Frame(buf[i + 2], buf[i + 3], buf[i + 4:end - 2]))
                pos = end
            else:
                self.bad_frames += 1
                self.damaged += types is not None
                self.skipped += 1
                pos = i + 1
        self._buf = buf[pos:] if pos < n else b""
        self.frames += len(out)
        return out
