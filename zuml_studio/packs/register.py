"""The pack register: add, list, read and remove packs, and which pack a live port or passport serial
was attached to (asked once, remembered)."""
from __future__ import annotations

import datetime as dt
import re
from dataclasses import dataclass

from ..domain.chemistry import load_chemistry
from .text import storable
from .db import Logbook, LogbookError
from ..errors import ZumlError
from ..i18n import _

_NAME = re.compile(r"^\S(.{0,78}\S)?$")


@dataclass(frozen=True)
class Pack:
    id: int
    name: str
    chemistry: str
    cells: int
    capacity_mah: float
    bought: str | None = None
    notes: str = ""
    serial: str | None = None

    def as_dict(self) -> dict:
        return {"name": self.name, "chemistry": self.chemistry, "cells": self.cells,
                "capacity_mah": self.capacity_mah, "bought": self.bought, "notes": self.notes,
                "serial": self.serial}


class PackError(ZumlError, ValueError):
    """A pack that does not exist, or values a pack cannot have; the message says which."""


def _checked(name: str, chemistry: str, cells: int, capacity_mah: float, bought: str | None) -> str:
    if not _NAME.match(name or ""):
        raise PackError(_("pack name {name!r}: 1 to 80 characters, not starting or ending with a space").format(
                name=name))
    try:
        chem = load_chemistry(chemistry).name
    except KeyError as exc:
        raise PackError(str(exc.args[0])) from None
    if not 1 <= cells <= 32:
        raise PackError(_("cells must be 1 to 32, not {cells}").format(cells=cells))
    if not 0 < capacity_mah <= 1_000_000:
        raise PackError(_("capacity must be above 0 and at most 1000000 mAh, not {capacity:g}").format(
                capacity=capacity_mah))
    if bought is not None:
        try:
            dt.date.fromisoformat(bought)
        except ValueError:
            raise PackError(_("date bought {bought!r}: write it as YYYY-MM-DD").format(bought=bought)) from None
    return chem


def add_pack(book: Logbook, name: str, chemistry: str, cells: int, capacity_mah: float, *,
             bought: str | None = None, notes: str = "", serial: str | None = None) -> Pack:
    """A name, notes or serial with bytes that are not UTF-8 (a shell's argument) are kept with those
    bytes as ``\\xNN`` (``text.storable``)."""
    name, notes, serial = storable(name), storable(notes), None if serial is None else storable(serial)
    chem = _checked(name, chemistry, cells, capacity_mah, bought)
    with book.write() as conn:
        if conn.execute("SELECT 1 FROM packs WHERE name = ?", (name,)).fetchone():
            raise PackError(_("a pack named {name!r} exists already").format(name=name))
        cur = conn.execute(
            "INSERT INTO packs (name, chemistry, cells, capacity_mah, bought, notes, serial, created) "
            "VALUES (?, ?, ?, ?, ?, ?, ?, ?)",
            (name, chem, cells, float(capacity_mah), bought, notes, serial or None,
             dt.datetime.now(dt.timezone.utc).isoformat(timespec="seconds")))
        pack_id = cur.lastrowid
    return Pack(pack_id, name, chem, cells, float(capacity_mah), bought, notes, serial or None)


def _pack(row) -> Pack:
    return Pack(row["id"], row["name"], row["chemistry"], row["cells"], row["capacity_mah"], row["bought"],
                row["notes"], row["serial"])


def list_packs(book: Logbook) -> list[Pack]:
    return [_pack(r) for r in book.read("SELECT * FROM packs ORDER BY name COLLATE NOCASE")]


def get_pack(book: Logbook, name: str) -> Pack:
    name = storable(name)
    rows = book.read("SELECT * FROM packs WHERE name = ?", (name,))
    if not rows:
        known = ", ".join(p.name for p in list_packs(book)) or _("none yet")
        raise PackError(_("no pack named {name!r} (packs: {known})").format(name=name, known=known))
    return _pack(rows[0])


def remove_pack(book: Logbook, name: str) -> int:
    """Removes the pack with its sessions; returns how many sessions went with it."""
    pack = get_pack(book, name)
    with book.write() as conn:
        sessions = conn.execute("SELECT COUNT(*) FROM sessions WHERE pack_id = ?", (pack.id,)).fetchone()[0]
        conn.execute("DELETE FROM packs WHERE id = ?", (pack.id,))
    return sessions


def attachment_key(port: str, serial: str | None) -> str:
    """A passport's serial names the battery wherever it is plugged in; without one, the port does."""
    return f"serial:{serial}" if serial else f"port:{port}"


def attachment(book: Logbook, key: str) -> tuple[bool, Pack | None]:
    """(whether a choice is remembered for ``key``, the pack chosen: None for "record no pack here")."""
    rows = book.read("SELECT packs.* FROM attachments LEFT JOIN packs ON packs.id = attachments.pack_id "
                     "WHERE attachments.key = ?", (key,))
    if not rows:
        return False, None
    return True, (_pack(rows[0]) if rows[0]["id"] is not None else None)


def attach(book: Logbook, key: str, pack: Pack | None) -> None:
    """Remember ``pack`` for ``key``; None remembers "no pack" (the runs there are not recorded)."""
    with book.write() as conn:
        conn.execute("INSERT OR REPLACE INTO attachments (key, pack_id) VALUES (?, ?)",
                     (key, pack.id if pack is not None else None))


def forget_attachments(book: Logbook, key: str | None = None) -> int:
    """The next run there (``key``; None: everywhere) asks again; returns how many answers were forgotten."""
    with book.write() as conn:
        if key is None:
            return conn.execute("DELETE FROM attachments").rowcount
        return conn.execute("DELETE FROM attachments WHERE key = ?", (key,)).rowcount


__all__ = ["Pack", "PackError", "LogbookError", "add_pack", "list_packs", "get_pack", "remove_pack",
           "attachment_key", "attachment", "attach", "forget_attachments"]
