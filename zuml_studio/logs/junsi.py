"""Junsi iCharger DUO/X/S text logs written to SD card or PC (``../shared/realdata/
icharger_logview.md``), with their header, battery type and internal-resistance records. The records are decoded by the live driver, ``streams/icharger_logview.py`` (which
also reads the older serial models' lines in raw captures and ``.lov`` files): what it counts
as bad (checksum, a field that is not an integer or out of its range, a field count that fits
no layout, garbage) is the log's ``bad_records``."""
from __future__ import annotations

from dataclasses import replace

from ..streams.icharger_logview import IChargerLineDecoder
from ..streams.stream_decoder import Reading, integers
from .model import Log, LogFormatError, from_samples
from ..i18n import _

SNIFF_LINES = 8
IR_STATE = 128                 # LOG_EX_IR: internal resistance, 0.1 mΩ
DUO_BATTERY = ("?", "LiPo", "LiIo", "LiFe", "NiMH", "NiCd", "Pb", "NiZn", "LiHV")
X_BATTERY = ("?", "LiPo", "LiIo", "LiFe", "LiHV", "LTO", "NiMH", "NiCd", "NiZn", "Pb", "Power", "User")


def parse_header(data: bytes) -> dict[str, str]:
    """``@Model:X6; Fireware:V2.0.6; ...`` -> {"Model": "X6", ...} (empty without the line)."""
    if not data.startswith(b"@"):
        return {}
    line = data[1:data.find(b"\n") if b"\n" in data else len(data)]
    out = {}
    for part in line.replace(b"\0", b"").decode("latin-1").split(";"):
        key, sep, value = part.partition(":")
        if sep and key.strip():
            out[key.strip()] = value.strip()
    return out


def sniff_duo(head: bytes, name: str) -> bool:
    if head.startswith(b"@Model:"):
        return True
    # One of the first records (a torn first line is no reason to refuse the file) in the DUO/X
    # layout: a time in field 2, where the older serial lines leave it empty.
    for line in head.split(b"\n")[:SNIFF_LINES]:
        line = line.strip()
        if line.count(b";") > 3 and line.split(b";")[2] and IChargerLineDecoder().feed(line + b"\n"):
            return True
    return False


class _DuoLogDecoder(IChargerLineDecoder):
    """The live driver's decoder (one decoder of these records), keeping what a log file has
    beyond the samples: internal-resistance records, the battery type, the other channel."""

    def __init__(self) -> None:
        super().__init__()
        self.resistance: list[tuple[float, float | None, tuple[float, ...]]] = []
        self.kind: int | None = None
        self.other_channel = 0

    def record(self, fields: list[str]) -> Reading | None:
        reading = super().record(fields)          # raises ValueError for a record to count as bad
        if fields[0] != self.channel:
            self.other_channel += 1
        elif fields[2] and int(fields[1]) == IR_STATE:
            values = integers(fields[3:])
            if values:
                self.resistance.append(_resistance(int(fields[2]) / 1000.0, values))
        elif reading is not None and fields[2] and self.kind is None:
            self.kind = int(fields[3])
        return reading


def read_duo(data: bytes) -> Log:
    header = parse_header(data)
    model = header.get("Model", "")
    battery_names = X_BATTERY if model[:1] in ("X", "S") or model[:2] == "DX" else DUO_BATTERY
    decoder = _DuoLogDecoder()
    samples = decoder.feed(data if data.endswith(b"\n") else data + b"\n")
    if not samples:
        raise LogFormatError(_("no iCharger DUO/X record read ({good} records, {bad} bad)").format(
                good=decoder.good + decoder.bad + decoder.skipped, bad=decoder.bad))
    device = f"Junsi iCharger {model}".strip() if model else "Junsi iCharger (DUO/X log)"
    meta: dict = {"channel": int(decoder.channel)} if decoder.channel else {}
    if header:
        meta["header"] = header
    if decoder.kind is not None and 0 <= decoder.kind < len(battery_names):
        meta["battery"] = battery_names[decoder.kind]
    if decoder.other_channel:
        meta["other_channel_records"] = decoder.other_channel
    log = from_samples("icharger-duo-txt", device, samples, decoder.bad, **meta)
    # IR records list every cell slot; keep those the voltage records show connected.
    width = log.cells
    return replace(log, resistance=tuple((t, pack, cells[:width]) for t, pack, cells in decoder.resistance))


def _resistance(t: float, values: list[int]) -> tuple[float, float | None, tuple[float, ...]]:
    """An IR record, in mΩ. Firmware 2.0.8+/2.19 gives pack and Σcells before the cells; 2.0.6
    gives Σcells then the cells (6 of them): when the first value is the sum of the rest, there
    is no pack value."""
    tenths = [v / 10.0 for v in values]
    if len(values) >= 2 and values[0] == sum(values[1:]):
        return t, None, tuple(tenths[1:])
    if len(values) >= 3:
        return t, tenths[0], tuple(tenths[2:])
    return t, tenths[0], ()
