"""Names, notes and paths from the user's command line, file system or GUI, made safe to store and
to print: the logbook (SQLite, UTF-8) cannot hold a file name's undecodable bytes (Python gives them as
lone surrogates, ``\\udcfc`` for a Latin-1 "ü"), and a terminal obeys control characters (an ESC sequence
clears the screen). Both are written ``\\xNN`` (``\\uNNNN`` above 0xFF), as the battery passport's
strings are (``protocol.passport.printable``), while readable text (Cyrillic, accents) stays as it is."""
from __future__ import annotations

import os
import re
import unicodedata
from pathlib import Path

_ESCAPED_BYTE = re.compile(r"\\x([0-9a-fA-F]{2})")


def _escape(c: str) -> str:
    code = ord(c)
    if 0xDC80 <= code <= 0xDCFF:               # an undecodable byte of a file name (surrogateescape)
        return f"\\x{code - 0xDC00:02x}"
    return f"\\x{code:02x}" if code <= 0xFF else f"\\u{code:04x}"


def storable(text: str) -> str:
    """``text`` with lone surrogates (undecodable bytes) as ``\\xNN``: valid UTF-8 for the logbook."""
    return "".join(_escape(c) if 0xD800 <= ord(c) <= 0xDFFF else c for c in text)


def printable(text: str) -> str:
    """``text`` for a terminal or a label: control and format characters (C0, DEL, C1, bidirectional
    overrides, zero-width marks) and lone surrogates as ``\\xNN``/``\\uNNNN``."""
    return "".join(_escape(c) if unicodedata.category(c) in ("Cc", "Cf", "Cs") else c for c in text)


def stored_path(path: str | Path) -> str:
    """An absolute path as the logbook keeps it (``storable``)."""
    return storable(os.path.abspath(path))


def path_of(stored: str) -> Path:
    """The file a stored path names: as it is when that exists, else with its ``\\xNN`` bytes restored."""
    if Path(stored).exists() or "\\x" not in stored:
        return Path(stored)
    raw = _ESCAPED_BYTE.sub(lambda m: chr(0xDC00 + int(m.group(1), 16)) if int(m.group(1), 16) >= 0x80
                            else chr(int(m.group(1), 16)), stored)
    return Path(os.fsdecode(os.fsencode(raw)))
