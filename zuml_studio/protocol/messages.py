"""Payload layouts of every message type, in one table (docs/protocol.md).

Requests go host -> device with types 0x01..0x3F; the answer has the same SEQ and the
type | 0x80, or is an ERROR frame (0x7F). The device sends TELEMETRY and EVENT frames on
its own (types 0x40..0x4F, SEQ counts them modulo 256). All integers little-endian.

``encode(kind, **fields) -> bytes`` and ``decode(kind, payload) -> dict`` work from the
table; a payload that does not fit its layout raises ``PayloadError`` (the device answers
BAD_REQUEST, the client treats the frame as garbage).
"""
from __future__ import annotations

import enum
import struct
from dataclasses import dataclass
from ..errors import ZumlError
from ..domain.tasks import TASKS
from ..i18n import _, ngettext

PROTOCOL_VERSION = 1
RESPONSE_FLAG = 0x80
MAX_DATA = 240                # EEPROM bytes per READ_EEPROM / WRITE_STAGE
NO_SLOT = 0xFF
NO_OFFSET = 0xFFFF
TEMP_UNKNOWN = 0x7FFF         # i16 0.01 °C: no sensor
STATES = ("idle", "running", "paused", "finished")
EVENT_KINDS = ("section", "phase_start", "phase_end", "pause", "resume", "music", "light", "finish")
SECTIONS = ("discharge", "charge")
SECTION_NONE = 0xFF


class PayloadError(ZumlError, ValueError):
    pass


class ErrorCode(enum.IntEnum):
    BAD_FRAME = 1          # a frame with a bad CRC arrived (sent with request type 0, SEQ 0)
    BAD_REQUEST = 2        # payload does not fit the request's layout
    UNKNOWN_TYPE = 3
    BAD_RANGE = 4          # offset/length outside the EEPROM, rate outside 1..50, ...
    BAD_TOKEN = 5          # no write transaction with this token
    CRC_MISMATCH = 6       # COMMIT: the staged image's CRC is not the one the host computed
    BAD_SLOT = 7
    INVALID_RECORD = 8
    PASSPORT_CONFLICT = 9
    START_ERROR = 10
    NO_PASSPORT = 11
    PASSPORT_ERROR = 12
    INTERNAL = 13
    NO_TEMPLATE = 14       # GET_TEMPLATE: no start template with this number
    BUSY = 15              # an EEPROM write or CAL_OUTPUT while a macro runs (the B6 firmware)
    UNCALIBRATED = 16      # START: the charger holds no valid calibration
    PROTECTION = 17        # START or CAL_OUTPUT: a protection forbids it


@dataclass(frozen=True)
class Field:
    name: str
    fmt: str               # struct code; "s*" = the rest as bytes; "u*" = the rest as UTF-8; "p" = u8-length UTF-8


@dataclass(frozen=True)
class MessageType:
    code: int
    name: str
    request: tuple[Field, ...] | None     # None: not a request (device-initiated)
    response: tuple[Field, ...]
    doc: str

    @property
    def response_code(self) -> int:
        return self.code | RESPONSE_FLAG if self.request is not None else self.code


def _f(spec: str) -> tuple[Field, ...]:
    """'name:fmt name:fmt' -> fields."""
    return tuple(Field(*item.split(":")) for item in spec.split())


_TEMPLATE = "number:B task:B repetitions:B capacity_mah:H current_ma:H voltage_mv:H series:B"

# The one table. Field formats: B u8, H u16, I u32, b i8, h i16, i i32, p short UTF-8, u* rest UTF-8, s* rest bytes.
MESSAGE_TYPES: tuple[MessageType, ...] = (
    MessageType(0x01, "IDENTIFY", (), _f(
        "protocol:B eeprom_size:H max_data:B max_charge_ma:I max_charge_dw:H max_discharge_ma:I "
        "max_discharge_dw:H max_mv:I write_us_per_byte:I model:p firmware:p"),
        "who is there: protocol version, EEPROM size, charger limits (W in tenths), model and firmware"),
    MessageType(0x02, "READ_EEPROM", _f("offset:H length:B"), _f("offset:H data:s*"),
                "read length (1..240) EEPROM bytes at offset"),
    MessageType(0x03, "BEGIN_WRITE", _f("nonce:I"), _f("token:I size:H"),
                "open a write transaction: staging := a copy of the EEPROM; the host's random nonce is the "
                "token (an empty request: the charger picks one); answers the token"),
    MessageType(0x04, "WRITE_STAGE", _f("token:I offset:H data:s*"), _f("offset:H length:B"),
                "write up to 240 bytes into the staging copy"),
    MessageType(0x05, "COMMIT", _f("token:I crc:H"), _f("changed:H crc:H"),
                "check the staged image's CRC-16, then copy its changed bytes to the EEPROM"),
    MessageType(0x06, "ABORT", _f("token:I"), (), "drop the staging copy (token 0: whatever is open)"),
    MessageType(0x10, "START", _f("slot:B task:B repetitions:B capacity_mah:H current_ma:H voltage_mv:H "
                                  "series:B sensor:B"), _f("slot:B name:u*"),
                "start the macro in a slot (0 = value not given for capacity/current/voltage/series)"),
    MessageType(0x11, "STOP", (), _f("state:B"), "stop the running macro"),
    MessageType(0x12, "STATUS", (), _f(
        "state:B slot:B task:B uptime_ms:I run_ms:I events:I speed:I name:p end_reason:u*"),
        "state (idle/running/paused/finished), slot, task, clocks, event count, end reason"),
    MessageType(0x13, "SET_TELEMETRY_RATE", _f("hz:B"), _f("hz:B"), "telemetry frames per second, 1..50"),
    MessageType(0x14, "GET_EVENT", _f("number:I"), _f(
        "number:I time_ms:I kind:B section:B index:B repetition:B offset:H detail:u*"),
        "an event of the current run again, by number (to fill a gap)"),
    MessageType(0x15, "LIST_TEMPLATES", (), _f("numbers:s*"),
                "the numbers of the start templates the charger holds, one byte each, ascending"),
    MessageType(0x16, "GET_TEMPLATE", _f("number:B"), _f(_TEMPLATE),
                "start template n (START_SHABLON=n): task, repetitions, capacity, current, voltage, cells "
                "(0 = not in the template)"),
    MessageType(0x17, "SET_TEMPLATE", _f(_TEMPLATE), _f(_TEMPLATE),
                "store start template n (1..16); answers what is stored"),
    MessageType(0x20, "PASSPORT", _f("request:s*"), _f("answer:s*"),
                "pass an 8-byte passport request (docs/zuml-2.0.md §4) to the battery; answers its 32 bytes"),
    MessageType(0x30, "CAL_READ", (), _f("source:B block:s*"),
                "the calibration block (source 1: the EEPROM's, 0: not calibrated, the nominal one)"),
    MessageType(0x31, "CAL_WRITE", _f("block:s*"), _f("source:B block:s*"), "store a calibration block"),
    MessageType(0x32, "CAL_MEASURE", (), _f("inputs:s*"),
                "each input's last whole-second average: ADC16 u16 and its value i32, 13 times"),
    MessageType(0x33, "CAL_OUTPUT", _f("mode:B current_ma:H"), _f("mode:B current_ma:H"),
                "hold a current for calibration: 0 off, 1 charge, 2 discharge"),
    MessageType(0x40, "TELEMETRY", None, _f(
        "time_ms:I task:B section:B repetition:B cycle:B phase:B run:H flags:B voltage_mv:H current_ma:i "
        "temp_c100:h heatsink_c100:h mah10_in:I mah10_out:I"),
        "measurements: macro clock, where the macro is, V, signed I, T, Tc, charge in/out"),
    MessageType(0x41, "EVENT", None, _f(
        "number:I time_ms:I kind:B section:B index:B repetition:B offset:H detail:u*"),
        "something happened: a phase started or ended (with its reason), pause, resume, music, ..."),
    MessageType(0x42, "LCD", None, _f("row:B text:u*"),
                "a line of the charger's display (row 0 or 1), sent only while no host has spoken (listen-only)"),
    MessageType(0x7F, "ERROR", None, _f("request_type:B code:B message:u*"),
                "the request could not be served: its type, an ErrorCode, a message"),
)

BY_NAME: dict[str, MessageType] = {m.name: m for m in MESSAGE_TYPES}
BY_CODE: dict[int, MessageType] = {m.code: m for m in MESSAGE_TYPES}
REQUEST_CODES = frozenset(m.code for m in MESSAGE_TYPES if m.request is not None)
# Every TYPE a device may send; the client's parser refuses other types at once.
DEVICE_TYPES = frozenset(m.response_code for m in MESSAGE_TYPES)
HOST_TYPES = REQUEST_CODES

IDENTIFY, READ_EEPROM, BEGIN_WRITE, WRITE_STAGE, COMMIT, ABORT = (BY_NAME[n].code for n in (
    "IDENTIFY", "READ_EEPROM", "BEGIN_WRITE", "WRITE_STAGE", "COMMIT", "ABORT"))
START, STOP, STATUS, SET_TELEMETRY_RATE, GET_EVENT, PASSPORT = (BY_NAME[n].code for n in (
    "START", "STOP", "STATUS", "SET_TELEMETRY_RATE", "GET_EVENT", "PASSPORT"))
TELEMETRY, EVENT, LCD, ERROR = 0x40, 0x41, 0x42, 0x7F

FLAG_RUNNING, FLAG_PAUSED, FLAG_SENSOR = 1, 2, 4

_STRUCTS: dict[tuple[Field, ...], tuple[struct.Struct, tuple[str, ...], tuple[Field, ...]]] = {}


def _layout(fields: tuple[Field, ...]):
    cached = _STRUCTS.get(fields)
    if cached is None:
        fixed = []
        for f in fields:
            if f.fmt in ("s*", "u*", "p"):
                break
            fixed.append(f)
        tail = fields[len(fixed):]
        cached = (struct.Struct("<" + "".join(f.fmt for f in fixed)), tuple(f.name for f in fixed), tail)
        _STRUCTS[fields] = cached
    return cached


def pack_fields(fields: tuple[Field, ...], values: dict) -> bytes:
    st, names, tail = _layout(fields)
    try:
        out = st.pack(*(values[n] for n in names))
    except (struct.error, KeyError) as exc:
        raise PayloadError(_("cannot pack {names}: {exc}").format(names=names, exc=exc)) from None
    for f in tail:
        v = values.get(f.name, b"" if f.fmt == "s*" else "")
        if f.fmt == "s*":
            out += bytes(v)
        else:
            raw = str(v).encode("utf-8")
            if f.fmt == "p":
                raw = raw[:255]
                out += bytes((len(raw),)) + raw
            else:
                out += raw
    return out


def unpack_fields(fields: tuple[Field, ...], payload: bytes) -> dict:
    st, names, tail = _layout(fields)
    if len(payload) < st.size or (not tail and len(payload) != st.size):
        raise PayloadError(_("payload of {n_payload} bytes; the layout needs {size}").format(
                n_payload=len(payload), size=st.size))
    values = dict(zip(names, st.unpack_from(payload)))
    at = st.size
    for f in tail:
        if f.fmt == "p":
            if at >= len(payload):
                raise PayloadError(_("a length-prefixed text is missing"))
            n = payload[at]
            raw = payload[at + 1:at + 1 + n]
            if len(raw) != n:
                raise PayloadError(_("a length-prefixed text runs past the payload"))
            values[f.name] = raw.decode("utf-8", "replace")
            at += 1 + n
        elif f.fmt == "s*":
            values[f.name] = bytes(payload[at:])
            at = len(payload)
        else:
            values[f.name] = bytes(payload[at:]).decode("utf-8", "replace")
            at = len(payload)
    if at != len(payload):
        raise PayloadError(ngettext("{n_payload} extra byte after the payload's fields",
                                    "{n_payload} extra bytes after the payload's fields", len(payload) - at).format(
                n_payload=len(payload) - at))
    return values


def encode_request(name: str, /, **values) -> bytes:
    return pack_fields(BY_NAME[name].request, values)


def decode_request(code: int, payload: bytes) -> dict:
    return unpack_fields(BY_CODE[code].request, payload)


def encode_response(name: str, /, **values) -> bytes:
    return pack_fields(BY_NAME[name].response, values)


def decode_response(code: int, payload: bytes) -> dict:
    """``code`` is the request's type (without the response flag)."""
    return unpack_fields(BY_CODE[code].response, payload)


def encode_error(request_type: int, code: int, message: str) -> bytes:
    raw = message.encode("utf-8")[:240]
    return bytes((request_type & 0xFF, int(code))) + raw


def decode_error(payload: bytes) -> tuple[int, int, str]:
    if len(payload) < 2:
        raise PayloadError(_("an ERROR payload has at least 2 bytes"))
    return payload[0], payload[1], bytes(payload[2:]).decode("utf-8", "replace")


# -- the two device-initiated messages as objects, for the client's callbacks -------------

_TELEMETRY_STRUCT = _layout(BY_NAME["TELEMETRY"].response)[0]
TELEMETRY_CELLS = 6       # the cell voltages a TELEMETRY frame carries at most (a B6's balance port)


@dataclass(frozen=True)
class Telemetry:
    """One measurement. ``current_a`` is signed: + charge, - discharge.

    ``section`` is "discharge", "charge" or "" (idle); ``temp_c`` is None without a sensor.
    ``heatsink_c`` is the charger's internal temperature. ``cells_v`` holds per-cell voltages
    where the charger measures them (balance port); our protocol's frame carries up to the first
    ``TELEMETRY_CELLS`` of them, with ``balance_mask`` (bit k-1: cell k bleeds), in an optional tail
    (docs/protocol.md), and only for more than one cell. ``state`` is a monitor-only charger's own
    name for its state ("charging", "done", …; ``streams.drivers``), "" for our protocol (not encoded)."""

    time_s: float             # the macro's clock (device time of the run)
    task: str
    section: str
    repetition: int
    cycle: int                # pass of the enclosing CYCLE, 0 outside a cycle
    phase: int                # FAZE index in its section (0: none or the default discharge)
    run: int                  # sequential number of the phase in this run, 1-based (0: none)
    running: bool
    paused: bool
    sensor: bool
    voltage_v: float
    current_a: float
    temp_c: float | None
    heatsink_c: float | None
    mah_in: float
    mah_out: float
    cells_v: tuple[float, ...] = ()
    state: str = ""
    balance_mask: int = 0

    def encode(self) -> bytes:
        flags = (FLAG_RUNNING if self.running else 0) | (FLAG_PAUSED if self.paused else 0) | \
            (FLAG_SENSOR if self.sensor else 0)
        return _TELEMETRY_STRUCT.pack(
            _clamp(round(self.time_s * 1000), 0, 0xFFFFFFFF), TASKS.index(self.task) if self.task in TASKS else 0,
            SECTIONS.index(self.section) if self.section in SECTIONS else SECTION_NONE,
            _clamp(self.repetition, 0, 255), _clamp(self.cycle, 0, 255), _clamp(self.phase, 0, 255),
            _clamp(self.run, 0, 0xFFFF), flags, _clamp(round(self.voltage_v * 1000), 0, 0xFFFF),
            _clamp(round(self.current_a * 1000), -0x80000000, 0x7FFFFFFF), _temp(self.temp_c),
            _temp(self.heatsink_c), _clamp(round(self.mah_in * 10), 0, 0xFFFFFFFF),
            _clamp(round(self.mah_out * 10), 0, 0xFFFFFFFF)) + self._cells_tail()

    def _cells_tail(self) -> bytes:
        cells = self.cells_v[:TELEMETRY_CELLS]
        if len(cells) < 2:
            return b""
        return bytes((len(cells), self.balance_mask & ((1 << len(cells)) - 1))) + b"".join(
            _clamp(round(v * 1000), 0, 0xFFFF).to_bytes(2, "little") for v in cells)

    @classmethod
    def decode(cls, payload: bytes) -> "Telemetry":
        base = _TELEMETRY_STRUCT.size
        cells_v: tuple[float, ...] = ()
        mask = 0
        if len(payload) > base:
            n = payload[base]
            if not 2 <= n <= TELEMETRY_CELLS or len(payload) != base + 2 + 2 * n:
                raise PayloadError(_("TELEMETRY's cell tail is not a count of 2..{top} cells, a mask and their "
                                     "voltages").format(top=TELEMETRY_CELLS))
            mask = payload[base + 1]
            if mask >> n:
                raise PayloadError(_("TELEMETRY's balance mask {mask:#04x} names a cell beyond its {n} cells").format(
                    mask=mask, n=n))
            cells_v = tuple(int.from_bytes(payload[k:k + 2], "little") / 1000.0
                            for k in range(base + 2, len(payload), 2))
        elif len(payload) != base:
            raise PayloadError(_("TELEMETRY has {size} bytes, not {n_payload}").format(
                    size=base, n_payload=len(payload)))
        (t, task, section, rep, cycle, phase, run, flags, mv, ma, tc, hs, qi, qo) = \
            _TELEMETRY_STRUCT.unpack(payload[:base])
        return cls(t / 1000.0, TASKS[task] if task < len(TASKS) else "charge",
                   SECTIONS[section] if section < len(SECTIONS) else "", rep, cycle, phase, run,
                   bool(flags & FLAG_RUNNING), bool(flags & FLAG_PAUSED), bool(flags & FLAG_SENSOR),
                   mv / 1000.0, ma / 1000.0, None if tc == TEMP_UNKNOWN else tc / 100.0,
                   None if hs == TEMP_UNKNOWN else hs / 100.0, qi / 10.0, qo / 10.0, cells_v, "", mask)


@dataclass(frozen=True)
class DeviceEvent:
    """Something that happened in the run; mirrors ``sim.interpreter.Event``.

    ``number`` counts the run's events from 0: a jump shows a lost frame, and
    ``ChargerClient.get_event(number)`` fetches it again."""

    number: int
    time_s: float
    kind: str                 # section | phase_start | phase_end | pause | resume | music | light | finish
    section: str = ""
    index: int = 0
    repetition: int = 0
    offset: int = -1          # byte offset of the FAZE (or command) in the record, -1 none
    detail: str = ""          # phase_end: the end reason, e.g. "IF(DELTA_PEAK>0.01S) STOP_FAZE"

    def encode(self) -> bytes:
        return pack_fields(BY_NAME["EVENT"].response, {
            "number": self.number & 0xFFFFFFFF, "time_ms": _clamp(round(self.time_s * 1000), 0, 0xFFFFFFFF),
            "kind": EVENT_KINDS.index(self.kind),
            "section": SECTIONS.index(self.section) if self.section in SECTIONS else SECTION_NONE,
            "index": _clamp(self.index, 0, 255), "repetition": _clamp(self.repetition, 0, 255),
            "offset": NO_OFFSET if self.offset < 0 else _clamp(self.offset, 0, 0xFFFE),
            "detail": _utf8_prefix(self.detail, 200)})

    @classmethod
    def decode(cls, payload: bytes) -> "DeviceEvent":
        v = unpack_fields(BY_NAME["EVENT"].response, payload)
        if v["kind"] >= len(EVENT_KINDS):
            raise PayloadError(_("unknown event kind {v}").format(v=v['kind']))
        return cls(v["number"], v["time_ms"] / 1000.0, EVENT_KINDS[v["kind"]],
                   SECTIONS[v["section"]] if v["section"] < len(SECTIONS) else "", v["index"], v["repetition"],
                   -1 if v["offset"] == NO_OFFSET else v["offset"], v["detail"])


def template_fields(number: int, template) -> dict:
    """A ``domain.start_templates.StartTemplate`` as GET_TEMPLATE/SET_TEMPLATE fields (0: not given)."""
    return {"number": number, "task": TASKS.index(template.task), "repetitions": template.repetitions,
            "capacity_mah": round(template.capacity_mah or 0), "current_ma": round((template.current_a or 0) * 1000),
            "voltage_mv": round((template.voltage_v or 0) * 1000), "series": template.series or 0}


def template_of(fields: dict):
    """GET_TEMPLATE/SET_TEMPLATE fields -> (number, StartTemplate); TemplateError for values it refuses."""
    from ..domain.start_templates import StartTemplate, TemplateError
    if fields["task"] >= len(TASKS):
        raise TemplateError(_("task {fields}: 0 charge, 1 discharge, 2 train").format(fields=fields['task']))
    return fields["number"], StartTemplate(
        TASKS[fields["task"]], fields["repetitions"], float(fields["capacity_mah"]) or None,
        fields["current_ma"] / 1000.0 or None, fields["voltage_mv"] / 1000.0 or None, fields["series"] or None)


def _clamp(v: int, lo: int, hi: int) -> int:
    return lo if v < lo else hi if v > hi else int(v)


def _temp(c: float | None) -> int:
    return TEMP_UNKNOWN if c is None else _clamp(round(c * 100), -0x7FFF, 0x7FFE)


def _utf8_prefix(text: str, limit: int) -> str:
    raw = text.encode("utf-8")
    return raw[:limit].decode("utf-8", "ignore") if len(raw) > limit else text
