"""DataExplorer's CSV export (``tests/data/logs/AkkuMasterC4_*.csv``): a first
line naming the device (``AkkuMasterC4`` or ``device;configuration``), a header line
``Zeit [sec];Spannung [V];Strom [A];Ladung [mAh]`` (``Time [sec]`` in English), then one row
per point, ``;``-separated, the decimal point or comma as the user's settings had it.

The export says nothing about the direction: a discharge exported with positive current is
told by its voltage falling under load, else the current's sign decides (``record_sets``).
Which column is what: ``columns.py``. Times may also be ``hh:mm:ss.SSS``."""
from __future__ import annotations

import re

from . import record_sets
from .columns import parse_column, roles
from .model import Log, LogFormatError, SampleBuilder
from ..i18n import _

MAX_COLUMNS = 256
_HEADER = re.compile(r"^\s*(?:Zeit|Time)\s*\[[^\]]*\]\s*;")
_CLOCK = re.compile(r"^(\d{1,6}):(\d{2}):(\d{2}(?:[.,]\d{1,6})?)$")


def _lines(data: bytes) -> list[str]:
    try:
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError:            # written on Windows: code page 1252
        text = data.decode("latin-1")
    return text.splitlines()


def sniff(head: bytes, name: str) -> bool:
    lines = head.lstrip(b"\xef\xbb\xbf").split(b"\n", 2)
    return len(lines) >= 2 and _HEADER.match(lines[1].decode("latin-1")) is not None


def _number(text: str) -> float:
    value = float(text.strip().replace(",", "."))
    if value != value or value in (float("inf"), float("-inf")):
        raise ValueError(text)
    return value


def _seconds(text: str) -> float:
    m = _CLOCK.match(text.strip())
    if m:
        return int(m.group(1)) * 3600 + int(m.group(2)) * 60 + _number(m.group(3))
    return _number(text)


def read(data: bytes) -> Log:
    lines = _lines(data)
    if len(lines) < 2 or not _HEADER.match(lines[1]):
        raise LogFormatError(_("not a DataExplorer CSV export: no 'Zeit [sec];…' header on line 2"))
    device = lines[0].split(";")[0].strip() or "DataExplorer CSV"
    columns = [parse_column(part) for part in lines[1].split(";")[1:MAX_COLUMNS + 1]]
    r = roles(columns)
    if r.voltage is None:
        raise LogFormatError(_("no column in volts ([V]) for the pack voltage"))
    rows: list[list[float]] = []
    bad = 0
    for line in lines[2:]:
        if not line.strip():
            continue
        parts = line.split(";")
        if len(parts) < len(columns) + 1:
            bad += 1
            continue
        try:
            t = _seconds(parts[0])
            numbers = [_number(p) for p in parts[1:len(columns) + 1]]
        except ValueError:
            bad += 1
            continue
        rows.append([t] + numbers)
    if not rows:
        raise LogFormatError(_("no data row ({bad} bad rows)").format(bad=bad))
    cols = list(zip(*rows))
    pick = lambda k: None if k is None else cols[k + 1]
    mah = pick(r.mah) if r.mah is not None else (None if r.ah is None else [x * 1000.0 for x in cols[r.ah + 1]])
    builder = SampleBuilder()
    record_sets.add_set(builder, "", cols[0], pick(r.voltage), pick(r.current), mah, temp=pick(r.temp),
                        cells=[cols[k + 1] for k in r.cells])
    meta = {} if r.current is not None else {"current_measured": False}
    return builder.build("dataexplorer-csv", device, bad, **meta)
