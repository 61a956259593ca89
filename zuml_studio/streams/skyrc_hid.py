"""SkyRC "Charge Master" USB-HID chargers (iMAX B6 mini, B6AC v2, Q200, D100, Hitec X1 …).

Host-polled: ``POLL`` (command 0x55) once a second; the 64-byte reply is
``0F LEN 55 00 state mAh(2) s(2) mV(2) mA(2) Text Tint mΩ(2) cells(2 each) CHK FF FF`` (big
endian), CHK = sum of bytes 2..LEN. Other replies (0x57 device info, 0x5A settings, 0x5F)
are checked and skipped. The reply does not say whether the program charges or discharges:
the section follows the current's sign (DataExplorer reads it signed).
"""
from __future__ import annotations

from .frame_scanner import INVALID, SKIP, FrameDecoder
from .stream_decoder import Reading

VID_PIDS = ((0x0000, 0x0001),)
POLL = bytes((0x0F, 0x03, 0x55, 0x00, 0x55, 0xFF, 0xFF))
POLL_S = 1.0
STATES = {1: ("running", True), 2: ("idle", False), 3: ("finished", False), 4: ("error", False)}


def checksum(frame: bytes | bytearray, length: int) -> int:
    return sum(frame[2:length + 1]) & 0xFF


class SkyRcDecoder(FrameDecoder):
    name = "skyrc"
    starts = b"\x0f"
    filler = b"\x00"
    max_record = 64

    def frame(self, buf: bytearray, at: int):
        if len(buf) - at < 2:
            return None
        length = buf[at + 1]
        if not 3 <= length <= 58:
            return INVALID, None
        end = at + length + 4
        if len(buf) < end:
            return None
        f = bytes(buf[at:end])
        if f[length + 1] != checksum(f, length) or f[length + 2:length + 4] != b"\xff\xff":
            return INVALID, None
        if f[2] != 0x55:
            return end - at, SKIP
        if length < 16 or f[4] not in STATES:
            return INVALID, None
        name, running = STATES[f[4]]

        def be(i: int, signed: bool = False) -> int:
            return int.from_bytes(f[i:i + 2], "big", signed=signed)

        ma = be(11, True)
        section = ("charge" if ma > 0 else "discharge" if ma < 0 else "") if running else ""
        cells = tuple(be(17 + 2 * k) / 1000 for k in range(max(0, min(8, (length - 16) // 2))))
        text, tint = int.from_bytes(f[13:14], "big", signed=True), int.from_bytes(f[14:15], "big", signed=True)
        return end - at, Reading(time_s=float(be(7)), state=name, section=section, running=running,
                                 voltage_v=be(9) / 1000, current_a=ma / 1000, temp_c=float(text) if text else None,
                                 heatsink_c=float(tint) if tint else None, charge_mah=float(be(5)), cells_v=cells,
                                 task="discharge" if section == "discharge" else "charge")


def decoder() -> SkyRcDecoder:
    return SkyRcDecoder()
