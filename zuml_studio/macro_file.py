"""Reading and writing .zuml files so that a save gives back exactly the bytes
that were opened: line endings and a UTF-8 byte-order mark are kept."""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

from .file_errors import FileReadError, read_file_bytes
from .recovery import atomic_write
from .errors import ZumlError
from .i18n import _

EXTENSION = ".zuml"


class MacroFileError(ZumlError):
    pass


@dataclass(frozen=True)
class MacroFile:
    text: str            # "\n" line endings, as the editor holds it
    newline: str = "\n"
    bom: bool = False

    def encode(self, text: str | None = None) -> bytes:
        body = (self.text if text is None else text).replace("\n", self.newline)
        return ("\ufeff" if self.bom else "").encode("utf-8") + body.encode("utf-8")


def read_macro_file(path: str | Path) -> MacroFile:
    try:
        data = read_file_bytes(path)
    except FileReadError as exc:
        raise MacroFileError(str(exc)) from None
    bom = data.startswith(b"\xef\xbb\xbf")
    try:
        text = data[3 if bom else 0:].decode("utf-8")
    except UnicodeDecodeError as exc:
        raise MacroFileError(_("{path}: not UTF-8 text (byte 0x{data:02x} at offset {start})").format(
                path=path, data=data[exc.start], start=exc.start)) from None
    if "\x00" in text:
        raise MacroFileError(_("{path}: a binary file, not a macro (a compiled record? open it with Decompile)").format(
                path=path))
    newline = "\r\n" if "\r\n" in text else "\n"
    return MacroFile(text.replace("\r\n", "\n"), newline, bom)


def write_macro_file(path: str | Path, text: str, like: MacroFile | None = None) -> MacroFile:
    saved = MacroFile(text, like.newline if like else "\n", like.bom if like else False)
    try:
        atomic_write(Path(path), saved.encode())
    except OSError as exc:
        raise MacroFileError(_("{path}: cannot save: {error}").format(path=path, error=exc.strerror or exc)) from None
    return saved
