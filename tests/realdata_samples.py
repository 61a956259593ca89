"""The real recordings under tests/data/realdata (see the README there) and small readers of
their text forms."""
from pathlib import Path

DATA = Path(__file__).resolve().parent / "data" / "realdata"


def path(name: str) -> Path:
    return DATA / name


def raw(name: str) -> bytes:
    return (DATA / name).read_bytes()


def dollar_lines(name: str) -> list[bytes]:
    return [line.rstrip(b"\r\x00") for line in raw(name).split(b"\n") if line.startswith(b"$")]


def imaxb6_frames(name: str = "imaxb6_Ladung3S450mAh_frames_head300.txt") -> list[bytes]:
    return [bytes.fromhex(line.split(";")[2].strip()) for line in path(name).read_text().splitlines()
            if line and not line.startswith("#")]


def ultramat_sections() -> dict[str, list[bytes]]:
    """Model -> its frames with 0x0C/0x0D restored."""
    out: dict[str, list[bytes]] = {}
    current = None
    for line in path("ultramat_frames_extracted.txt").read_text().splitlines():
        if line.startswith("## "):
            current = line[3:].split("_", 1)[0]
            out[current] = []
        elif line and not line.startswith("#"):
            out[current].append(b"\x0c" + line.strip().encode() + b"\r")
    return out


def isdt_frames() -> list[bytes]:
    """The RX frames, as 64-byte reports (the one quoted from the recipient byte on gets its
    0x02 <len> 0xAA head back)."""
    out = []
    for line in path("isdt_real_frames.txt").read_text().splitlines():
        if line.startswith("RX "):
            out.append(bytes.fromhex(line.split()[1]).ljust(64, b"\0"))
        elif line.startswith("RX(from rcpt) "):
            body = bytes.fromhex(line.split()[2])
            out.append((bytes((0x02, len(body) + 2, 0xAA)) + body).ljust(64, b"\0"))
    return out


# DUO/X USB-HID log report quoted in shared/realdata/icharger_logview.md (section C), from
# DataExplorer's iChargerUsb.convertDataBytes source comment: a 4S pack discharging.
ICHARGER_HID_REPORT = bytes.fromhex(
    "2C 10 01 F8 7D 07 00 02 01 00 E5 FF 04 87 2B 3C CF FF FF FF 64 01 00 00 02 0F 0B 0F 0E 0F 00 0F").ljust(64, b"\0")
# The iMAX B6 frame of the fornellas README (shared/realdata/imaxb6_serial.md, worked example).
IMAXB6_README_FRAME = bytes.fromhex(
    "7b9e8484d08580ee8181818081948a808196828a828e868181808a808a808cb280829587cc808080808dcf80ba83d883d6"
    "808080808080808080808080808080808080808080818fa438307d")


def skyrc_reply(state: int, mah: int, secs: int, mv: int, ma: int, text: int, tint: int, cells: list[int]) -> bytes:
    """A SkyRC 0x55 reply in the documented layout (shared/realdata/skyrc_hid.md): no raw one
    exists publicly, so the tests put a B6AC v2's logged values into it."""
    body = bytes((0x55, 0x00, state)) + mah.to_bytes(2, "big") + secs.to_bytes(2, "big") + mv.to_bytes(2, "big") \
        + ma.to_bytes(2, "big", signed=True) + bytes((text, tint)) + (0).to_bytes(2, "big") \
        + b"".join(c.to_bytes(2, "big") for c in cells)
    return (bytes((0x0F, len(body) + 1)) + body + bytes((sum(body) & 0xFF, 0xFF, 0xFF))).ljust(64, b"\0")
