"""LogView ``.lov`` files (``LogView-Stream:V5``), as far as ``dataexplorer.md`` describes them.

The header is u32-length-prefixed strings, then the LogView device .ini (``Name=…``), chart
settings, then the records, each holding the raw bytes the charger sent. LogView itself is
closed and no layout of the records is published, so records are found as the notes do and
their bytes go to the live driver of the charger the .ini names (``streams/drivers.py``):

* text devices (Junsi iCharger serial models, cheali-charger): ``u32 length`` then
  ``<spaces><seconds>;<raw line>\\r\\n`` (the length counts up to 16 bytes more than the
  text: seen are 8, what they hold is not known); the seconds are the sample's time.
* iMAX B6 / e-Station: the 76-byte ``{…}`` frame then a Delphi TDateTime (days, comma
  decimal) that gives the sample's time.
* Ultramat / Ultra Duo Plus: the ``0x0C … 0x0D`` frame alone; the driver's 1 s step gives the time.

A record whose length prefix does not fit is counted as bad, as is every record the driver
refuses (checksum, shape)."""
from __future__ import annotations

import datetime as dt
import re
from dataclasses import replace

from ..streams.drivers import DRIVERS
from ..protocol.messages import Telemetry
from .model import Log, LogFormatError, from_samples
from ..i18n import _

_DATE = re.compile(r"(?:(?P<d1>\d\d)\.(?P<m1>\d\d)\.(?P<y1>\d{4})|(?P<y2>\d{4})-(?P<m2>\d\d)-(?P<d2>\d\d)), "
                   r"(?P<H>\d\d):(?P<M>\d\d):(?P<S>\d\d)")

MAGIC = b"LogView-Stream:"
SLACK = 16
SECONDS_PER_DAY = 86400.0
_NAME = re.compile(rb"Name=([^\x00-\x1f]{1,80})")
_TEXT_RECORD = re.compile(rb"([\x20-\x7f]{0,12}?)(\d{1,9});(\$[\x20-\x7e]{1,400}?)\r\n")
_FRAME_RECORD = re.compile(rb"(\{.{74}\})(\d{1,6},\d{1,12})", re.S)
_ULTRAMAT_RECORD = re.compile(rb"\x0c[0-9A-Fa-f]{8,200}\r")
# words of the .ini's device name -> the driver that reads its records
DEVICE_DRIVERS = (("icharger", "icharger"), ("junsi", "icharger"), ("cheali", "cheali"), ("imax", "imaxb6"),
                  ("e-station", "imaxb6"), ("estation", "imaxb6"), ("ultramat", "ultramat"),
                  ("ultra duo", "ultramat"), ("ultraduo", "ultramat"))


def sniff(head: bytes, name: str) -> bool:
    return MAGIC in head[:64]


def device_name(data: bytes) -> str:
    """The ``Name=`` of the embedded device .ini, cut to the length its u32 prefix gives."""
    for m in _NAME.finditer(data):
        start = m.start()
        if start >= 4:
            length = int.from_bytes(data[start - 4:start], "little")
            if 5 < length <= 85:
                return data[start + 5:start + length].decode("latin-1").strip()
    return ""


def driver_for(device: str) -> str | None:
    low = device.lower()
    return next((drv for word, drv in DEVICE_DRIVERS if word in low), None)


def _prefix(data: bytes, start: int) -> int:
    return int.from_bytes(data[start - 4:start], "little") if start >= 4 else -1


def text_records(data: bytes) -> tuple[list[tuple[float | None, bytes]], int]:
    """(seconds, raw line) of every text record whose u32 length prefix matches, and the
    count of '$' records found without a matching prefix (torn ones)."""
    out: list[tuple[float | None, bytes]] = []
    torn = 0
    for m in _TEXT_RECORD.finditer(data):
        size = m.end() - m.start()
        if size <= _prefix(data, m.start()) <= size + SLACK and not m.group(1).strip():
            out.append((float(int(m.group(2))), m.group(3) + b"\r\n"))
        else:
            torn += 1
    return out, torn


def frame_records(data: bytes) -> tuple[list[tuple[float | None, bytes]], int]:
    """(seconds since 30 Dec 1899, frame) of every iMAX B6 record."""
    out: list[tuple[float | None, bytes]] = []
    for m in _FRAME_RECORD.finditer(data):
        out.append((float(m.group(2).replace(b",", b".")) * SECONDS_PER_DAY, m.group(1)))
    return out, 0


def ultramat_records(data: bytes) -> tuple[list[tuple[float | None, bytes]], int]:
    return [(None, m.group(0)) for m in _ULTRAMAT_RECORD.finditer(data)], 0


RECORDS = {"icharger": text_records, "cheali": text_records, "imaxb6": frame_records, "ultramat": ultramat_records}


def charger_stream(data: bytes) -> bytes:
    """The bytes the charger sent, as LogView kept them: the records of the driver the .ini names,
    one after the other (for a replay); LogFormatError when the file names no charger a driver reads."""
    if MAGIC not in data[:64]:
        raise LogFormatError(_("not a LogView file: no 'LogView-Stream:' header"))
    name = driver_for(device_name(data))
    if name is None:
        raise LogFormatError(_("LogView file from '{device}': .lov records are read for {readers}; export it "
                               "from LogView as text").format(device=device_name(data),
                                                               readers=", ".join(DRIVERS[d].title for d in RECORDS)))
    return b"".join(raw for _seconds, raw in RECORDS[name](data)[0])


def read(data: bytes) -> Log:
    if MAGIC not in data[:64]:
        raise LogFormatError(_("not a LogView file: no 'LogView-Stream:' header"))
    device = device_name(data)
    if not device:
        raise LogFormatError(_("LogView file without a device .ini (no 'Name=' entry)"))
    name = driver_for(device)
    if name is None:
        readers = ", ".join(DRIVERS[d].title for d in RECORDS)
        raise LogFormatError(_("LogView file from '{device}': .lov records are read for {readers}; export it "
                               "from LogView as text").format(device=device, readers=readers))
    records, bad = RECORDS[name](data)
    decoder = DRIVERS[name].decoder()
    samples: list[Telemetry] = []
    t0 = None
    for seconds, raw in records:
        for sample in decoder.feed(raw):
            if seconds is not None:
                t0 = seconds if t0 is None else t0
                sample = replace(sample, time_s=round(seconds - t0, 3))
            samples.append(sample)
    bad += decoder.bad
    if not samples and decoder.skipped:
        # Frames that pass their checksum but hold no sample: say so, not "no record read".
        raise LogFormatError(_("LogView file from '{device}': its {n_records} records are {name} frames whose "
                               "field layout is not known").format(device=device, name=name,
                                                                    n_records=decoder.skipped))
    if not samples:
        raise LogFormatError(_("LogView file from '{device}': no {name} record read ({n_records} records, {bad} "
                               "bad)").format(device=device, name=name, n_records=len(records), bad=bad))
    meta = {"driver": name}
    started = _started(data)
    if started:
        meta["started"] = started
    return from_samples("logview-lov", device, samples, bad, **meta)


def _started(data: bytes) -> str | None:
    """The first date-time in the header ("22.05.2011, 08:54:07" or "2011-04-21, 21:45:32": LogView's
    local time when the recording began), as an ISO date-time without a zone."""
    head = data[:512].decode("latin-1")
    m = _DATE.search(head)
    if not m:
        return None
    day, month, year = (m["d1"], m["m1"], m["y1"]) if m["d1"] else (m["d2"], m["m2"], m["y2"])
    try:
        return dt.datetime(int(year), int(month), int(day), int(m["H"]), int(m["M"]), int(m["S"])).isoformat()
    except ValueError:
        return None
