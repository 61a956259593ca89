"""The battery passport of spec §4 (seed 003): an 8-byte request, a 32-byte answer.

Request: ``A7 | RW_INDEX | PAGE | DATA0..3 | XOR of bytes 0..6`` where RW_INDEX is 0x00
(whole passport), 0x1X (read page X) or 0x2X (write page X) and PAGE repeats X.

Answer (32 bytes, to every request, always; a page read takes bytes 4X..4X+3 of it):

    0x00 A7, 0x01 layout version 1, 0x02-0x11 SERIAL (16 ASCII, NUL-padded),
    0x12-0x15 VENDOR (4 ASCII), 0x16 TYPE (AKK_TYPE code), 0x17 ERR u16, 0x19 CRIT u16,
    0x1B V_LIMIT (V, u8), 0x1C A_LIMIT (A, u8), 0x1D TEMP (°C, i8, live),
    0x1E-0x1F check: XOR of the 15 little-endian 16-bit words at 0x00..0x1D, little-endian.

Pages are 0..6 (seed 003). On a production battery only the error section (ERR, CRIT) is
writable; a factory battery lets the host write SERIAL, VENDOR, TYPE and V_LIMIT too (A_LIMIT
sits on page 7, which no request addresses: it is set when the battery is made).

Decisions where the spec is silent: a request the battery cannot serve (bad length, magic, XOR,
RW_INDEX or page, or a write to a read-only byte) gets an *error answer*: 32 bytes, MAGIC, then
0xEE where the layout version stands, an error code (``AnswerError``), the request's RW_INDEX and
PAGE, zeros, and the same check word; a refused write changes nothing. The battery keeps MAGIC,
version, TEMP and the check itself (written bytes there are ignored); a limit of 0 means "not
set". ``conflicts`` is the lockout: what a charger must refuse to start on this battery.
"""
from __future__ import annotations

import enum
import struct
from dataclasses import dataclass, replace
from typing import Callable

from ..lang import opcodes as ops
from ..lang.formatter import format_args
from ..lang.opcodes import canonical_text
from ..lang.operands import AKK_TYPE as AKK_KIND, AKK_TYPE_ALIASES, DISPLAY_NAMES, absolute_value
from ..i18n import N_, _

MAGIC = 0xA7
VERSION = 0x01
SIZE = 32
REQUEST_SIZE = 8
PAGE_SIZE = 4
PAGES = 7                     # pages 0..6 (seed 003): bytes 0x00..0x1B
READ_ALL, READ_PAGE, WRITE_PAGE = 0x00, 0x10, 0x20
ERROR_MARK = 0xEE             # in the version byte: this answer is an error answer


class AnswerError(enum.IntEnum):
    """Error codes of an error answer (byte 0x02)."""

    BAD_LENGTH = 1
    BAD_MAGIC = 2
    BAD_XOR = 3
    BAD_COMMAND = 4       # RW_INDEX neither 0x00, 0x1X nor 0x2X
    BAD_PAGE = 5          # not 0..6, or PAGE does not repeat RW_INDEX's X
    READ_ONLY = 6         # a write would change a byte the battery does not let the charger write


ANSWER_ERROR_TEXT = {
    AnswerError.BAD_LENGTH: N_("the request is not 8 bytes"),
    AnswerError.BAD_MAGIC: N_("the request's magic is not 0xA7"),
    AnswerError.BAD_XOR: N_("the request's XOR byte is wrong"),
    AnswerError.BAD_COMMAND: N_("RW_INDEX is not a passport command"),
    AnswerError.BAD_PAGE: N_("the page is not 0..6 (or PAGE differs from RW_INDEX's page)"),
    AnswerError.READ_ONLY: N_("the write touches read-only fields (on a production battery only ERR and CRIT "
                           "are writable)"),
}

# field -> (offset, size)
LAYOUT = {"magic": (0x00, 1), "version": (0x01, 1), "serial": (0x02, 16), "vendor": (0x12, 4),
          "type": (0x16, 1), "err": (0x17, 2), "crit": (0x19, 2), "v_limit": (0x1B, 1),
          "a_limit": (0x1C, 1), "temp": (0x1D, 1), "check": (0x1E, 2)}
FIELDS = ("serial", "vendor", "type", "err", "crit", "v_limit", "a_limit")
WRITABLE = ("err", "crit")               # through the charger, on a production battery
FACTORY_WRITABLE = ("serial", "vendor", "type", "err", "crit", "v_limit")   # pages 0..6
# Bytes the battery maintains itself.
_OWN_BYTES = frozenset((0x00, 0x01, 0x1D, 0x1E, 0x1F))
_ERROR_SECTION = frozenset(range(0x17, 0x1B))      # ERR, CRIT
_BODY = struct.Struct("<BB16s4sBHHBBb")


class PassportError(ValueError):
    pass


def akk_name(code: int) -> str:
    key = AKK_KIND.name_of(code)
    return DISPLAY_NAMES.get(key, key) if key else f"type {code}"


def akk_code(text: str | int) -> int:
    if isinstance(text, int):
        code = text
    else:
        t = text.strip().upper()
        if t in AKK_TYPE_ALIASES:
            return AKK_TYPE_ALIASES[t]
        if t in AKK_KIND.names:
            return AKK_KIND.names[t]
        try:
            code = int(t, 0)
        except ValueError:
            names = ", ".join(DISPLAY_NAMES[k] for k in AKK_KIND.names)
            raise PassportError(_("'{text}' is not a battery type; use one of {names} or 0..255").format(
                    text=text, names=names)) from None
    if not 0 <= code <= 255:
        raise PassportError(_("battery type {code} is not 0..255").format(code=code))
    return code


def check_word(data: bytes) -> int:
    """XOR of the 15 little-endian words at 0x00..0x1D."""
    w = 0
    for (v,) in struct.iter_unpack("<H", bytes(data[:0x1E])):
        w ^= v
    return w


def check_ok(data: bytes) -> bool:
    return len(data) == SIZE and data[0] == MAGIC and check_word(data) == int.from_bytes(data[0x1E:0x20], "little")


@dataclass(frozen=True)
class Passport:
    serial: str = ""
    vendor: str = ""
    type: int = 0
    err: int = 0
    crit: int = 0
    v_limit: int = 0          # volts, whole pack; 0 = not set
    a_limit: int = 0          # amperes; 0 = not set
    temp: int = 25            # °C, the battery's live reading
    version: int = VERSION

    @property
    def type_name(self) -> str:
        return akk_name(self.type)

    @property
    def unprintable_fields(self) -> list[str]:
        """The text fields holding bytes outside printable ASCII (a damaged or forged passport)."""
        return [f for f in ("serial", "vendor") if printable(getattr(self, f)) != getattr(self, f)]

    def to_bytes(self) -> bytes:
        body = _BODY.pack(MAGIC, self.version, _ascii(self.serial, 16, "serial"), _ascii(self.vendor, 4, "vendor"),
                          _u(self.type, 0xFF, "type"), _u(self.err, 0xFFFF, "err"), _u(self.crit, 0xFFFF, "crit"),
                          _u(self.v_limit, 0xFF, "v_limit"), _u(self.a_limit, 0xFF, "a_limit"),
                          max(-128, min(127, int(self.temp))))
        return body + check_word(body).to_bytes(2, "little")

    @classmethod
    def from_bytes(cls, data: bytes) -> "Passport":
        data = bytes(data)
        if len(data) != SIZE:
            raise PassportError(_("a passport is {size} bytes, not {n_data}").format(size=SIZE, n_data=len(data)))
        if data[0] != MAGIC:
            raise PassportError(_("passport magic is 0x{data:02x}, expected 0x{magic:02x}").format(
                    data=data[0], magic=MAGIC))
        stored, expected = int.from_bytes(data[0x1E:0x20], "little"), check_word(data)
        if stored != expected:
            raise PassportError(_("passport check is 0x{stored:04x}, expected 0x{expected:04x}").format(
                    stored=stored, expected=expected))
        magic, version, serial, vendor, typ, err, crit, vl, al, temp = _BODY.unpack(data[:0x1E])
        return cls(_text(serial), _text(vendor), typ, err, crit, vl, al, temp, version)

    def with_field(self, field: str, value) -> "Passport":
        """A copy with one field set; text values are parsed ("NiMh", "12", "0x10"). Which fields a
        battery lets the charger write is the battery's decision (``PassportChip``)."""
        field = field.strip().lower()
        if field not in FIELDS:
            raise PassportError(_("'{field}' is not a passport field; fields: {fields}").format(
                    field=field, fields=', '.join(FIELDS)))
        if field in ("serial", "vendor"):
            value = str(value)
            _ascii(value, LAYOUT[field][1], field)
        elif field == "type":
            value = akk_code(value)
        else:
            try:
                value = int(value, 0) if isinstance(value, str) else int(value)
            except ValueError:
                raise PassportError(_("{field} takes a whole number, not '{value}'").format(
                        field=field, value=value)) from None
            _u(value, 0xFFFF if field in ("err", "crit") else 0xFF, field)
        return replace(self, **{field: value})


def _ascii(text: str, size: int, what: str) -> bytes:
    try:
        raw = text.encode("ascii")
    except UnicodeEncodeError:
        raise PassportError(_("{what} must be ASCII").format(what=what)) from None
    if len(raw) > size:
        raise PassportError(_("{what} has at most {size} characters, not {n_raw}").format(
                what=what, size=size, n_raw=len(raw)))
    if any(b < 0x20 or b > 0x7E for b in raw):
        raise PassportError(_("{what} must be printable ASCII").format(what=what))
    return raw.ljust(size, b"\0")


def _text(raw: bytes) -> str:
    return raw.split(b"\0", 1)[0].decode("latin-1")      # one character per byte, shown by ``printable``


def printable(text: str) -> str:
    """Text that came from a battery, safe to print or show: every character outside printable
    ASCII as ``\\xNN`` (a control byte could clear a terminal or forge a line)."""
    return "".join(c if " " <= c <= "~" else f"\\x{ord(c):02x}" for c in text)


def _u(value: int, top: int, what: str) -> int:
    if not isinstance(value, int) or not 0 <= value <= top:
        raise PassportError(_("{what} must be 0..{top}, not {value}").format(what=what, top=top, value=value))
    return value


# -- requests ----------------------------------------------------------------------------

def make_request(rw_index: int, page: int = 0, data: bytes = b"\0\0\0\0") -> bytes:
    if len(data) != PAGE_SIZE:
        raise PassportError(_("a request carries exactly 4 data bytes"))
    body = bytes((MAGIC, rw_index & 0xFF, page & 0xFF)) + bytes(data)
    x = 0
    for b in body:
        x ^= b
    return body + bytes((x,))


def read_all_request() -> bytes:
    return make_request(READ_ALL)


def read_page_request(page: int) -> bytes:
    _page(page)
    return make_request(READ_PAGE | page, page)


def write_page_request(page: int, data: bytes) -> bytes:
    _page(page)
    return make_request(WRITE_PAGE | page, page, data)


def _page(page: int) -> None:
    if not 0 <= page < PAGES:
        raise PassportError(_("a passport page is 0..{pages}, not {page}").format(pages=PAGES - 1, page=page))


class BadRequest(PassportError):
    def __init__(self, code: AnswerError, message: str):
        super().__init__(message)
        self.code = code


def parse_request(req: bytes) -> tuple[str, int, bytes]:
    """-> ("all" | "read" | "write", page, data). Raises BadRequest (with the answer's error code)
    for a request the battery cannot serve."""
    req = bytes(req)
    if len(req) != REQUEST_SIZE:
        raise BadRequest(AnswerError.BAD_LENGTH, _("a passport request is {request_size} bytes, not {n_req}").format(
                request_size=REQUEST_SIZE, n_req=len(req)))
    if req[0] != MAGIC:
        raise BadRequest(AnswerError.BAD_MAGIC, _("request magic 0x{req:02x}, expected 0x{magic:02x}").format(
                req=req[0], magic=MAGIC))
    x = 0
    for b in req[:7]:
        x ^= b
    if x != req[7]:
        raise BadRequest(AnswerError.BAD_XOR, _("request XOR 0x{req:02x}, expected 0x{x:02x}").format(req=req[7], x=x))
    rw, page, data = req[1], req[2], req[3:7]
    if rw == READ_ALL:
        return "all", 0, data
    op = {READ_PAGE: "read", WRITE_PAGE: "write"}.get(rw & 0xF0)
    if op is None:
        raise BadRequest(AnswerError.BAD_COMMAND, _("RW_INDEX 0x{rw:02x} is not a passport command").format(rw=rw))
    if (rw & 0x0F) != page or page >= PAGES:
        raise BadRequest(AnswerError.BAD_PAGE,
                         _("RW_INDEX 0x{rw:02x} with PAGE {page} is not a page 0..{pages}").format(
                rw=rw, page=page, pages=PAGES - 1))
    return op, page, data


def error_answer(code: AnswerError, request: bytes) -> bytes:
    """The 32-byte answer to a request the battery cannot serve."""
    req = bytes(request)
    body = bytearray(SIZE)
    body[0], body[1], body[2] = MAGIC, ERROR_MARK, int(code)
    body[3] = req[1] if len(req) > 1 else 0
    body[4] = req[2] if len(req) > 2 else 0
    body[0x1E:0x20] = check_word(body).to_bytes(2, "little")
    return bytes(body)


def answer_error(answer: bytes) -> str | None:
    """What an error answer says ("the battery refused: ..."), or None for a passport answer."""
    if len(answer) == SIZE and answer[0] == MAGIC and answer[1] == ERROR_MARK:
        try:
            text = _(ANSWER_ERROR_TEXT[AnswerError(answer[2])])
        except ValueError:
            text = _("an unknown error")
        return _("{text} (passport error {code})").format(text=text, code=answer[2])
    return None


def page_of(answer: bytes, page: int) -> bytes:
    _page(page)
    return bytes(answer[PAGE_SIZE * page:PAGE_SIZE * (page + 1)])


def page_writes(old: bytes, new: bytes) -> list[bytes]:
    """The write requests that turn passport ``old`` into ``new`` (pages that differ in bytes the host owns).
    PassportError when a differing byte lies beyond page 6 (A_LIMIT: no request reaches it)."""
    beyond = [i for i in range(PAGES * PAGE_SIZE, SIZE) if i not in _OWN_BYTES and old[i] != new[i]]
    if beyond:
        raise PassportError(_("A_LIMIT lies on page 7, which no passport request addresses (pages 0..6): it is "
                              "set when the battery is made"))
    out = []
    for page in range(PAGES):
        lo = PAGE_SIZE * page
        if any(old[i] != new[i] for i in range(lo, lo + PAGE_SIZE) if i not in _OWN_BYTES):
            out.append(write_page_request(page, new[lo:lo + PAGE_SIZE]))
    return out


class PassportChip:
    """The battery's side: holds the 32 bytes, keeps TEMP live and the check right, and lets the
    charger write only the error section (``factory``: SERIAL, VENDOR, TYPE and V_LIMIT too)."""

    def __init__(self, passport: Passport, temp_source: Callable[[], float] | None = None, *,
                 factory: bool = False):
        self._image = bytearray(passport.to_bytes())
        self._temp_source = temp_source
        self.factory = factory
        self.writes = 0

    def _refresh(self) -> None:
        if self._temp_source is not None:
            t = round(self._temp_source())
            self._image[0x1D] = max(-128, min(127, t)) & 0xFF
        self._image[0] = MAGIC
        self._image[1] = VERSION
        self._image[0x1E:0x20] = check_word(self._image).to_bytes(2, "little")

    @property
    def image(self) -> bytes:
        self._refresh()
        return bytes(self._image)

    @property
    def passport(self) -> Passport:
        return Passport.from_bytes(self.image)

    def answer(self, request: bytes) -> bytes:
        """32 bytes, always: the passport, or an error answer."""
        try:
            op, page, data = parse_request(request)
        except BadRequest as exc:
            return error_answer(exc.code, request)
        if op == "write":
            lo = PAGE_SIZE * page
            changes = [(lo + k, data[k]) for k in range(PAGE_SIZE)
                       if lo + k not in _OWN_BYTES and self._image[lo + k] != data[k]]
            if not self.factory and any(at not in _ERROR_SECTION for at, _ in changes):
                return error_answer(AnswerError.READ_ONLY, request)
            for at, value in changes:
                self._image[at] = value
            self.writes += 1
        return self.image


def default_passport(chemistry: str, capacity_mah: float, series: int, serial: str = "ZUML-VIRT-0001") -> Passport:
    """What the virtual charger's battery carries: its chemistry, V_LIMIT = the chemistry's absolute
    maximum per cell × cells (rounded up), A_LIMIT = 2C (rounded up, at least 1 A)."""
    import math
    from ..domain.chemistry import load_chemistry
    code = akk_code(chemistry)
    try:
        chem = load_chemistry(akk_name(code))
        v_limit = min(255, math.ceil(chem.max_v * series - 1e-9))
    except KeyError:
        v_limit = 0
    a_limit = min(255, max(1, math.ceil(2 * capacity_mah / 1000.0 - 1e-9)))
    return Passport(serial, "ZUML", code, 0, 0, v_limit, a_limit, 25)


# -- the lockout -------------------------------------------------------------------------

def fitness_warnings(passport: Passport) -> list[str]:
    """What a charger shows before a start without refusing it: errors (ERR) the battery counted."""
    if passport.err:
        return [_("the battery reports {n} error(s) (ERR={n})").format(n=passport.err)]
    return []


def conflicts(passport: Passport, record: bytes, start, *, charger_max_a: float | None = None) -> list[str]:
    """Why the macro in ``record`` must not run on the battery this passport describes.

    ``start`` is a ``sim.interpreter.StartParams``. Values are resolved by the interpreter's
    rules (C with the capacity, S with the series, INPUT with the start values); a value that
    cannot be resolved is skipped (the start itself will fail on it). ``charger_max_a`` is the
    current a CONSTANT_V phase alone may reach when no current was entered.
    """
    from ..sim.program import DefaultDischarge, PhaseCode, Program
    program = Program(record)          # DecodeError for bytes that are not a record
    out: list[str] = []
    if passport.crit:
        out.append(_("the battery reports {n} critical error(s) (CRIT={n}): it is not fit for use").format(
            n=passport.crit))
    akk = program.intro.declarations.get(ops.AKK_TYPE.code, 0)
    if akk != passport.type:
        if akk == 0:
            out.append(_("the macro sets no battery type (AKK_TYPE Undef); the battery is {battery}").format(
                battery=akk_name(passport.type)))
        else:
            out.append(_("the macro is for {macro}; the battery is {battery}").format(
                macro=akk_name(akk), battery=akk_name(passport.type)))
    capacity_ah = program.intro.capacity_ah(start.capacity_mah)
    series = program.intro.series(start.series)

    def current(raw: int) -> float | None:
        return absolute_value(raw, start.current_a, capacity_ah)

    def voltage(raw: int) -> float | None:
        return absolute_value(raw, start.voltage_v, series)

    a_lim, v_lim = passport.a_limit, passport.v_limit
    seen: set[str] = set()

    def add(text: str) -> None:
        if text not in seen:
            seen.add(text)
            out.append(text)

    def text(ins) -> str:
        return canonical_text(ins.op, format_args(ins.op, ins.raws))

    for step in program.steps(start.task, 1):
        if isinstance(step, DefaultDischarge) or not isinstance(step, PhaseCode):
            continue
        by_code = {a.op.code: a for a in step.actions}
        charging = step.section == "charge" or 62 in by_code or 63 in by_code
        if not charging:
            continue
        where = (_("charge phase {index}") if step.section == "charge"
                 else _("discharge phase {index}")).format(index=step.index)
        if a_lim:
            charge_currents = []
            if 62 in by_code:
                charge_currents.append((by_code[62].raws[1], by_code[62]))
            elif 63 in by_code:
                charge_currents.append((by_code[63].raws[0], by_code[63]))
            elif 60 in by_code:
                charge_currents.append((by_code[60].raws[0], by_code[60]))
            for raw, ins in charge_currents:
                amps = current(raw)
                if amps is not None and amps > a_lim + 1e-9:
                    add(_("the macro charges at {amps:.2f} A ({where}: {statement}); the battery allows {limit} "
                          "A").format(amps=amps, where=where, statement=text(ins), limit=a_lim))
            if 61 in by_code and 60 not in by_code:
                amps = start.current_a if start.current_a else charger_max_a
                if amps is not None and amps > a_lim + 1e-9:
                    how = (_("the current entered at start") if start.current_a
                           else _("the charger's limit, no current entered"))
                    add(_("the macro charges at up to {amps:.2f} A ({where}: {statement} limited to {how}); the "
                          "battery allows {limit} A").format(amps=amps, where=where, statement=text(by_code[61]),
                                                             how=how, limit=a_lim))
        if v_lim:
            checks = []
            if 61 in by_code:
                checks.append((by_code[61].raws[0], by_code[61],
                               _("the macro holds {volts:.2f} V ({where}: {statement}); the battery allows {limit} V")))
            if 63 in by_code:
                checks.append((by_code[63].raws[2], by_code[63],
                               _("the macro tops up to {volts:.2f} V ({where}: {statement}); the battery allows "
                                 "{limit} V")))
            for ins in step.conditions:
                if ins.op.code == 83:
                    checks.append((ins.raws[0], ins, _("the macro lets the voltage rise to {volts:.2f} V ({where}: "
                                                       "{statement}); the battery allows {limit} V")))
            for raw, ins, sentence in checks:
                volts = voltage(raw)
                if volts is not None and volts > v_lim + 1e-9:
                    add(sentence.format(volts=volts, where=where, statement=text(ins), limit=v_lim))
    return out
