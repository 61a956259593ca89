"""Putting one macro into a device's EEPROM image: the rule ``zuml flash`` and the GUI's
Compile & Flash share. Without a slot, a macro of the same name is replaced, else the
record is appended; with a slot, that slot is replaced (slot = the count appends).

No Qt, no port: ``merge_record(image, record, slot)`` works on bytes; the caller writes
the result with ``ChargerClient.write_image``."""
from __future__ import annotations

from dataclasses import dataclass

from ...lang.decoder import decode_record
from ...lang.eeprom import pack, slots
from ...errors import ZumlError, error_text
from ...i18n import _, ngettext


class MergeError(ZumlError, ValueError):
    """The record cannot go into the image as asked."""


class SlotOutOfRange(MergeError):
    def __init__(self, slot: int, count: int):
        self.slot = slot
        self.count = count
        super().__init__(_("slot {slot}: the charger has slots 0..{last} ({count} appends)").format(
                slot=slot, last=count - 1, count=count) if count
                         else _("slot {slot}: the charger has no macros yet (0 appends)").format(slot=slot))

    def words(self, action: str = "") -> str:
        if action in ("flash", "restore"):
            return _("Cannot flash: {error}").format(error=error_text(self))
        return super().words(action)


class ImageFull(MergeError):
    """The records do not fit the EEPROM."""

    def __init__(self, name: str, count: int, needed: int, size: int):
        self.name = name
        self.count = count
        self.needed = needed
        self.size = size
        super().__init__(ngettext("{count} record needs {needed} bytes; the EEPROM has {size}",
                                  "{count} records need {needed} bytes; the EEPROM has {size}", count).format(
                count=count, needed=needed, size=size))

    def words(self, action: str = "") -> str:
        if action in ("flash", "restore"):
            return _("The image needs {needed} bytes; the charger has {size}. Nothing was written.").format(
                needed=self.needed, size=self.size)
        return super().words(action)


@dataclass(frozen=True)
class Merge:
    image: bytes              # the new image, as large as the old one
    index: int                # the slot the record is in now
    name: str                 # the record's macro name
    replaced: str | None      # the name of the macro it replaced; None when appended
    size: int                 # the record's length in bytes
    used: int                 # bytes the records take in the new image

    @property
    def appended(self) -> bool:
        return self.replaced is None

    @property
    def action(self) -> str:
        """``replaced slot 0 (NiMh-dV)`` or ``appended as slot 2``."""
        if self.replaced is None:
            return _("appended as slot {index}").format(index=self.index)
        return _("replaced slot {index} ({name})").format(index=self.index, name=self.replaced)


def merge_record(image: bytes, record: bytes, slot: int | None = None) -> Merge:
    """``image`` with ``record`` put in: into ``slot`` if given, else over the macro of the
    same name, else appended.

    Raises ``lang.eeprom.ImageError`` (the image's record list is broken),
    ``lang.record.DecodeError`` (``record`` is not a record), ``SlotOutOfRange``, ``ImageFull``."""
    record = bytes(record)
    name = decode_record(record).macro.name
    found = slots(image)
    recs = [s.record for s in found]
    if slot is not None:
        if not 0 <= slot <= len(recs):
            raise SlotOutOfRange(slot, len(recs))
        index = slot
    else:
        index = next((s.index for s in found if s.decoded and s.name == name), len(recs))
    replaced = found[index].name if index < len(recs) else None
    if index < len(recs):
        recs[index] = record
    else:
        recs.append(record)
    needed = sum(len(r) for r in recs)
    if needed > len(image):
        raise ImageFull(name, len(recs), needed, len(image))
    return Merge(pack(recs, len(image)), index, name, replaced, len(record), needed)
