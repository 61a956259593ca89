"""The raw serial monitor's bytes as text and back (no Qt): what came in shown as text (bytes
that are not printable as ``\\xNN``) or as hex, and a send line read as text (with ``\\n``,
``\\r``, ``\\t``, ``\\\\`` and ``\\xNN`` escapes) or as hex digits, plus the chosen line ending."""
from __future__ import annotations

import re

from ...errors import ZumlError
from ...i18n import _

ENDINGS = {"none": b"", "lf": b"\n", "cr": b"\r", "crlf": b"\r\n"}
_ESCAPES = {"n": b"\n", "r": b"\r", "t": b"\t", "\\": b"\\", "0": b"\0"}


class SendLineError(ZumlError, ValueError):
    """A send line that is not what its mode expects; the message is for the user."""


def as_text(data: bytes) -> str:
    """Printable ASCII as it is, line breaks and tabs kept, every other byte as ``\\xNN``."""
    out = []
    for byte in data:
        if byte in (0x0A, 0x09) or 0x20 <= byte < 0x7F:
            out.append(chr(byte))
        elif byte == 0x0D:
            continue                    # a CR of a CR+LF: the LF breaks the line
        else:
            out.append(f"\\x{byte:02x}")
    return "".join(out)


def as_hex(data: bytes) -> str:
    """Two hex digits a byte, a space between bytes, and one after (chunks join up)."""
    return "".join(f"{byte:02x} " for byte in data)


def parse_send(line: str, hex_mode: bool, ending: str = "none") -> bytes:
    """The bytes a send line stands for, with the line ending ``ending`` (a key of ENDINGS)."""
    if hex_mode:
        digits = re.sub(r"[\s,:]+", "", line.removeprefix("0x"))
        if len(digits) % 2 or re.search(r"[^0-9a-fA-F]", digits):
            raise SendLineError(_("not hex bytes: {line!r} (write pairs of hex digits, e.g. 55 aa 01)").format(
                line=line))
        return bytes.fromhex(digits) + ENDINGS[ending]
    out = bytearray()
    i = 0
    while i < len(line):
        char = line[i]
        if char != "\\":
            out += char.encode("utf-8")
            i += 1
            continue
        code = line[i + 1:i + 2]
        if code == "x" and re.fullmatch(r"[0-9a-fA-F]{2}", line[i + 2:i + 4]):
            out.append(int(line[i + 2:i + 4], 16))
            i += 4
        elif code in _ESCAPES:
            out += _ESCAPES[code]
            i += 2
        else:
            raise SendLineError(_("unknown escape {escape} at column {column}: use \\n, \\r, \\t, \\\\ or \\xNN")
                                .format(escape="\\" + code, column=i + 1))
    return bytes(out) + ENDINGS[ending]
