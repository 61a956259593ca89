"""EEPROM image: records back to back (docs/zuml-2.0.md §2), ending at a record whose first
byte is 0x00 or 0xFF, or at the end of memory. Free space is written 0xFF, the
erased state, so a later write changes as few bytes as possible."""
from __future__ import annotations

from dataclasses import dataclass

from .decoder import Decoded, decode_record
from .record import MIN_RECORD, DecodeError
from ..errors import ZumlError, error_text
from ..i18n import _, ngettext

DEFAULT_SIZE = 1024
ERASED = 0xFF
END_MARKERS = (0x00, 0xFF)


class ImageError(ZumlError):
    def __init__(self, offset: int, message: str):
        super().__init__(_("offset {offset}: {message}").format(
                offset=offset, message=message) if offset >= 0 else message)
        self.offset = offset
        self.message = message

    def words(self, action: str = "") -> str:
        if action in ("flash", "restore"):
            return _("The charger's record list is broken ({error}): restore a backup of its EEPROM, then flash "
                     "again.").format(error=error_text(self))
        return _("EEPROM image: {exc}").format(exc=error_text(self))


@dataclass(frozen=True)
class Slot:
    index: int
    offset: int
    record: bytes
    decoded: Decoded | None        # None when the record does not decode
    error: DecodeError | None

    @property
    def name(self) -> str:
        return self.decoded.macro.name if self.decoded else "?"

    @property
    def ok(self) -> bool:
        return self.error is None


def slots(image: bytes) -> list[Slot]:
    """Every record in the image, each decoded (and its check byte checked) on its own."""
    out: list[Slot] = []
    at = 0
    while at < len(image) and image[at] not in END_MARKERS:
        length = image[at]
        if length < MIN_RECORD:
            raise ImageError(at, _("record {n_out} says it is {length} bytes long; a record has at least "
                                   "{min_record}").format(n_out=len(out), length=length, min_record=MIN_RECORD))
        if at + length > len(image):
            raise ImageError(at, _("record {n_out} runs past the end of memory ({at} + {length} > {n_image})").format(
                    n_out=len(out), at=at, length=length, n_image=len(image)))
        record = bytes(image[at:at + length])
        try:
            decoded, error = decode_record(record), None
        except DecodeError as exc:
            decoded, error = None, exc
        out.append(Slot(len(out), at, record, decoded, error))
        at += length
    return out


def used_bytes(image: bytes) -> int:
    found = slots(image)
    return found[-1].offset + len(found[-1].record) if found else 0


def pack(records: list[bytes], size: int = DEFAULT_SIZE) -> bytes:
    """Records back to back, the rest erased. Raises ImageError when they do not fit."""
    body = b"".join(records)
    if len(body) > size:
        raise ImageError(-1, ngettext("{n_records} record needs {n_body} bytes; the EEPROM has {size}",
                                      "{n_records} records need {n_body} bytes; the EEPROM has {size}",
                                      len(records)).format(
                n_records=len(records), n_body=len(body), size=size))
    for record in records:
        if not record or record[0] != len(record):
            raise ImageError(-1, _("a record's first byte must be its length"))
    return body + bytes([ERASED]) * (size - len(body))


def records(image: bytes) -> list[bytes]:
    return [s.record for s in slots(image)]


def replace(image: bytes, index: int, record: bytes) -> bytes:
    current = records(image)
    if not 0 <= index < len(current):
        raise ImageError(-1, _("there is no slot {index}; the image has {n_current}").format(
                index=index, n_current=len(current)))
    current[index] = record
    return pack(current, len(image))


def extract(image: bytes, index: int) -> bytes:
    current = records(image)
    if not 0 <= index < len(current):
        raise ImageError(-1, _("there is no slot {index}; the image has {n_current}").format(
                index=index, n_current=len(current)))
    return current[index]
