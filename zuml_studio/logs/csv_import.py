"""Any CSV with a header line and a row per sample (a SkyRC logger's ``SN,Volatge,Current,mAH``,
a lab cycler's export, a spreadsheet, LogView's and DataExplorer's text exports): what is in
it is guessed, shown, and can be corrected.

``guess(data)`` finds the separator (``;``, tab, ``,`` or ``|``: the one that splits the
lines into the same number of fields), whether numbers use a decimal comma, the header line,
and for each column a role and a unit, by its name (German and English words, a unit in
``[…]`` or ``(…)`` or after ``_``) and, where the name gives no unit, by the size of its
values (a current above 50 is in mA, a voltage above 100 in mV, a time that counts days
since 1899 is a spreadsheet date). ``read(data, guess)`` reads the rows as that guess says.
``parse_columns`` reads a correction given as text (``zuml log info FILE.csv --columns
time:s,voltage:V,current:mA,charge:mAh``: one ``role[:unit]`` per column in order, ``-`` for
a column to leave out; columns beyond the list are left out).

Rows that do not split into the header's field count, or whose used fields are not numbers,
are bad records; a file without any good row is an error. The current's sign gives the
state (charge positive), as for DataExplorer's CSV export; a current logged positive while
discharging (the SkyRC logger's) is read with the unit ``-A`` or ``-mA``. A charge counter
that counts up while discharging counts as discharged."""
from __future__ import annotations

import codecs
import csv
import math
import re
from collections.abc import Callable, Iterator
from dataclasses import dataclass, field, replace

import numpy as np

from . import record_sets
from .model import Log, LogFormatError, SampleBuilder, in_time_order, started_at_ms
from ..i18n import _

FORMAT = "csv"
SEPARATORS = (";", "\t", ",", "|")
ROLES = ("time", "voltage", "current", "temp", "charge", "cell", "-")
UNITS = {"time": ("s", "min", "h", "ms", "day"), "voltage": ("V", "mV"), "cell": ("V", "mV"),
         "current": ("A", "mA", "-A", "-mA"), "temp": ("°C", "°F"), "charge": ("mAh", "Ah"), "-": ("",)}
SCALE = {"s": 1.0, "min": 60.0, "h": 3600.0, "ms": 0.001, "day": 86400.0, "V": 1.0, "mV": 0.001, "A": 1.0,
         "mA": 0.001, "-A": -1.0, "-mA": -0.001, "°C": 1.0, "mAh": 1.0, "Ah": 1000.0}
MAX_COLUMNS = 256
# A column's name is read up to this many characters: the guess stays linear and bounded (a header
# field of 50 000 '(' took minutes).
MAX_NAME = 200
PROBE_LINES = 40
RECORDSET = "### RECORDSET"
UTF16_BOMS = (b"\xff\xfe", b"\xfe\xff")
# A head of this many bytes without a line end is a header longer than it: the reader judges the file.
LONG_LINE = 1024
# The guess reads the columns from the file's first bytes only (its header and PROBE_LINES rows).
GUESS_BYTES = 1 << 20
# The reader decodes and reads this many bytes at a time (a large file is never held decoded whole).
TEXT_BLOCK = 1 << 20
# Where a column's name gives no unit: the largest value read as V (pack), V (cell), A. Beyond these
# no hobby charger measures (a 30S pack is 126 V; the largest charger outputs 40-60 A), so the values
# are mV or mA. Said in the log's meta (csv_assumed), never silently.
PLAUSIBLE = {"voltage": 200.0, "cell": 10.0, "current": 60.0}
CURVE_CSV = b"time_s,voltage_v,current_a"      # the fit's plain curve CSV (sim/curve.py), read there

# Words of a column's name (lower case) -> role; the first column that fits a role takes it.
WORDS = {
    "time": ("zeit", "time", "sec", "elapsed", "sn", "t", "время"),
    "voltage": ("spannung", "voltage", "volatge", "volt", "u", "v", "ubat", "vbat", "напряжение"),
    "current": ("strom", "current", "curr", "i", "ibat", "amp", "ток"),
    "temp": ("temperatur", "temperature", "temp", "t_bat", "температура"),
    "charge": ("ladung", "charge", "capacity", "kapazit", "mah", "ah", "q", "заряд", "емкость", "ёмкость"),
}
# Columns of a role whose names have one of these words are something else (a supply voltage,
# the charger's inside temperature, a raw ADC value, a date or a power).
NOT = {
    "time": ("date", "datum", "step", "index", "point", "cycle"),
    "voltage": ("versorgung", "eingang", "input", "supply", "zelle", "cell", "balance", "bec", "raw", "digital",
                "dv", "ladung"),
    "current": ("raw", "digital", "ladung", "charge_c", "capacity"),
    "temp": ("int", "ambient", "umgebung", "raw", "digital", "heatsink", "kühl"),
    "charge": ("discharge", "entlad", "energy", "energie", "wh", "raw"),
}
# Among the columns that fit, the first with the earliest of these words wins.
PREFER = {"voltage": ("calibrated", "bat", "akku", "accu", "lipo", "pack"), "current": ("calibrated",),
          "temp": ("calibrated", "bat", "akku")}
_UNIT = re.compile(r"[\[(]([^\[\]()]*)[\])]")
_CELL = re.compile(r"(?:zellenspannung|cellvoltage|cell|zelle)[\s_]{0,3}(\d{1,2})", re.IGNORECASE)
_META = re.compile(r"(\w+)=(?:'([^']*)'|(\S+))")
_DECIMAL_COMMA = re.compile(r"^\s*-?\d+,\d+\s*$")
_UNIT_WORDS = {"sec": "s", "s": "s", "seconds": "s", "sekunden": "s", "min": "min", "minutes": "min", "h": "h",
               "hours": "h", "std": "h", "ms": "ms", "v": "V", "mv": "mV", "a": "A", "ma": "mA", "°c": "°C",
               "c": "°C", "degc": "°C", "°f": "°F", "f": "°F", "mah": "mAh", "ah": "Ah",
               "с": "s", "мин": "min", "ч": "h", "мс": "ms", "в": "V", "мв": "mV", "а": "A", "ма": "mA",
               "°с": "°C", "мач": "mAh", "ач": "Ah"}


@dataclass(frozen=True)
class Column:
    name: str
    role: str = "-"        # one of ROLES
    unit: str = ""         # one of UNITS[role]
    # Why the unit was chosen when the name gives none ("" : the name gives it).
    assumed: str = field(default="", compare=False)


@dataclass(frozen=True)
class CsvGuess:
    separator: str
    decimal_comma: bool
    header_line: int           # index of the header among the file's lines
    columns: tuple[Column, ...]

    @property
    def key(self) -> str:
        """What identifies a kind of file: its separator and column names."""
        return self.separator.join(c.name for c in self.columns)

    def with_columns(self, columns: tuple[Column, ...]) -> "CsvGuess":
        return replace(self, columns=columns)

    def spec(self) -> str:
        """The columns as ``--columns`` takes them."""
        return ",".join(f"{c.role}:{c.unit}" if c.role != "-" else "-" for c in self.columns)

    def assumptions(self) -> list[str]:
        """One line per unit the header does not give: what was assumed and why."""
        return [f"{c.name or c.role}: {c.assumed}" for c in self.columns if c.role != "-" and c.assumed]


def decode(data: bytes) -> str:
    """UTF-16 with its byte-order mark (Excel's "Unicode text"), UTF-8, else a Windows code page:
    1251 (Cyrillic) when most letters are bytes above 0xBF (Russian words are all such bytes; German
    ones have an umlaut here and there), else 1252."""
    if data.startswith(UTF16_BOMS):
        return data.decode("utf-16", "replace")
    return data.decode(_encoding(data), "replace")


def _encoding(data: bytes) -> str:
    """``decode``'s choice for bytes without a UTF-16 mark, found without decoding them whole."""
    if data.isascii():
        return "ascii"
    check = codecs.getincrementaldecoder("utf-8")()
    try:
        for at in range(0, len(data), TEXT_BLOCK):
            check.decode(data[at:at + TEXT_BLOCK])
        check.decode(b"", final=True)
        return "utf-8-sig"
    except UnicodeDecodeError:
        pass
    sample = data[:65536]
    high = sum(sample.count(bytes([b])) for b in range(0xC0, 0x100))
    latin = sum(sample.count(bytes([b])) for b in range(0x41, 0x7B) if chr(b).isalpha())
    return "cp1251" if high > latin else "cp1252"


def _text_blocks(data: bytes) -> Iterator[tuple[str, int]]:
    """The file's text in blocks of whole lines, each with the bytes read up to its end: a large file is
    never held decoded whole (UTF-16, rare and made by a spreadsheet, is)."""
    if data.startswith(UTF16_BOMS):
        yield decode(data), len(data)
        return
    encoding = _encoding(data)
    at = 0
    if data.startswith(b"\xef\xbb\xbf") and encoding == "utf-8-sig":
        at, encoding = 3, "utf-8"
    while at < len(data):
        end = data.find(b"\n", at + TEXT_BLOCK)
        end = len(data) if end < 0 else end + 1
        yield data[at:end].decode(encoding, "replace"), end
        at = end


def _content_lines(lines: list[str]) -> list[int]:
    return [k for k, line in enumerate(lines) if line.strip() and not line.lstrip().startswith("#")]


def _split(line: str, sep: str) -> list[str]:
    """The fields of one line, RFC 4180 quoting understood (a quoted "3,85" is one field)."""
    if '"' not in line:
        return [part.strip() for part in line.split(sep)]
    try:
        fields = next(csv.reader([line], delimiter=sep))
    except (csv.Error, StopIteration):
        return [part.strip().strip('"').strip() for part in line.split(sep)]
    return [f.strip() for f in fields]


def _width(line: str, sep: str) -> int:
    return len(_split(line, sep))


def _is_number(text: str, comma: bool) -> bool:
    try:
        _number(text, comma)
    except ValueError:
        return False
    return True


def _number(text: str, comma: bool) -> float:
    text = text.strip()
    if comma:
        text = text.replace(".", "").replace(",", ".") if "," in text else text
    value = float(text)
    if value != value or value in (float("inf"), float("-inf")):
        raise ValueError(text)
    return value


def _separator(lines: list[str]) -> str:
    """The separator that splits the last probed lines into one field count of at least 2."""
    tail = lines[-PROBE_LINES:]
    fits = []
    for sep in SEPARATORS:
        counts = {_width(line, sep) for line in tail}
        if len(counts) == 1 and (n := counts.pop()) >= 2:
            fits.append((sum(_width(line, sep) == n for line in lines), sep))
    if fits:        # the one that also splits the header so: '|' over the ',' of decimal commas
        return max(fits, key=lambda f: (f[0], -SEPARATORS.index(f[1])))[1]
    best = max(SEPARATORS, key=lambda s: min(_width(line, s) for line in tail))
    if min(_width(line, best) for line in tail) < 2:
        raise LogFormatError(_("not a CSV: no separator (; tab , |) splits its lines into columns"))
    return best


def _unit_of(name: str) -> tuple[str, str]:
    """(name without its unit, unit) of ``Spannung [V]``, ``Current (mA)``, ``time_s``, ``mAH``."""
    name = name[:MAX_NAME]
    m = _UNIT.search(name)
    if m:
        unit = _UNIT_WORDS.get(m.group(1).strip().lower().split(",")[0].strip(), "")
        return _UNIT.sub("", name).strip(), unit
    low = name.lower()
    if low in _UNIT_WORDS:
        return name, _UNIT_WORDS[low]
    tail = re.search(r"[_ ]([a-z°]+)$", low)
    if tail and tail.group(1) in _UNIT_WORDS:
        return name[:tail.start()], _UNIT_WORDS[tail.group(1)]
    return name, ""


def _words(name: str) -> list[str]:
    return [w for w in re.split(r"[^a-zäöüßа-яё°0-9]+", name.lower()) if w]


def _fits(role: str, name: str, bare: str, unit: str) -> bool:
    """Whether a column may hold a role: no word of NOT[role] in its full name, a unit of the
    role if it has one (each unit but V belongs to one role; cell columns are taken before),
    else one of the role's words (or a longer word one of them starts)."""
    if any(n in name.lower() for n in NOT[role]):
        return False
    if unit:
        return unit in UNITS[role]
    words = _words(bare)
    return any(w in words for w in WORDS[role]) or any(x.startswith(w) for x in words for w in WORDS[role]
                                                       if len(w) > 3)


def guess(data: bytes) -> CsvGuess:
    """The separator, decimal comma, header line and each column's role and unit (of the first
    record set, where the file has ``### RECORDSET`` blocks)."""
    return _guess_lines(_head_lines(data))


def _head_lines(data: bytes) -> list[str]:
    """The lines of the file's first ``GUESS_BYTES`` (whole lines where there is a line end): the
    guess and the preview look at no more, so a large file costs them no more than a small one."""
    head = data[:GUESS_BYTES]
    if len(data) > GUESS_BYTES:
        end = max(head.rfind(b"\n"), head.rfind(b"\r"))
        if end > 0:
            head = head[:end + (2 if head.startswith(b"\xff\xfe") else 1)]    # UTF-16 LE: "\n\0"
    return decode(head).splitlines()


def _guess_lines(lines: list[str]) -> CsvGuess:
    content = _content_lines(lines)
    if len(content) < 2:
        raise LogFormatError(_("not a CSV: fewer than two lines"))
    probe = [lines[k] for k in content[:PROBE_LINES * 2]]
    sep = _separator(probe)
    width = _width(probe[-1], sep)
    header = next((k for k in content if _width(lines[k], sep) == width
                   and not all(_is_number(f, True) for f in _split(lines[k], sep) if f)), None)
    if header is None:
        raise LogFormatError(_("not a CSV with a header: no line names the columns"))
    names = _split(lines[header], sep)
    rows = [r for r in (_split(lines[k], sep) for k in content[:header + PROBE_LINES * 2] if k > header)
            if r != names][:PROBE_LINES]                 # a record set's header again is not a row
    names = names[:MAX_COLUMNS]
    comma = any(_DECIMAL_COMMA.match(f) for row in rows for f in row) and (
        sep != "," or any("," in f for row in rows for f in row))
    columns = _guess_columns(names, rows, comma)
    return CsvGuess(sep, comma, header, tuple(columns))


def _values(rows: list[list[str]], k: int, comma: bool) -> list[float]:
    out = []
    for row in rows:
        if k < len(row):
            try:
                out.append(_number(row[k], comma))
            except ValueError:
                pass
    return out


def _guess_columns(names: list[str], rows: list[list[str]], comma: bool) -> list[Column]:
    parsed = [_unit_of(n) for n in names]
    # A column may take a role when its probed fields are numbers (some may be empty: not measured then).
    numeric = [bool(_values(rows, k, comma)) or (bool(rows) and all(k < len(r) and not r[k] for r in rows))
               for k in range(len(names))]
    taken: dict[str, int] = {}
    cells: list[int] = []
    for k, (bare, unit) in enumerate(parsed):
        if numeric[k] and _CELL.search(bare) and unit in ("", "V", "mV"):
            cells.append(k)
    for role in ("time", "voltage", "current", "temp", "charge"):
        fits = [k for k, (bare, unit) in enumerate(parsed)
                if numeric[k] and k not in taken.values() and k not in cells and _fits(role, names[k], bare, unit)]
        preferred = [k for w in PREFER.get(role, ()) for k in fits if w in names[k].lower()]
        if fits:
            taken[role] = (preferred or fits)[0]
    if "time" not in taken and numeric and numeric[0] and 0 not in taken.values():
        taken["time"] = 0                          # an unnamed first column counts the time
    out = [Column(name) for name in names]
    for role, k in list(taken.items()) + [("cell", k) for k in cells]:
        unit, why = (parsed[k][1], "") if parsed[k][1] else _unit_by_size(role, _values(rows, k, comma))
        out[k] = Column(names[k], role, unit, why)
    return out


def _unit_by_size(role: str, values: list[float]) -> tuple[str, str]:
    """(unit, why) for a column whose name gives no unit: the reading that gives a plausible pack."""
    if not values:
        return UNITS[role][0], _("no unit in the header and no value: {unit} assumed").format(unit=UNITS[role][0])
    big = max(abs(v) for v in values)
    if role in PLAUSIBLE:
        small, large = ("V", "mV") if role in ("voltage", "cell") else ("A", "mA")
        unit = small if big <= PLAUSIBLE[role] else large
        return unit, _("no unit in the header: read as {unit} (largest value {big:g}; {small} up to {top:g}, "
                       "{large} beyond: no charger measures more)").format(
                unit=unit, big=big, small=small, large=large, top=PLAUSIBLE[role])
    if role == "time" and values[0] > 20000 and len(values) > 1 and 0 < values[1] - values[0] < 0.01:
        return "day", _("no unit in the header: read as days (a spreadsheet date, days since 1899)")
    return UNITS[role][0], _("no unit in the header: {unit} assumed").format(unit=UNITS[role][0])


def parse_columns(spec: str, names: tuple[str, ...]) -> tuple[Column, ...]:
    """``time:s,voltage:V,-,current:mA`` for the columns ``names`` in order; ValueError with the reason."""
    parts = [p.strip() for p in spec.split(",")]
    if len(parts) > len(names):
        raise ValueError(_("{given} columns given, the file has {n}").format(given=len(parts), n=len(names)))
    out = []
    for k, name in enumerate(names):
        part = parts[k] if k < len(parts) else "-"
        role, _sep, unit = part.partition(":")
        role = role.strip().lower()
        if role not in ROLES:
            raise ValueError(_("column {k}: '{role}' is not a role ({roles})").format(
                    k=k + 1, role=role, roles=", ".join(ROLES)))
        unit = unit.strip() or UNITS[role][0]
        if unit not in UNITS[role]:
            raise ValueError(_("column {k}: '{unit}' is not a unit of {role} ({units})").format(
                    k=k + 1, unit=unit, role=role, units=", ".join(UNITS[role])))
        out.append(Column(name, role, unit if role != "-" else ""))
    return tuple(out)


def check(g: CsvGuess) -> None:
    """A guess that can be read: one time and one voltage column, no other role twice."""
    roles = [c.role for c in g.columns if c.role not in ("-", "cell")]
    for role in ("time", "voltage"):
        if role not in roles:
            raise LogFormatError(_("no {role} column (give one with --columns, or in the CSV import dialog)").format(
                    role=_(role)))
    twice = sorted({r for r in roles if roles.count(r) > 1})
    if twice:
        raise LogFormatError(_("more than one {role} column").format(role=twice[0]))


@dataclass
class _Set:
    """One record set (a ``### RECORDSET`` block): its name, time stamps and first row."""
    name: str = ""
    start_ms: float = -1.0
    step_ms: float = -1.0
    first: int = 0


def _set_meta(line: str) -> dict[str, str]:
    """``# source=… recordset='1) Entladen' timestep_ms=1000.0 startTimeStamp_epoch_ms=…``."""
    return {m.group(1): m.group(2) if m.group(2) is not None else m.group(3) for m in _META.finditer(line)}


def _float_or(text: str | None, default: float) -> float:
    try:
        return float(text) if text is not None else default
    except ValueError:
        return default


def _median_step(times: np.ndarray) -> float:
    steps = np.diff(times)
    steps = steps[steps > 0]
    return float(np.sort(steps)[len(steps) // 2]) if len(steps) else 1.0


def _plain_row(line: str, sep: str, used: list[int], scale: list[float], comma: bool,
               width: int) -> list[float] | None:
    """A row's numbers the quick way (no quotes, every used field a plain finite number; a decimal comma
    where the line has no point), None where ``read`` must look closer (a header, a bad row, an empty
    temperature, quotes)."""
    if '"' in line or (comma and "." in line):
        return None
    if comma:
        line = line.replace(",", ".")
    fields = line.split(sep)
    if len(fields) < width:
        return None
    try:
        row = [float(fields[k]) * x for k, x in zip(used, scale)]
        return row if math.isfinite(math.fsum(row)) else None
    except (ValueError, OverflowError):
        return None


def read(data: bytes, g: CsvGuess | None = None, progress: Callable[[int, int], None] | None = None) -> Log:
    """The rows as the guess (or a corrected one) says. ``### RECORDSET`` blocks (DataExplorer-style
    exports, each restarting at time 0) are record sets, placed on one time line and given their
    direction as the ``.osd`` reader does (``record_sets``); so is each part of a file after its time
    goes back. No row is left out for its time. The rows go straight into one array (a row per line at
    most), read a block of lines at a time; ``progress(bytes read, bytes)`` is told after each block."""
    g = g or guess(data)
    check(g)
    at = {c.role: k for k, c in enumerate(g.columns) if c.role not in ("-", "cell")}
    cells = [k for k, c in enumerate(g.columns) if c.role == "cell"]
    used = sorted(set(at.values()) | set(cells))
    scale = [SCALE.get(g.columns[k].unit, 1.0) for k in used]
    names = [c.name for c in g.columns]
    optional = at.get("temp", -1)                   # an empty temperature: not measured then
    comma = g.decimal_comma
    values = np.empty((data.count(b"\n") + 1 if not data.startswith(UTF16_BOMS) else len(data) // 2 + 1,
                       len(used)))
    rows = 0
    pending: list[list[float]] = []
    sets = [_Set()]
    bad = 0
    header_due = False                              # a block's first line names its columns
    n = -1

    def store() -> None:
        nonlocal rows
        if pending:
            values[rows:rows + len(pending)] = pending
            rows += len(pending)
            pending.clear()

    for text, done in _text_blocks(data):
        for line in text.splitlines():
            n += 1
            stripped = line.strip()
            if stripped == RECORDSET:
                store()
                if rows > sets[-1].first or sets[-1].name:
                    sets.append(_Set(first=rows))
                header_due = n > g.header_line
                continue
            if not stripped:
                continue
            if stripped.startswith("#"):
                meta = _set_meta(stripped)
                if "recordset" in meta and rows + len(pending) == sets[-1].first:
                    sets[-1].name = meta["recordset"]
                    sets[-1].start_ms = _float_or(meta.get("startTimeStamp_epoch_ms"), -1.0)
                    sets[-1].step_ms = _float_or(meta.get("timestep_ms"), -1.0)
                continue
            if n <= g.header_line:
                continue
            if not header_due:
                row = _plain_row(line, g.separator, used, scale, comma, len(g.columns))
                if row is not None:
                    pending.append(row)
                    continue
            fields = _split(line, g.separator)
            if header_due or fields[:len(names)] == names:     # the next block's header
                header_due = False
                if not all(_is_number(f, comma) for f in fields if f):
                    continue
            if len(fields) < len(g.columns):
                bad += 1
                continue
            try:
                pending.append([math.nan if k == optional and not fields[k] else _number(fields[k], comma) * x
                                for k, x in zip(used, scale)])
            except ValueError:
                bad += 1
        store()
        if progress is not None:
            progress(done, len(data))
    builder = SampleBuilder()
    col = {k: j for j, k in enumerate(used)}
    cell_at = [col[k] for k in cells]
    # Cell columns side by side in the file are one view of the rows, not a copy.
    cell_view = (lambda lo, hi: values[lo:hi, cell_at[0]:cell_at[-1] + 1]) \
        if cell_at and cell_at == list(range(cell_at[0], cell_at[-1] + 1)) else \
        (lambda lo, hi: values[lo:hi, cell_at] if cell_at else None)
    temp_f = "temp" in at and g.columns[at["temp"]].unit == "°F"
    end_s = first_ms = None
    notes = []
    named = []
    bounds = [part.first for part in sets[1:]] + [rows]
    for part, hi in zip(sets, bounds):
        lo = part.first
        if hi <= lo:
            continue
        column = lambda role: values[lo:hi, col[at[role]]] if role in at else None
        times = column("time")                  # the rows' own array, worked in place: no copy
        times -= times[0]
        placed, note = in_time_order(times)
        if note is not None:
            notes.append(note)
            times = placed
        step = part.step_ms / 1000.0 if part.step_ms > 0 else _median_step(times)
        if first_ms is None and part.start_ms > 0:
            first_ms = part.start_ms
        offset = record_sets.offset_s(end_s, step, part.start_ms, first_ms)
        temp = column("temp")
        if temp is not None and temp_f:
            temp = (temp - 32.0) / 1.8
        end_s = float(times[-1]) + offset
        times += offset
        record_sets.add_set(builder, part.name, np.round(times, 6, out=times), column("voltage"),
                            column("current"), column("charge"), temp=temp, cells=cell_view(lo, hi))
        named.append(part.name)
    if not len(builder):
        raise LogFormatError(_("no data row ({bad} bad rows)").format(bad=bad))
    meta = {"csv_columns": g.spec(), "csv_key": g.key}
    if g.assumptions():
        meta["csv_assumed"] = g.assumptions()
    if any(named):
        meta["record_sets"] = named
    started = started_at_ms(first_ms) if first_ms is not None else None
    if started:
        meta["started"] = started
    if notes:
        first = dict(notes[0])
        first["record_sets"] = sum(n["record_sets"] - 1 for n in notes) + 1
        meta["time_order"] = first
    if "current" not in at:
        meta["current_measured"] = False
    return builder.build(FORMAT, _("CSV file"), bad, **meta)


def read_as(data: bytes, spec: str | None) -> Log:
    """Read with the guess, its columns replaced by ``spec`` (``parse_columns``) when given."""
    g = guess(data)
    if spec:
        try:
            g = g.with_columns(parse_columns(spec, tuple(c.name for c in g.columns)))
        except ValueError as exc:
            raise LogFormatError(str(exc)) from None
    return read(data, g)


def preview(data: bytes, g: CsvGuess, rows: int = 3) -> list[list[str]]:
    """The first data rows' fields as the file has them."""
    lines = _head_lines(data)[g.header_line + 1:]
    return [_split(line, g.separator) for line in lines if line.strip() and not line.lstrip().startswith("#")][:rows]


def sniff(head: bytes, name: str) -> bool:
    """A text whose guess finds a time and a voltage column (last in the detection order); not
the fit's plain curve CSV, which ``sim.curve`` reads as it is. A header longer than the bytes
looked at (a single line with a separator and no end) is left to the reader to judge."""
    if head.lstrip(b"\xef\xbb\xbf").startswith(CURVE_CSV):
        return False
    if b"\x00" in head and not head.startswith(UTF16_BOMS):
        return False
    text = decode(head)
    lines = text.splitlines()
    if len(lines) <= 1 and len(head) >= LONG_LINE:
        return any(sep in text for sep in SEPARATORS)
    if len(lines) > 1 and not text.endswith(("\n", "\r")):
        lines = lines[:-1]                       # the head cuts the last line
    try:
        check(_guess_lines(lines))
    except LogFormatError:
        return False
    return True
