"""Junsi iCharger DUO/X/S text logs written to SD card or PC (``../shared/realdata/
icharger_logview.md``), with their header, battery type, cycle and internal-resistance
records. The older serial models' lines (in raw captures and ``.lov`` files) are read by the
live driver, ``device/icharger_logview.py``.

Every record is ``$<ch>;<fields>;<checksum>`` with the checksum the XOR of every byte from
``$`` through the last ``;``, in decimal. A record with a bad checksum, a field that is not
an integer or a field count that fits no layout is counted as bad and skipped."""
from __future__ import annotations

from dataclasses import replace

from ..device.stream_decoder import xor8
from .model import Log, LogFormatError, SampleBuilder, state_from_current

MAX_LINE = 400                 # longer than any real record (12 cells, 20 fields of 6 digits)
SNIFF_LINES = 8
IR_STATE = 128                 # LOG_EX_IR: internal resistance, 0.1 mΩ
# DUO/X log states onto ours; a state not listed (0 "normal") follows the current's sign.
DUO_STATES = {1: "charge", 2: "discharge", 3: "idle", 4: "pause", 5: "charge", 6: "idle", 7: "idle",
              8: "charge", 9: "charge", 10: "discharge", 11: "idle", 12: "discharge", 30: "idle"}
DUO_BATTERY = ("?", "LiPo", "LiIo", "LiFe", "NiMH", "NiCd", "Pb", "NiZn", "LiHV")
X_BATTERY = ("?", "LiPo", "LiIo", "LiFe", "LiHV", "LTO", "NiMH", "NiCd", "NiZn", "Pb", "Power", "User")
DUO_CELLS = (6, 8, 10, 12)


def checksum_ok(line: bytes) -> bool:
    body, sep, ck = line.rpartition(b";")
    if not sep or not ck.isdigit() or len(ck) > 3:
        return False
    return xor8(body + b";") == int(ck)


def split_record(line: bytes) -> list[bytes] | None:
    """The fields between ``$<ch>`` and the checksum, or None for a record to count as bad."""
    line = line.strip()
    if len(line) > MAX_LINE or not line.startswith(b"$") or not checksum_ok(line):
        return None
    return line.split(b";")[:-1]


def _ints(fields: list[bytes]) -> list[int] | None:
    out = []
    for f in fields:
        text = f[1:] if f[:1] == b"-" else f
        if not text.isdigit() or len(text) > 9:
            return None
        out.append(int(f))
    return out


# -- DUO / X / S text logs ------------------------------------------------------------------
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
        fields = split_record(line)
        if fields and len(fields) >= 3 and fields[2] != b"" and _ints(fields[1:]) is not None:
            return True
    return False


def read_duo(data: bytes) -> Log:
    header = parse_header(data)
    model = header.get("Model", "")
    battery_names = X_BATTERY if model[:1] in ("X", "S") or model[:2] == "DX" else DUO_BATTERY
    builder = SampleBuilder()
    resistance = []
    bad = 0
    channel = None
    other_channels = 0
    battery = None
    records = 0
    for raw in data.split(b"\n"):
        raw = raw.strip()
        if not raw.startswith(b"$"):
            if raw and not raw.startswith(b"@") and raw.strip(b"\0"):
                bad += 1
            continue
        records += 1
        fields = split_record(raw)
        values = _ints(fields[1:]) if fields else None
        ch = fields[0][1:] if fields else b""
        if values is None or not ch.isdigit() or len(values) < 3:
            bad += 1
            continue
        if channel is None:
            channel = ch
        elif ch != channel:
            other_channels += 1
            continue
        state, ms = values[0], values[1]
        if state == IR_STATE:
            if len(values) < 3:
                bad += 1
                continue
            resistance.append(_resistance(ms / 1000.0, values[2:]))
            continue
        if state > IR_STATE:                # 130 "cell capacity" and other special records
            continue
        cells = len(values) - 10
        if cells not in DUO_CELLS:
            bad += 1
            continue
        (_, _, kind, cycle, current, _vin, vbat, capacity, t_int, t_ext), cell_mv = values[:10], values[10:]
        if battery is None and 0 <= kind < len(battery_names):
            battery = battery_names[kind]
        amps = current / 100.0
        builder.add(ms / 1000.0, vbat / 1000.0, amps, DUO_STATES.get(state) or state_from_current(amps),
                    temp=t_ext / 10.0, heatsink=t_int / 10.0, cells=[mv / 1000.0 for mv in cell_mv],
                    counter=float(capacity), cycle=cycle)
    if not len(builder):
        raise LogFormatError(f"no iCharger DUO/X record read ({records} '$' records, {bad} bad)")
    _drop_absent_sensor(builder)
    device = f"Junsi iCharger {model}".strip() if model else "Junsi iCharger (DUO/X log)"
    meta = {"channel": int(channel)} if channel else {}
    if header:
        meta["header"] = header
    if battery:
        meta["battery"] = battery
    if other_channels:
        meta["other_channel_records"] = other_channels
    log = builder.build("icharger-duo-txt", device, bad, **meta)
    # IR records list every cell slot; keep those the voltage records show connected.
    width = log.cells
    return replace(log, resistance=tuple((t, pack, cells[:width]) for t, pack, cells in resistance))


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


def _drop_absent_sensor(builder: SampleBuilder) -> None:
    """An external temperature of exactly 0.0 in every sample: no probe plugged in."""
    if builder.temp and all(t == 0.0 for t in builder.temp):
        builder.temp[:] = [None] * len(builder.temp)
