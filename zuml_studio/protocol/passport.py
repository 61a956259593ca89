"""The battery passport of docs/zuml-2.0.md §4 (seed 003): an 8-byte request, a 32-byte answer.

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
set". The lockout (what a charger must refuse to start on this battery) is ``safety.conflicts``; the
battery's side of the exchange, ``virtual.passport_chip``.
"""
from __future__ import annotations

import enum
import struct
from dataclasses import dataclass, replace

from ..errors import ZumlError, error_text
from ..lang.operands import AKK_TYPE as AKK_KIND, AKK_TYPE_ALIASES, DISPLAY_NAMES
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
OWN_BYTES = frozenset((0x00, 0x01, 0x1D, 0x1E, 0x1F))   # the battery keeps these itself
ERROR_SECTION = frozenset(range(0x17, 0x1B))      # ERR, CRIT
_BODY = struct.Struct("<BB16s4sBHHBBb")


class PassportError(ZumlError, ValueError):
    def words(self, action: str = "") -> str:
        return f"passport: {error_text(self)}"


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
    beyond = [i for i in range(PAGES * PAGE_SIZE, SIZE) if i not in OWN_BYTES and old[i] != new[i]]
    if beyond:
        raise PassportError(_("A_LIMIT lies on page 7, which no passport request addresses (pages 0..6): it is "
                              "set when the battery is made"))
    out = []
    for page in range(PAGES):
        lo = PAGE_SIZE * page
        if any(old[i] != new[i] for i in range(lo, lo + PAGE_SIZE) if i not in OWN_BYTES):
            out.append(write_page_request(page, new[lo:lo + PAGE_SIZE]))
    return out


# -- the fitness --------------------------------------------------------------------------

def fitness_warnings(passport: Passport) -> list[str]:
    """What a charger shows before a start without refusing it: errors (ERR) the battery counted."""
    if passport.err:
        return [_("the battery reports {n} error(s) (ERR={n})").format(n=passport.err)]
    return []
