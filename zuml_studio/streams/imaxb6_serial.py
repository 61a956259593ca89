"""Original SkyRC iMAX B6 / B6AC (v1), Bantam e-Station, Pichler P6: 76-byte ``{…}`` frames at
9600 baud, sent unsolicited.

Bytes 1..72 carry 7-bit values with bit 7 set; bytes 73, 74 are ``0x30 + nibble`` of the
8-bit sum of bytes 1..72. Values come in pairs ``v[i]*100 + v[i+1]``. The frame has only
whole minutes of run time, so sample k is at ``1.48 * k`` s (the median spacing measured on
the real recording). Both temperature pairs read 0 in every known capture and their unit is
unverified: they are not reported.
"""
from __future__ import annotations

from .frame_scanner import INVALID, FrameDecoder
from .stream_decoder import Reading

FRAME = 76
STEP_S = 1.48
MODES = {0: "config", 1: "Li", 2: "NiMH", 3: "NiCd", 4: "Pb", 5: "save", 6: "load"}


def checksum_ok(frame: bytes) -> bool:
    s = sum(frame[1:73]) & 0xFF
    return frame[73] == 0x30 + (s >> 4) and frame[74] == 0x30 + (s & 0x0F)


class IMaxB6Decoder(FrameDecoder):
    name = "imaxb6"
    starts = b"{"
    max_record = FRAME

    def __init__(self) -> None:
        super().__init__()
        self._count = 0

    def frame(self, buf: bytearray, at: int):
        end = at + FRAME
        for i in range(at + 1, min(end - 3, len(buf))):
            if buf[i] < 0x80:
                return INVALID, None
        if len(buf) < end:
            return None
        f = bytes(buf[at:end])
        if f[75] != 0x7D or not checksum_ok(f):
            return INVALID, None
        v = [b - 0x80 for b in f[:73]]

        def pair(i: int) -> int:
            return v[i] * 100 + v[i + 1]

        charging = bool(v[8] & 0x01)
        running = bool(v[24] & 0x01)
        mode = MODES.get(v[23], "?")
        section = ("charge" if charging else "discharge") if running else ""
        amps = pair(33) / 100
        t = self._count * STEP_S
        self._count += 1
        return FRAME, Reading(
            time_s=t, state=f"{mode} {'charging' if charging else 'discharging'}" if running else "standby",
            section=section, running=running, voltage_v=pair(35) / 100,
            current_a=-amps if section == "discharge" else amps, charge_mah=float(pair(43)),
            cells_v=tuple(pair(45 + 2 * k) / 100 for k in range(6)),
            task="discharge" if running and not charging else "charge")


def decoder() -> IMaxB6Decoder:
    return IMaxB6Decoder()
