"""DataExplorer ``.osd`` files (``docs/formats/dataexplorer.md``).

A Java ``DataOutputStream`` (big-endian), optionally inside a one-entry ZIP: header lines
written with ``writeUTF`` up to ``NumberRecordSets : N``, then N record-set descriptors
(``writeUTF`` up to version 3, ``int32 length`` + UTF-8 from version 4) whose fields are
separated by ``||::||``, then each set's data at its ``RecordSetDataPointer``: time stamps
(int32, 0.1 ms) when ``timeStep_ms`` ≤ 0, then ``RecordDataSize`` points of one int32 per
stored record, point-major. Value = (raw/1000 − reduction)·factor + offset.

Which records are stored is device specific (calculated ones are left out); the count
follows from the block's size and each stored column is matched, in order, to the record
whose ``_minValue``/``_maxValue`` it has. Where each set lies on the time line and which way it
goes: ``record_sets.py`` (one rule with the CSV exports)."""
from __future__ import annotations

import io
import re
import struct
import zipfile
import zlib

import numpy as np

from . import record_sets
from .model import Log, LogFormatError, SampleBuilder, started_at_ms
from ..i18n import _

MAX_UNZIPPED = 512 * 1024 * 1024
MAX_SETS = 10000
MAGICS = (b"DataExplorer version", b"OpenSerialData version")
_SET_SEP = "||::||"
_REC_SEP = "|:-:|"
_PROP_SEP = "|-|"
_VERSION = re.compile(r"version : (\d+)")
_CELL = re.compile(r"(?:zellenspannung|cellvoltage|cell voltage|zelle|cell)\s*(\d{1,2})$", re.IGNORECASE)
_NOT_PACK = ("versorgung", "eingang", "input", "supply", "zelle", "cell", "balance", "bec")


def sniff(head: bytes, name: str) -> bool:
    if head.startswith(b"PK\x03\x04"):
        return name.lower().endswith(".osd") or b".osd" in head[30:30 + 300]
    return any(m in head[2:40] for m in MAGICS)


def _unzip(data: bytes) -> bytes:
    try:
        with zipfile.ZipFile(io.BytesIO(data)) as z:
            infos = z.infolist()
            if not infos:
                raise LogFormatError(_("an empty ZIP archive"))
            info = infos[0]
            if info.file_size > MAX_UNZIPPED:
                raise LogFormatError(_("the .osd inside the ZIP is {file_size} bytes; at most {max_unzipped}").format(
                        file_size=info.file_size, max_unzipped=MAX_UNZIPPED))
            with z.open(info) as fh:
                out = fh.read(MAX_UNZIPPED + 1)
    except (zipfile.BadZipFile, zipfile.LargeZipFile, zlib.error, EOFError, NotImplementedError, RuntimeError,
            ValueError, OSError) as exc:
        raise LogFormatError(_("a damaged ZIP around the .osd: {exc}").format(exc=exc)) from None
    if len(out) > MAX_UNZIPPED:
        raise LogFormatError(_("the .osd inside the ZIP is larger than {max_unzipped} bytes").format(
                max_unzipped=MAX_UNZIPPED))
    return out


class _Stream:
    def __init__(self, data: bytes) -> None:
        self.data = data
        self.pos = 0

    def utf(self) -> str:
        if self.pos + 2 > len(self.data):
            raise LogFormatError(_("the header ends early (offset {pos})").format(pos=self.pos))
        (n,) = struct.unpack_from(">H", self.data, self.pos)
        return self._text(self.pos + 2, n)

    def int_text(self) -> str:
        if self.pos + 4 > len(self.data):
            raise LogFormatError(_("the header ends early (offset {pos})").format(pos=self.pos))
        (n,) = struct.unpack_from(">i", self.data, self.pos)
        if n < 0:
            raise LogFormatError(_("a negative string length at offset {pos}").format(pos=self.pos))
        return self._text(self.pos + 4, n)

    def _text(self, start: int, n: int) -> str:
        end = start + n
        if end > len(self.data):
            raise LogFormatError(_("a header string runs past the end of the file (offset {pos})").format(pos=self.pos))
        self.pos = end
        return self.data[start:end].decode("utf-8", errors="replace")


def _props(text: str) -> dict[str, str]:
    out = {}
    for item in text.split(_PROP_SEP):
        key, sep, value = item.partition("=")
        if sep:
            out[key.strip()] = value.strip()
    return out


def _float(props: dict, key: str, default: float) -> float:
    try:
        value = float(props.get(key, default))
    except ValueError:
        return default
    return value if np.isfinite(value) else default


def _int(text: str, what: str) -> int:
    text = text.strip()
    if not text.isdigit() or len(text) > 10:
        raise LogFormatError(_("{what} is not a number: {text!r}").format(what=what, text=text[:20]))
    return int(text)


def _descriptor(text: str) -> dict:
    fields: dict = {"records": []}
    for part in text.split(_SET_SEP):
        key, sep, value = part.partition(" : ")
        key = key.strip()
        if not sep:
            key, sep, value = part.partition(":")
            key = key.strip()
        if key == "RecordProperties":
            for rec in (key + " : " + value).split(_REC_SEP):
                fields["records"].append(_props(rec.partition(" : ")[2]))
        else:
            fields[key] = value
    return fields


def read(data: bytes) -> Log:
    if data.startswith(b"PK\x03\x04"):
        data = _unzip(data)
    s = _Stream(data)
    header: dict[str, str] = {}
    first = s.utf()
    if not first.startswith(("DataExplorer version", "OpenSerialData version")):
        raise LogFormatError(_("not a DataExplorer file: no 'DataExplorer version' line"))
    m = _VERSION.search(first)
    version = int(m.group(1)) if m else 0
    header["version"] = str(version)
    while True:
        line = s.utf().strip()
        key, __, value = line.partition(" : ")
        header[key.strip()] = value.strip()
        if key.strip() == "NumberRecordSets":
            break
        if len(header) > 64:
            raise LogFormatError(_("no 'NumberRecordSets' line in the header"))
    count = _int(header["NumberRecordSets"], "NumberRecordSets")
    if not 0 < count <= MAX_SETS:
        raise LogFormatError(_("NumberRecordSets is {count}").format(count=count))
    sets = [_descriptor(s.int_text() if version >= 4 else s.utf()) for __ in range(count)]
    for d in sets:
        d["size"] = _int(d.get("RecordDataSize", ""), "RecordDataSize")
        d["pointer"] = _int(d.get("RecordSetDataPointer", ""), "RecordSetDataPointer")
    bounds = sorted({d["pointer"] for d in sets} | {len(data)})
    builder = SampleBuilder()
    end_s = None
    start0 = None
    names = []
    for d in sets:
        props = _props(d.get("RecordSetProperties", ""))
        step_ms = _float(props, "timeStep_ms", -1.0)
        start_ms = _float(props, "startTimeStamp", -1.0)
        name = d.get("RecordSetName", "").strip()
        names.append(name)
        t, columns = _set_data(data, d, bounds, step_ms, name)
        if not len(t):
            continue
        if start_ms > 0 and start0 is None:
            start0 = start_ms
        offset = record_sets.offset_s(end_s, step_ms / 1000.0 if step_ms > 0 else 1.0, start_ms, start0)
        _add_set(builder, d["records"], columns, t + offset, name)
        end_s = float(t[-1] + offset)
    if not len(builder):
        raise LogFormatError(_("no data points in any record set"))
    device = header.get("DeviceName", "") or "DataExplorer"
    meta = {"record_sets": names, "comment": header.get("FileComment", "")}
    started = started_at_ms(start0) if start0 is not None else None
    if started:
        meta["started"] = started              # the first record set's time stamp
    return builder.build("dataexplorer-osd", device, 0, **meta)


def _set_data(data: bytes, d: dict, bounds: list[int], step_ms: float, name: str):
    n, pointer = d["size"], d["pointer"]
    if pointer > len(data):
        raise LogFormatError(_("record set '{name}': data pointer {pointer} past the end ({n_data} bytes)").format(
                name=name, pointer=pointer, n_data=len(data)))
    if n == 0:
        return np.zeros(0), np.zeros((0, 0))
    block_end = next(b for b in bounds if b > pointer) if pointer < len(data) else pointer
    block = block_end - pointer
    stamps = 4 * n if step_ms <= 0 else 0
    if block < stamps or (block - stamps) % (4 * n):
        raise LogFormatError(_("record set '{name}': {block} data bytes do not hold {n} points").format(
                name=name, block=block, n=n))
    k = (block - stamps) // (4 * n)
    if k == 0 or k > len(d["records"]):
        raise LogFormatError(_("record set '{name}': {k} stored values per point for {n_d} records").format(
                name=name, k=k, n_d=len(d['records'])))
    raw = np.frombuffer(data, dtype=">i4", count=stamps // 4 + n * k, offset=pointer)
    if stamps:
        t = raw[:n].astype(float) / 10000.0
        t -= t[0]
    else:
        t = np.arange(n, dtype=float) * step_ms / 1000.0
    columns = raw[stamps // 4:].reshape(n, k)
    return t, columns


def _match(records: list[dict], columns: np.ndarray, name: str) -> list[int]:
    """Index of the record each stored column holds: in order, the next record whose stored
    min/max are the column's (as long as enough records are left for the other columns)."""
    k = columns.shape[1]
    lo, hi = columns.min(axis=0), columns.max(axis=0)
    out = []
    r = 0
    for c in range(k):
        while r < len(records):
            left = len(records) - r
            rec = records[r]
            same = rec.get("_minValue") == str(lo[c]) and rec.get("_maxValue") == str(hi[c])
            if same or left == k - c:
                out.append(r)
                r += 1
                break
            r += 1
        else:
            raise LogFormatError(_("record set '{name}': stored column {c} matches no record").format(
                    name=name, c=c + 1))
    return out


def _add_set(builder: SampleBuilder, records: list[dict], columns: np.ndarray, t: np.ndarray, name: str) -> None:
    which = _match(records, columns, name)
    values = {}
    for c, r in enumerate(which):
        rec = records[r]
        factor, offset, reduction = (_float(rec, "factor_DOUBLE", 1.0), _float(rec, "offset_DOUBLE", 0.0),
                                     _float(rec, "reduction_DOUBLE", 0.0))
        values[r] = (columns[:, c] / 1000.0 - reduction) * factor + offset

    def find(units: tuple[str, ...], want=(), avoid=()) -> np.ndarray | None:
        for r in values:
            nm, unit = records[r].get("_name", "").strip().lower(), records[r].get("_unit", "")
            if nm.endswith("ri"):           # internal resistance ("BatteríeRi"), whatever its unit says
                continue
            if unit in units and all(w in nm for w in want) and not any(a in nm for a in avoid):
                return values[r]
        return None

    volts = find(("V",), avoid=_NOT_PACK)
    if volts is None:
        raise LogFormatError(_("record set '{name}': no pack voltage record (unit V)").format(name=name))
    amps = find(("A",))
    mah = find(("mAh",))
    temp = find(("°C",), ("temp",), ("int",))
    heatsink = find(("°C",), ("temp", "int"))
    cells = sorted((int(m.group(1)), r) for r in values
                   if records[r].get("_unit") == "V" and (m := _CELL.search(records[r].get("_name", "").strip())))
    record_sets.add_set(builder, name, t, volts, amps, mah, temp=temp, heatsink=heatsink,
                        cells=[values[r] for __, r in cells])
