"""ISDT USB-HID chargers (C4, C4EVO, A4, Q8): host-polled, 64-byte reports.

A response is ``02 len AA 21 N data[N] CHK`` where every data ``AA`` is sent twice and CHK =
(0x21 + N + sum(data)) & 0xFF on the unescaped bytes. Telemetry is the 0xDF answer to
``DE <channel>`` (26 data bytes, little endian): channel, mode, chemistry, size, T, Tint,
progress, mV, mA, mΩ, power, energy, mAh, s. These chargers have several channels: the
decoder follows ``channel`` (default: the first one seen) and skips the others.
"""
from __future__ import annotations

import struct

from .frame_scanner import INVALID, SKIP, FrameDecoder
from .stream_decoder import Reading

VID_PIDS = ((0x28E9, 0x028A),)
POLL_S = 1.0
_METRICS = struct.Struct("<BBBBBBBhhHhhiI")
# mode: name, section, running
MODES = {
    0: ("idle", "", False), 1: ("waiting", "", False), 2: ("reversed", "", False), 3: ("charging", "charge", True),
    4: ("charged", "", False), 5: ("discharging", "discharge", True), 6: ("discharged", "", False),
    7: ("storage", "", True), 8: ("storage done", "", False), 9: ("cycling", "", True),
    10: ("cycling done", "", False), 11: ("analysis", "", True), 12: ("analysis done", "", False),
    13: ("activate", "", True), 15: ("destroy", "", True), 17: ("cut off", "", False),
}


def poll_request(channel: int) -> bytes:
    """``01 len AA 12 02 DE ch CHK``."""
    data = bytes((0xDE, channel & 0xFF))
    body = bytes((0x12, len(data))) + data
    ck = sum(body) & 0xFF
    raw = bytes((0x01, 0x06, 0xAA)) + body.replace(b"\xaa", b"\xaa\xaa") + bytes((ck,))
    return raw


class IsdtDecoder(FrameDecoder):
    name = "isdt"
    starts = b"\x02"
    filler = b"\x00"
    max_record = 64

    def __init__(self, channel: int | None = None) -> None:
        super().__init__()
        self.channel = channel

    def frame(self, buf: bytearray, at: int):
        n = len(buf)
        if n - at < 5:
            return None
        if buf[at + 2] != 0xAA or buf[at + 3] != 0x21:
            return INVALID, None
        size = buf[at + 4]
        i = at + 5
        data = bytearray()
        while len(data) < size:
            if i >= n:
                return None
            b = buf[i]
            if b == 0xAA:
                if i + 1 >= n:
                    return None
                if buf[i + 1] != 0xAA:
                    return INVALID, None
                i += 1
            data.append(b)
            i += 1
            if i - at > self.max_record:
                return INVALID, None
        if i >= n:
            return None
        if buf[i] != (0x21 + size + sum(data)) & 0xFF:
            return INVALID, None
        length = i + 1 - at
        if not data or data[0] != 0xDF:
            return length, SKIP
        if size != 1 + _METRICS.size:
            return INVALID, None
        ch, mode, _chem, _dim, temp, tint, _prog, mv, ma, _mohm, _pw, _en, mah, secs = _METRICS.unpack_from(data, 1)
        if mode not in MODES:
            return INVALID, None
        if self.channel is None:
            self.channel = ch
        if ch != self.channel:
            return length, SKIP
        name, section, running = MODES[mode]
        amps = abs(ma) / 1000
        return length, Reading(time_s=float(secs), state=name, section=section, running=running,
                               voltage_v=max(0, mv) / 1000, current_a=-amps if section == "discharge" else amps,
                               temp_c=float(temp), heatsink_c=float(tint), charge_mah=float(mah),
                               task="discharge" if section == "discharge" else "charge")


def decoder() -> IsdtDecoder:
    return IsdtDecoder()
