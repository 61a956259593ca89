"""Sessions: one log file (or one live run's recording) is one session of one pack, whatever cycles it
holds. A file is known by the SHA-256 of its bytes, so importing it again, under any name or from any
folder, adds nothing."""
from __future__ import annotations

import datetime as dt
import hashlib
import re
import sqlite3
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from pathlib import Path

from ..file_errors import FileReadError, read_file_bytes
from ..logs import Log, LogFormatError, read_log
from .db import Logbook
from .figures import SessionFigures, session_figures
from .matching import mismatch
from .register import Pack
from .text import storable, stored_path
from ..i18n import _

_DATE_IN_NAME = re.compile(r"(?<!\d)((?:19|20)\d\d)[-_.]?(0[1-9]|1[0-2])[-_.]?(0[1-9]|[12]\d|3[01])(?!\d)")
FIGURE_COLUMNS = tuple(SessionFigures.__dataclass_fields__)


@dataclass(frozen=True)
class Session:
    id: int
    file: str
    source: str                    # "file" or "live"
    format: str | None
    device: str | None
    recorded: str                  # ISO date or date-time
    recorded_from: str             # "file name", "file time" or "run"
    figures: SessionFigures
    passport_errors: int | None = None        # the battery passport's ERR and CRIT when a live run read them
    passport_critical: int | None = None
    # Why the log seems another pack's, when it was filed all the same (--force): its figures are kept out
    # of the trend and the health verdict.
    foreign_reason: str | None = None
    # The other files that hold the same charge (a .lov and its raw capture, an .osd and its CSV export),
    # one a line: recognised on import and kept once.
    same_files: str = ""

    def as_dict(self) -> dict:
        return {"file": self.file, "source": self.source, "format": self.format, "device": self.device,
                "recorded": self.recorded, "recorded_from": self.recorded_from, **self.figures.as_dict(),
                "passport_errors": self.passport_errors, "passport_critical": self.passport_critical,
                "foreign_reason": self.foreign_reason,
                "same_files": [f for f in self.same_files.split("\n") if f]}


@dataclass(frozen=True)
class ImportResult:
    path: str
    status: str                    # "added", "known" (the same bytes are a session already), "foreign"
                                   # (another pack's: not filed, the message says why) or "error"
    message: str = ""


def file_sha256(data: bytes) -> str:
    return hashlib.sha256(data).hexdigest()


def recorded_date(path: Path, log: Log | None = None) -> tuple[str, str]:
    """When a file was recorded, and whence that is known: the log's own time stamp ("log": a .lov's
    header, an .osd's or a record-set CSV's first start time), else a date in its name ("file name":
    chargers' PC programs name logs by date), else the file's modification time ("file time", a
    fallback the report and ``pack show`` say)."""
    if log is not None and log.meta.get("started"):
        return str(log.meta["started"]), "log"
    found = _DATE_IN_NAME.search(path.name)
    if found:
        try:
            return dt.date(*map(int, found.groups())).isoformat(), "file name"
        except ValueError:
            pass
    stamp = dt.datetime.fromtimestamp(path.stat().st_mtime, dt.timezone.utc)
    return stamp.isoformat(timespec="seconds"), "file time"


def log_files(paths: Iterable[str | Path]) -> list[Path]:
    """The files named and every file under the folders named, in name order; hidden ones skipped."""
    out: list[Path] = []
    for p in map(Path, paths):
        if p.is_dir():
            out += sorted(f for f in p.rglob("*") if f.is_file()
                          and not any(part.startswith(".") for part in f.relative_to(p).parts))
        else:
            out.append(p)
    return out


def import_files(book: Logbook, pack: Pack, paths: Iterable[str | Path],
                 progress: Callable[[int, int, ImportResult], None] | None = None, *,
                 force: bool = False) -> list[ImportResult]:
    """Import each file (folders: every file under them) into ``pack``; ``progress(done, total, result)``
    after each. A file no reader reads is an "error" result, never a reason to stop; a log whose
    chemistry or cells contradict the pack's is "foreign" and not filed, unless ``force``."""
    files = log_files(paths)
    results = []
    for n, path in enumerate(files, 1):
        result = import_file(book, pack, path, force=force)
        results.append(result)
        if progress is not None:
            progress(n, len(files), result)
    return results


def import_file(book: Logbook, pack: Pack, path: Path, *, source: str = "file",
                passport: tuple[int | None, int | None] = (None, None), force: bool = False) -> ImportResult:
    """``passport``: the battery passport's (ERR, CRIT) counters, when the run read them. A log that is
    another pack's (``matching.mismatch``) is not filed, unless ``force``: filed then, marked."""
    try:
        data = read_file_bytes(path, pipes=False)
    except FileReadError as exc:
        return ImportResult(storable(str(path)), "error", storable(str(exc)))
    digest = file_sha256(data)
    known = _session_of(book, digest)
    if known:
        return ImportResult(storable(str(path)), "known", _("already in pack {pack!r} as {file}").format(
                pack=known[0], file=known[1]))
    try:
        log = read_log(data, path.name)
    except LogFormatError as exc:
        return ImportResult(storable(str(path)), "error", storable(str(exc)))
    if not log.samples:
        return ImportResult(storable(str(path)), "error", _("the log holds no sample"))
    foreign = mismatch(log, pack, path.name)
    if foreign and not force:
        return ImportResult(storable(str(path)), "foreign", _("not this pack's: {reason} (--force files it, "
                                                              "marked)").format(reason=foreign))
    figures = session_figures(log, pack.cells, pack.chemistry)
    if source == "live":
        recorded, recorded_from = dt.datetime.now(dt.timezone.utc).isoformat(timespec="seconds"), "run"
    else:
        recorded, recorded_from = recorded_date(path, log)
    # a run recorded live is a recording of its own; a file may be another format of one already filed
    same = None if source == "live" else _same_charge(book, pack, figures, recorded, recorded_from)
    if same is not None:
        with book.write() as conn:
            conn.execute("UPDATE sessions SET same_files = same_files || ? WHERE id = ?",
                         (stored_path(path) + "\n", same[0]))
        return ImportResult(storable(str(path)), "known", _("the same charge as {file} (duration and charge agree): "
                                                            "kept once, both files listed").format(file=same[1]))
    columns = ("pack_id", "sha256", "file", "source", "format", "device", "recorded", "recorded_from",
               "imported", "passport_errors", "passport_critical", "foreign_reason") + FIGURE_COLUMNS
    values = (pack.id, digest, stored_path(path), source, log.format, log.device, recorded,
              recorded_from, dt.datetime.now(dt.timezone.utc).isoformat(timespec="seconds"), *passport, foreign,
              *(getattr(figures, c) for c in FIGURE_COLUMNS))
    try:
        with book.write() as conn:
            conn.execute(f"INSERT INTO sessions ({', '.join(columns)}) VALUES ({', '.join('?' * len(columns))})",
                         values)
    except sqlite3.IntegrityError:        # another instance imported the same bytes meanwhile
        pack_name, file = _session_of(book, digest) or (pack.name, stored_path(path))
        return ImportResult(storable(str(path)), "known", _("already in pack {pack!r} as {file}").format(
                pack=pack_name, file=file))
    if foreign:
        return ImportResult(storable(str(path)), "added", _("filed as asked, marked: {reason}").format(
                reason=foreign))
    if log.cells and log.cells != pack.cells:
        return ImportResult(storable(str(path)), "added", _("the log shows {log_cells} cells, the pack has {cells}").format(
                log_cells=log.cells, cells=pack.cells))
    return ImportResult(storable(str(path)), "added")


# Two files hold the same charge when their durations and charges in and out agree within these.
SAME_DURATION = 0.01
SAME_CHARGE = 0.02
SAME_MIN_MAH = 2.0
SAME_START_S = 120.0       # two logs both dated by their own time stamps start this close, or are two charges


def _same_charge(book: Logbook, pack: Pack, figures: SessionFigures, recorded: str,
                 recorded_from: str) -> tuple[int, str] | None:
    """A session of the pack holding the charge ``figures`` describe (another format of the same
    recording): (its id, its file), else None. Logs that moved no charge are never the same; two that
    both carry their own start time must start together."""
    if not figures.charge_in_mah and not figures.charge_out_mah:
        return None
    for row in book.read("SELECT id, file, duration_s, charge_in_mah, charge_out_mah, recorded, recorded_from "
                         "FROM sessions WHERE pack_id = ?", (pack.id,)):
        if row["duration_s"] is None or abs(row["duration_s"] - figures.duration_s) > max(
                2.0, SAME_DURATION * figures.duration_s):
            continue
        if recorded_from == "log" and row["recorded_from"] == "log" and not _together(recorded, row["recorded"]):
            continue
        if all(a is not None and b is not None and abs(a - b) <= max(SAME_MIN_MAH, SAME_CHARGE * max(a, b))
               for a, b in ((row["charge_in_mah"], figures.charge_in_mah),
                            (row["charge_out_mah"], figures.charge_out_mah))):
            return row["id"], row["file"]
    return None


def _together(a: str, b: str) -> bool:
    try:
        ta, tb = dt.datetime.fromisoformat(a), dt.datetime.fromisoformat(b)
        return abs((ta - tb).total_seconds()) <= SAME_START_S
    except (TypeError, ValueError):         # naive against aware, or no date: the time cannot tell them apart
        return True


def _session_of(book: Logbook, digest: str) -> tuple[str, str] | None:
    rows = book.read("SELECT packs.name, sessions.file FROM sessions JOIN packs ON packs.id = sessions.pack_id "
                     "WHERE sha256 = ?", (digest,))
    return (rows[0][0], rows[0][1]) if rows else None


def pack_sessions(book: Logbook, pack: Pack) -> list[Session]:
    """The pack's sessions, oldest first."""
    rows = book.read("SELECT * FROM sessions WHERE pack_id = ? ORDER BY recorded, id", (pack.id,))
    return [Session(r["id"], r["file"], r["source"], r["format"], r["device"], r["recorded"], r["recorded_from"],
                    SessionFigures(**{c: r[c] for c in FIGURE_COLUMNS}), r["passport_errors"],
                    r["passport_critical"], r["foreign_reason"], r["same_files"])
            for r in rows]


def remove_session(book: Logbook, session_id: int) -> None:
    with book.write() as conn:
        conn.execute("DELETE FROM sessions WHERE id = ?", (session_id,))
