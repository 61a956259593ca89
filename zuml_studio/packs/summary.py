"""What ``zuml pack show`` prints and the Packs dock shows: one pack with its sessions, trend and health,
and the sessions as CSV rows."""
from __future__ import annotations

import csv
import io
from pathlib import Path

from ..recovery import atomic_write
from .db import Logbook
from .health import health, trend
from .register import Pack
from .sessions import FIGURE_COLUMNS, pack_sessions
from ..i18n import _

CSV_COLUMNS = ("recorded", "file", "format", "device", "source") + FIGURE_COLUMNS + (
        "passport_errors", "passport_critical")


# A session's date's source as one letter after it (``pack show`` and the report): none for the log's own.
DATED_MARK = {"log": "", "file name": "n", "file time": "t", "run": ""}


def dates_note(sessions: list[dict]) -> str | None:
    """The line that explains ``DATED_MARK``'s letters, when a session is dated otherwise than by its log."""
    if any(s["recorded_from"] in ("file name", "file time") for s in sessions):
        return _("dates from the logs' own time stamps; n: from the file's name, t: the file's modification "
                 "time (the log holds no date)")
    return None


def capacity_text(session: dict, spec: str = ".0f") -> str:
    """A session's capacity column: the figure when it is the pack's (a discharge from full to the cut-off),
    in parentheses when it is only what was taken out (see ``capacity_note``), "–" when none."""
    value = session["capacity_mah"]
    if value is None:
        return "–"
    text = format(value, spec)
    return text if session["capacity_from"] == "discharge" else f"({text})"


def capacity_note(sessions: list[dict]) -> str | None:
    """Why a capacity in parentheses is not the pack's, per session, in the user's language."""
    why = []
    for s in sessions:
        label = s["capacity_from"] or ""
        kind, _sep, pct = label.partition(": ")
        if kind == "not from full":
            why.append(_("{date}: the discharge began at about {pct} charged").format(date=s["recorded"][:10], pct=pct))
        elif kind == "partial":
            why.append(_("{date}: the discharge stopped with {pct} of its range to the cut-off covered").format(
                    date=s["recorded"][:10], pct=pct))
    if not why:
        return None
    return _("(capacity): taken out, not the pack's capacity: {why}").format(why="; ".join(why))


def pack_summary(book: Logbook, pack: Pack) -> dict:
    """The pack's fields, ``sessions`` (oldest first), ``trend`` and ``health`` (``verdict``, ``reasons``)."""
    sessions = pack_sessions(book, pack)
    return {**pack.as_dict(), "sessions": [s.as_dict() for s in sessions],
            "trend": [p.as_dict() for p in trend(pack, sessions)], "health": health(pack, sessions).as_dict()}


def write_sessions_csv(book: Logbook, pack: Pack, path: str | Path) -> int:
    """One row per session, the figures in their units (mAh, Wh, mΩ per cell, mV, °C); returns the rows.
    Written beside the target and renamed over it: a full disk never leaves half an export."""
    text = io.StringIO()
    writer = csv.writer(text, lineterminator="\n")
    writer.writerow(CSV_COLUMNS)
    sessions = pack_sessions(book, pack)
    for s in sessions:
        row = s.as_dict()
        writer.writerow(["" if row[c] is None else row[c] for c in CSV_COLUMNS])
    atomic_write(Path(path), text.getvalue().encode("utf-8"))
    return len(sessions)
