"""Graupner Ultramat / Ultra Duo Plus / Ultra Trio Plus: ``0x0C`` + ASCII hex + 4 hex checksum
chars + ``0x0D``, 9600 baud, sent unsolicited.

The checksum is the sum of the ASCII payload characters; some firmwares add a constant
(Ultramat18 +0x180, Ultra Duo Plus 45 +0x480, as DataExplorer learns it): only a model's
known offset is accepted, never one learned from the line. The field layout is known for the
52-byte frames (Ultramat 12/16/16S): Vin, V, I, capacity, 6 cells. Frames of the other models
are checked and counted but carry no sample here (``skipped``): their layouts are not in
the notes. The frame has no direction and no time: the section is "" and sample k is at k s.
"""
from __future__ import annotations

from .frame_scanner import INVALID, SKIP, FrameDecoder
from .stream_decoder import Reading

STEP_S = 1.0
# frame length (with 0x0C and 0x0D) -> accepted checksum offsets
LENGTHS = {52: (0,), 56: (0,), 70: (0,), 78: (0x180, 0), 106: (0,), 114: (0,), 124: (0,), 138: (0,),
           140: (0,), 146: (0x480, 0)}
DECODED = 52
_HEX = frozenset(b"0123456789ABCDEFabcdef")


class UltramatDecoder(FrameDecoder):
    name = "ultramat"
    starts = b"\x0c"
    max_record = max(LENGTHS)

    def __init__(self) -> None:
        super().__init__()
        self._count = 0

    def frame(self, buf: bytearray, at: int):
        i = at + 1
        n = len(buf)
        limit = min(n, at + self.max_record)
        while i < limit and buf[i] in _HEX:
            i += 1
        if i >= n:
            return None if i - at < self.max_record else (INVALID, None)
        if buf[i] != 0x0D:
            return INVALID, None
        length = i - at + 1
        offsets = LENGTHS.get(length)
        if offsets is None:
            return INVALID, None
        payload = bytes(buf[at + 1:i - 4])
        got = int(bytes(buf[i - 4:i]), 16)
        if (got - sum(payload)) & 0xFFFF not in offsets:
            return INVALID, None
        if length != DECODED:
            return length, SKIP
        words = [int(payload[k:k + 4], 16) for k in range(2, len(payload), 4)]
        vin, _status, mv, ma, mah = words[:5]
        t = self._count * STEP_S
        self._count += 1
        return length, Reading(time_s=t, state="running", section="", running=True, voltage_v=mv / 1000,
                               current_a=ma / 1000, charge_mah=float(mah),
                               cells_v=tuple(c / 1000 for c in words[5:11]))


def decoder() -> UltramatDecoder:
    return UltramatDecoder()
