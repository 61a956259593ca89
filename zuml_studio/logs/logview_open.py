"""LogView "open format" text (LogView Studio's documentation as quoted in DataExplorer's
``ZeroReaderWriter``): header lines ``$X$;…`` (``$Xn$;…`` for channel n = 1..6) and data
lines ``$v1;v2;…`` (``$n$;v1;…`` for channel n).

Headers: ``N`` data-set name (starts a data set), ``C`` columns ``Name [unit,symbol]``,
``V`` value format DOUBLE or HEX, ``F``/``O``/``S`` factor, offset, sum offset per column
(y = (x + offset) · factor + sum offset), ``T`` time given (column index, format such as
``ddHHmmss``), ``I`` time increment in ms, ``R`` back to receive time, ``L`` a log message.

What this reader decides where the format is silent (docs/logs.md): the first channel that
sends data is read (other channels are counted); data sets of that channel follow each
other on one time line; without ``T`` or ``I`` a line is 1 s; values beyond the named
columns are ignored, fewer values than columns make the line bad. Which column is the pack
voltage, the current, … : ``columns.py``."""
from __future__ import annotations

import math
import re

from .columns import Roles, add_row, parse_column, roles as column_roles
from .model import Log, LogFormatError, SampleBuilder
from ..i18n import _

MAX_LINE = 4096
MAX_COLUMNS = 256
MAX_MESSAGES = 200
DEFAULT_STEP_S = 1.0
_HEADER = re.compile(r"^\$([A-Z])([1-6]?)\$(?:;(.*))?$")
_CHANNEL_DATA = re.compile(r"^\$([1-6])\$;(.*)$")
_TIME_FIELDS = (("dd", 86400.0), ("HH", 3600.0), ("hh", 3600.0), ("mm", 60.0), ("ss", 1.0), ("fff", 0.001),
                ("zzz", 0.001))


def sniff(head: bytes, name: str) -> bool:
    for raw in head.split(b"\n")[:8]:
        line = raw.strip()
        if line:
            return re.match(rb"^\$[A-Z][1-6]?\$(;|$)", line) is not None
    return False


class _Channel:
    def __init__(self) -> None:
        self.columns: list[tuple[str, str]] = []
        self.hex = False
        self.factor: list[str] = []
        self.offset: list[str] = []
        self.sum_offset: list[str] = []
        self.time_index: int | None = None
        self.time_format = ""
        self.increment_s: float | None = None


def _apply_header(ch: _Channel, kind: str, rest: str) -> None:
    """What a header line sets for its channel's next data lines."""
    if kind == "C":
        ch.columns = _columns(rest)
    elif kind == "V":
        ch.hex = rest.strip().upper() == "HEX"
    elif kind == "F":
        ch.factor = rest.split(";")
    elif kind == "O":
        ch.offset = rest.split(";")
    elif kind == "S":
        ch.sum_offset = rest.split(";")
    elif kind == "T":
        parts = rest.split(";")
        index = parts[0].strip()
        ch.time_index = int(index) if index.isascii() and index.isdigit() and len(index) < 4 else None
        ch.time_format = parts[1].strip() if len(parts) > 1 else ""
        ch.increment_s = None
    elif kind == "I":
        try:
            ch.increment_s = max(_float(rest.split(";")[0]), 0.0) / 1000.0
        except ValueError:
            ch.increment_s = None
        ch.time_index = None
    elif kind == "R":
        ch.time_index, ch.increment_s = None, None


def _columns(spec: str) -> list[tuple[str, str]]:
    return [parse_column(part) for part in spec.split(";")[:MAX_COLUMNS]]


def _float(text: str) -> float:
    value = float(text.strip().replace(",", ".").replace(" ", ""))
    if value != value or value in (float("inf"), float("-inf")):
        raise ValueError(text)
    return value


def _coefficient(values: list[str], k: int, default: float) -> float:
    if k < len(values) and values[k].strip():
        try:
            return _float(values[k])
        except ValueError:
            return default
    return default


def _given_seconds(value: str, fmt: str) -> float:
    """``28160001`` with ``ddHHmmss`` -> seconds since the start of the month. Only day, hour,
    minute, second and millisecond fields count."""
    seconds = 0.0
    for key, scale in _TIME_FIELDS:
        at = fmt.find(key)
        if at >= 0:
            digits = value[at:at + len(key)]
            if len(digits) != len(key) or not digits.isdigit():
                raise ValueError(value)
            seconds += int(digits) * scale
    return seconds


def read(data: bytes) -> Log:
    if data.startswith(b"\xef\xbb\xbf"):
        data = data[3:]
    try:
        text = data.decode("utf-8")
    except UnicodeDecodeError:          # LogView runs on Windows: code page 1252 text
        text = data.decode("latin-1")
    channels: dict[int, _Channel] = {}
    messages: list[str] = []
    builder = SampleBuilder()
    roles: Roles | None = None
    chosen: int | None = None
    bad = other = 0
    t_next = 0.0            # receive/increment time of the next line
    set_offset = 0.0        # where the current data set starts on the time line
    given_start: float | None = None
    for raw in text.split("\n"):
        line = raw.strip()
        if not line.startswith("$"):
            continue
        if len(line) > MAX_LINE:
            bad += 1
            continue
        head = _HEADER.match(line)
        if head:
            kind, ch_text, rest = head.group(1), head.group(2), head.group(3) or ""
            ch = channels.setdefault(int(ch_text or 1), _Channel())
            if kind == "N" and int(ch_text or 1) == chosen and len(builder):
                set_offset = builder.last("t") + (ch.increment_s or DEFAULT_STEP_S)
                t_next, given_start = 0.0, None
            elif kind == "C" and int(ch_text or 1) == chosen:
                roles = None
            elif kind == "L" and len(messages) < MAX_MESSAGES:
                messages.append(rest)
            _apply_header(ch, kind, rest)
            continue
        m = _CHANNEL_DATA.match(line)
        number_ch, body = (int(m.group(1)), m.group(2)) if m else (1, line[1:])
        if chosen is None:
            chosen = number_ch
        if number_ch != chosen:
            other += 1
            continue
        ch = channels.get(chosen)
        if ch is None or not ch.columns:
            bad += 1
            continue
        if roles is None:
            roles = column_roles(ch.columns)
            if roles.voltage is None:
                raise LogFormatError(_("no column in volts ([V]) for the pack voltage"))
        values = body.split(";")
        given = ch.time_index
        try:
            if given is not None:
                if given >= len(values):
                    raise ValueError(_("no time"))
                t_given = _given_seconds(values[given].strip(), ch.time_format)
                values = values[:given] + values[given + 1:]
            if len(values) < len(ch.columns):
                raise ValueError(_("too few values"))
            numbers = []
            for k in range(len(ch.columns)):
                item = values[k].strip()
                x = float(int(item, 16)) if ch.hex else _float(item)
                y = (x + _coefficient(ch.offset, k, 0.0)) * _coefficient(ch.factor, k, 1.0) + \
                    _coefficient(ch.sum_offset, k, 0.0)
                if not math.isfinite(y):
                    raise ValueError(item)
                numbers.append(y)
        except (ValueError, OverflowError):
            bad += 1
            continue
        if given is not None:
            if given_start is None:
                given_start = t_given
            t = set_offset + t_given - given_start
        else:
            t = set_offset + t_next
            t_next += ch.increment_s if ch.increment_s is not None else DEFAULT_STEP_S
        add_row(builder, roles, numbers, t)
    if not len(builder):
        raise LogFormatError(_("no data line read ({bad} bad lines)").format(
                bad=bad) if channels else _("no '$X$;' header line"))
    meta = {"channel": chosen, "columns": [n for n, __ in channels[chosen].columns]}
    if other:
        meta["other_channel_lines"] = other
    if messages:
        meta["messages"] = messages
    if roles and roles.current is None:
        meta["current_measured"] = False
    return builder.build("logview-open", "LogView open format", bad, **meta)
