"""Junsi iCharger DUO/X/S over USB-HID: the charger pushes one 64-byte log report per channel
per log interval while a program runs (nothing to request).

``len type ch t_ms(4) state battery cycle I(s16, 10 mA) Vin Vbat mAh(s32) Tint Text cells…``
(little endian, cells s16 mV, N = (len - 24) / 2). The report has no checksum (USB checks
it), so a report is taken only whole and plausible: type 0x10, channel 1 or 2, a known state,
N in 6/8/10/12. IR reports (state 0x80 and up) are skipped; so is the second channel.
"""
from __future__ import annotations

import re
import struct

from .frame_scanner import INVALID, SKIP, FrameDecoder
from .icharger_logview import DUO_STATES, _direction, _temp
from .stream_decoder import Reading

VID_PIDS = ((0x0483, 0x5751),)
REPORT = 64
LOG_TYPE = 0x10
_HEAD = struct.Struct("<BBBIBBBhHHihh")
LENGTHS = frozenset(24 + 2 * n for n in (6, 8, 10, 12))


class IChargerHidDecoder(FrameDecoder):
    name = "icharger-hid"
    starts = bytes(sorted(LENGTHS))
    # A length, the log type, channel 1 or 2: the length bytes alone are '$', '(', ',' and '0', which
    # text captures are full of.
    start_pattern = b"[" + re.escape(starts) + rb"](?:\x10(?:[\x01\x02]|\Z)|\Z)"
    max_record = REPORT

    def __init__(self) -> None:
        super().__init__()
        self.channel: int | None = None

    def frame(self, buf: bytearray, at: int):
        if len(buf) - at < 8:
            return None
        if buf[at + 1] != LOG_TYPE or buf[at + 2] not in (1, 2):
            return INVALID, None
        state = buf[at + 7]
        if state < 0x80 and state not in DUO_STATES:
            return INVALID, None
        if len(buf) - at < REPORT:
            return None
        r = bytes(buf[at:at + REPORT])
        length, _type, ch, ms, state, _batt, _cycle, i10, _vin, mv, mah, tint, text = _HEAD.unpack_from(r)
        if self.channel is None:
            self.channel = ch
        if state >= 0x80 or ch != self.channel:
            return REPORT, SKIP
        n = (length - 24) // 2
        cells = struct.unpack_from(f"<{n}h", r, 24)
        name, section, running, paused = DUO_STATES[state]
        section = _direction(section, i10)
        return REPORT, Reading(time_s=ms / 1000, state=name, section=section, running=running, voltage_v=mv / 1000,
                               current_a=i10 / 100, temp_c=_temp(text), heatsink_c=_temp(tint),
                               charge_mah=float(mah), cells_v=tuple(c / 1000 for c in cells), paused=paused,
                               task="discharge" if section == "discharge" else "charge")


def decoder() -> IChargerHidDecoder:
    return IChargerHidDecoder()
