"""LogView ``.lov`` files (``LogView-Stream:V5``), as far as ``dataexplorer.md`` describes them.

The header is u32-length-prefixed strings, then the LogView device .ini (``Name=…``), chart
settings, then the records. LogView itself is closed and no layout of the records is
published, so records are found as the notes do: a text record is ``u32 length`` followed by
``<spaces><seconds>;<raw device line>\\r\\n`` (the length counts up to 16 bytes more than
the text: seen are 8, what they hold is not known). Text records of the Junsi
serial models are decoded here; other devices' records (binary iMAX B6 frames, Ultramat
frames) are refused with the device's name."""
from __future__ import annotations

import re

from . import junsi
from .model import Log, LogFormatError, SampleBuilder

MAGIC = b"LogView-Stream:"
SLACK = 16
_NAME = re.compile(rb"Name=([^\x00-\x1f]{1,80})")
_TEXT_RECORD = re.compile(rb"([\x20-\x7f]{0,12}?)(\d{1,9});(\$[\x20-\x7e]{1,400}?)\r\n")


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


def text_records(data: bytes) -> tuple[list[tuple[float, bytes]], int]:
    """(seconds, raw line) of every text record whose u32 length prefix matches, and the
    count of '$' records found without a matching prefix (torn ones)."""
    out = []
    torn = 0
    for m in _TEXT_RECORD.finditer(data):
        start, end = m.start(), m.end()
        prefix = data[start - 4:start] if start >= 4 else b""
        length = int.from_bytes(prefix, "little") if len(prefix) == 4 else -1
        if end - start <= length <= end - start + SLACK and not m.group(1).strip():
            out.append((float(int(m.group(2))), m.group(3)))
        else:
            torn += 1
    return out, torn


def read(data: bytes) -> Log:
    if MAGIC not in data[:64]:
        raise LogFormatError("not a LogView file: no 'LogView-Stream:' header")
    device = device_name(data)
    if not device:
        raise LogFormatError("LogView file without a device .ini (no 'Name=' entry)")
    if not device.lower().startswith("junsi"):
        raise LogFormatError(f"LogView file from '{device}': only the text records of Junsi iCharger serial "
                             f"models are read from .lov files; export it from LogView as text, or replay it")
    records, bad = text_records(data)
    builder = SampleBuilder()
    channel = None
    for seconds, line in records:
        decoded = junsi.serial_values(line)
        if decoded is None:
            bad += 1
            continue
        ch, values = decoded
        channel = ch if channel is None else channel
        if ch != channel:
            continue
        junsi.add_serial(builder, seconds, values)
    if not len(builder):
        raise LogFormatError(f"LogView file from '{device}': no iCharger record read ({bad} bad)")
    junsi.finish_serial(builder)
    return builder.build("logview-lov", device, bad, channel=channel)
