"""Operand kinds: how a value is written in text and stored in the byte code.

Every operand of every opcode is one of the kinds below. A kind knows its
width in bytes, its valid raw range, and how to turn text into a raw integer
(``parse``) and back (``format``). Text parsing reports problems as
``ValueProblem`` so the caller can attach a source position.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from decimal import ROUND_HALF_UP, Decimal, InvalidOperation
import re
from typing import Callable, Mapping
from ..errors import ZumlError
from ..i18n import N_, _

INPUT_U16 = 0xFFFF          # current/voltage entered at start (docs/zuml-2.0.md §2 decision)
RELATIVE_FLAG = 0x8000      # C for currents, S for voltages
CAPACITY_INPUT = 0x0000
CAPACITY_AUTO = 0xFFFF

# Parsed values by kind and text: the editor re-checks the same values on every keystroke.
_PARSED: dict[str, dict[tuple[str, int | None, int | None], "int | ValueProblem"]] = {}

_NUMBER = re.compile(r"^(-?(?:\d+(?:\.\d*)?|\.\d+))([A-Za-z]*)$")
# No operand holds more than 10 digits (4 bytes); a numeral longer than this is refused before it is
# converted (turning a million digits into an integer takes minutes).
MAX_NUMERAL_CHARS = 40


class ValueProblem(ZumlError):
    """A value in the text that cannot be stored. ``code`` is the diagnostic code."""

    def __init__(self, code: str, message: str, hint: str = "", warning_raw: int | None = None):
        super().__init__(message)
        self.code = code
        self.message = message
        self.hint = hint
        # For a warning (e.g. rounding changed the value) the value still encodes as this raw.
        self.warning_raw = warning_raw



def absolute_value(raw: int, entered: float | None, unit: float | None) -> float | None:
    """Amperes (volts) of a stored current (voltage): ``entered``, the value given at start, for
    INPUT; a relative value (C, S) times ``unit``, the capacity in Ah (the cell count). None
    where what it needs is unknown."""
    if raw == INPUT_U16:
        return entered
    value = (raw & 0x7FFF) / 100.0
    if raw & RELATIVE_FLAG:
        return value * unit if unit else None
    return value


def relative_value(raw: int, unit: float | None) -> float | None:
    """A stored current (voltage) as a multiple of the capacity in Ah (per cell): an absolute
    value divided by ``unit``. None for INPUT, or where ``unit`` is unknown."""
    if raw == INPUT_U16:
        return None
    value = (raw & 0x7FFF) / 100.0
    if raw & RELATIVE_FLAG:
        return value
    return value / unit if unit else None

def split_number(text: str) -> tuple[Decimal, str] | None:
    """``"2.1C"`` -> ``(Decimal("2.1"), "C")``; None when the text is not a number."""
    m = _NUMBER.match(text)
    if not m:
        return None
    try:
        return Decimal(m.group(1)), m.group(2)
    except InvalidOperation:
        return None


def _refuse_long_numeral(text: str) -> None:
    m = _NUMBER.match(text)
    if m and len(m.group(1)) > MAX_NUMERAL_CHARS:
        raise ValueProblem("E204", _("a number of {n} characters ({head}…) is longer than any value a macro "
                                     "stores").format(n=len(m.group(1)), head=text[:12]),
                           _("values have at most 10 digits"))


def round_half_away(x: Decimal) -> int:
    return int(x.to_integral_value(rounding=ROUND_HALF_UP))     # quantize overflows past 28 digits


def format_scaled(raw: int, scale: int) -> str:
    """Shortest decimal text of raw/scale: 410,100 -> '4.1'; 5,100 -> '0.05'."""
    text = format(Decimal(raw) / Decimal(scale), "f")
    if "." in text:
        text = text.rstrip("0").rstrip(".")
    return text


@dataclass(frozen=True, eq=False)   # singletons: identity is equality
class OperandKind:
    """One way of storing a value. ``what`` names the quantity in messages."""

    name: str
    size: int                       # bytes, little-endian
    signed: bool
    what: str                       # "a current", "a voltage", ...
    example: str                    # shown in hints
    parse_text: Callable[["OperandKind", str, int, int], int]
    format_raw: Callable[["OperandKind", int], str]
    names: Mapping[str, int] = field(default_factory=dict)   # symbolic values, upper-case keys
    reserved_ok: frozenset[int] = frozenset()   # raw values valid outside lo..hi (INPUT, AUTO)

    def raw_limits(self) -> tuple[int, int]:
        bits = 8 * self.size
        return (-(1 << (bits - 1)), (1 << (bits - 1)) - 1) if self.signed else (0, (1 << bits) - 1)

    def parse(self, text: str, lo: int | None = None, hi: int | None = None) -> int:
        """Text -> raw operand. Raises ValueProblem. ``lo``/``hi`` narrow the raw range."""
        key = (text, lo, hi)
        known = _PARSED.get(self.name, {}).get(key)
        if known is None:
            klo, khi = self.raw_limits()
            try:
                _refuse_long_numeral(text)
                known = self.parse_text(self, text, klo if lo is None else lo, khi if hi is None else hi)
            except ValueProblem as problem:
                known = problem
            cache = _PARSED.setdefault(self.name, {})
            if len(cache) > 10000:
                cache.clear()
            cache[key] = known
        if isinstance(known, ValueProblem):
            raise ValueProblem(known.code, known.message, known.hint, known.warning_raw)
        return known

    def format(self, raw: int) -> str:
        return self.format_raw(self, raw)

    def raw_valid(self, raw: int, lo: int | None = None, hi: int | None = None) -> bool:
        """Whether a stored value is one the charger can meet (the decoder's check)."""
        klo, khi = self.raw_limits()
        return raw in self.reserved_ok or (klo if lo is None else lo) <= raw <= (khi if hi is None else hi)

    def name_of(self, raw: int) -> str | None:
        for key, value in self.names.items():
            if value == raw:
                return key
        return None


# --- text -> raw -------------------------------------------------------------------

def _scaled_units(units: Mapping[str, tuple[Decimal, int]]):
    """Parser for a u16 value written with a unit: unit -> (multiplier to hundredths, flag)."""

    def parse(kind: OperandKind, text: str, lo: int, hi: int) -> int:
        if text.upper() == "INPUT":
            return INPUT_U16
        parsed = split_number(text)
        if parsed is None:
            raise ValueProblem("E203", _("'{text}' is not {what}").format(
                    text=text, what=_(kind.what)), _("write it like {example}").format(
                    example=_(kind.example)))
        number, unit = parsed
        if not unit:
            ways = " or ".join(f"{text}{u}" for u in units if not u.startswith("m"))
            raise ValueProblem("E201", _("{{subject}} needs a unit: {example}").format(example=_(kind.example)),
                               _("a bare {text} is never guessed: write {ways}, or INPUT").format(text=text, ways=ways))
        spelled = {u.upper(): u for u in units}
        key = spelled.get(unit.upper())
        if key is None:
            raise ValueProblem("E202", _("'{unit}' is not a unit of {what}").format(unit=unit, what=_(kind.what)),
                               f"allowed: {', '.join(units)}")
        unit = key
        mult, flag = units[key]
        if number < 0:
            raise ValueProblem("E204", _("{{subject}} cannot be negative: {text}").format(text=text))
        exact = number * mult
        raw = round_half_away(exact)
        top = 0x7FFF if not flag else 0x7FFE   # 0xFFFF with the flag set would read as INPUT
        if raw > top:
            raise ValueProblem("E204", _("{text} is too large to store").format(text=text),
                               _("at most {in_unit}{unit}").format(in_unit=_in_unit(top, mult), unit=unit))
        if raw != exact:
            raise ValueProblem(
                "W205", _("{text} is stored as {in_unit}{unit} (the charger keeps steps of {in_unit2}{unit})").format(
                        text=text, in_unit=_in_unit(raw, mult), unit=unit, in_unit2=_in_unit(1, mult)),
                _("write the stored value to make it explicit"), warning_raw=raw | flag)
        return raw | flag

    return parse


def _in_unit(raw: int, mult: Decimal) -> str:
    text = format(Decimal(raw) / mult, "f")
    return text.rstrip("0").rstrip(".") if "." in text else text


def _format_current_like(abs_unit: str, rel_unit: str):
    def fmt(kind: OperandKind, raw: int) -> str:
        if raw == INPUT_U16:
            return "INPUT"
        unit = rel_unit if raw & RELATIVE_FLAG else abs_unit
        return format_scaled(raw & 0x7FFF, 100) + unit

    return fmt


def _parse_integer(units: Mapping[str, int] | None = None):
    """Integer operand with optional unit suffixes (unit -> multiplier)."""

    units = units or {}

    def parse(kind: OperandKind, text: str, lo: int, hi: int) -> int:
        key = text.upper()
        if key in kind.names:
            return kind.names[key]
        parsed = split_number(text)
        if parsed is None:
            if kind.names:
                raise ValueProblem("E203", _("'{text}' is not {what}").format(text=text, what=_(kind.what)),
                                   _("use a number or one of {display_names}").format(
                                           display_names=', '.join(_display_names(kind))))
            raise ValueProblem("E203", _("'{text}' is not {what}").format(
                    text=text, what=_(kind.what)), _("write it like {example}").format(
                    example=_(kind.example)))
        number, unit = parsed
        if unit:
            spelled = {u.upper(): u for u in units}
            if unit.upper() not in spelled:
                if not units:
                    raise ValueProblem("E202", _("{{subject}} takes no unit: write {number}").format(number=number),
                                       _("for example {example}").format(example=_(kind.example)))
                raise ValueProblem("E202", _("'{unit}' is not a unit of {what}").format(unit=unit, what=_(kind.what)),
                                   f"allowed: {', '.join(units)}")
            mult = units[spelled[unit.upper()]]
        else:
            mult = 1
        exact = number * mult
        raw = round_half_away(exact)
        if raw < lo or raw > hi:
            raise ValueProblem("E204", _("{text} is out of range for {what}").format(text=text, what=_(kind.what)),
                               f"allowed: {_range_text(kind, lo, hi)}")
        if raw != exact:
            if mult == 1:
                raise ValueProblem("E203", _("{{subject}} must be a whole number, not {text}").format(text=text))
            raise ValueProblem("W205", _("{text} is stored as {format}").format(text=text, format=kind.format(raw)),
                               _("write the stored value to make it explicit"), warning_raw=raw)
        return raw

    return parse


def _range_text(kind: OperandKind, lo: int, hi: int) -> str:
    return f"{kind.format(lo)} to {kind.format(hi)}"


def _display_names(kind: OperandKind) -> list[str]:
    return [DISPLAY_NAMES.get(k, k) for k in kind.names]


def _format_int(kind: OperandKind, raw: int) -> str:
    return str(raw)


def _format_named(kind: OperandKind, raw: int) -> str:
    name = kind.name_of(raw)
    return DISPLAY_NAMES.get(name, name) if name else str(raw)


_TIME_UNITS = {"s": 10, "m": 600, "min": 600, "h": 36000}


def _format_time(kind: OperandKind, raw: int) -> str:
    """Largest unit that states the value exactly; bare tenths otherwise (the original's unit)."""
    if raw:
        for unit, tenths in (("h", 36000), ("min", 600), ("s", 10)):
            if raw % tenths == 0:
                return f"{raw // tenths}{unit}"
    return str(raw)


def _parse_capacity(kind: OperandKind, text: str, lo: int, hi: int) -> int:
    key = text.upper()
    if key == "INPUT":
        return CAPACITY_INPUT
    if key == "AUTO":
        return CAPACITY_AUTO
    parsed = split_number(text)
    if parsed is None:
        raise ValueProblem("E203", _("'{text}' is not a capacity").format(
                text=text), _("write it in mAh like 4200, or INPUT or AUTO"))
    number, unit = parsed
    mult = {"": 1, "MAH": 1, "AH": 1000}.get(unit.upper())
    if mult is None:
        raise ValueProblem("E202", _("'{unit}' is not a unit of capacity").format(
                unit=unit), _("write mAh (4200) or Ah (4.2Ah)"))
    exact = number * mult
    raw = round_half_away(exact)
    if raw != exact:
        raise ValueProblem("E203", _("Capacity is a whole number of mAh, not {text}").format(text=text))
    if not 1 < raw < 65535:
        raise ValueProblem("E204", _("Capacity {text} is out of range").format(
                text=text), _("allowed: 2 to 65534 mAh, INPUT or AUTO"))
    return raw


def _format_capacity(kind: OperandKind, raw: int) -> str:
    if raw == CAPACITY_INPUT:
        return "INPUT"
    if raw == CAPACITY_AUTO:
        return "AUTO"
    return str(raw)


# Canonical spelling of symbolic names (keys of ``names`` are upper case).
DISPLAY_NAMES = {
    "UNDEF": "Undef", "PB": "Pb", "NICD": "NiCd", "NIMH": "NiMh", "LIPO": "LiPo",
    "LIION": "LiIon", "LIS": "LiS", "LIFE": "LiFe", "NEW": "New",
}

AKK_TYPES = {"UNDEF": 0, "PB": 1, "NICD": 2, "NIMH": 3, "LIPO": 4, "LIION": 5, "LIS": 6, "LIFE": 7, "NEW": 8}
# The seed's table spells LiIon "Lilon" (a lower-case L); accepted, written back as LiIon.
AKK_TYPE_ALIASES = {"LILON": 5}

CURRENT = OperandKind(
    "current", 2, False, N_("a current"), N_("2A or 0.5C"),
    _scaled_units({"A": (Decimal(100), 0), "mA": (Decimal("0.1"), 0), "C": (Decimal(100), RELATIVE_FLAG)}),
    _format_current_like("A", "C"))
VOLTAGE = OperandKind(
    "voltage", 2, False, N_("a voltage"), N_("4.2V or 4.2S"),
    _scaled_units({"V": (Decimal(100), 0), "mV": (Decimal("0.1"), 0), "S": (Decimal(100), RELATIVE_FLAG)}),
    _format_current_like("V", "S"))
CAPACITY = OperandKind("capacity", 2, False, N_("a capacity"), "4200", _parse_capacity, _format_capacity,
                       reserved_ok=frozenset({CAPACITY_INPUT, CAPACITY_AUTO}))
TIME = OperandKind("time", 4, False, N_("a time"), N_("120 (tenths of a second), 12s, 30min or 2h"),
                   _parse_integer(_TIME_UNITS), _format_time)
CELSIUS = OperandKind("celsius", 1, True, N_("a temperature in °C"), "60", _parse_integer(), _format_int)
COUNT = OperandKind("count", 1, False, N_("a whole number"), "3", _parse_integer(), _format_int)
SECONDS = OperandKind("seconds", 1, False, N_("a time in seconds"), "30", _parse_integer({"s": 1}), _format_int)
AKK_TYPE = OperandKind("akk_type", 1, False, N_("a battery type"), "LiPo", _parse_integer(), _format_named,
                       names={**AKK_TYPES})
MELODY = OperandKind("melody", 1, False, N_("a melody"), "STOP", _parse_integer(), _format_named,
                     names={"START": 1, "STOP": 2, "ERROR": 3, "ATTENTION": 4})
LIGHT = OperandKind("light", 1, False, N_("a light pattern"), "FAST", _parse_integer(), _format_named,
                    names={"SLOW": 100, "FAST": 101, "ON": 102, "FAZE": 103})
MEASURE_POINT = OperandKind("measure_point", 1, False, N_("a measuring point (0, 1 or 2)"), "0",
                            _parse_integer(), _format_int)


def parse_akk_type(text: str) -> int:
    """AKK_TYPE accepts the seed's spelling 'Lilon' besides the kind's own names."""
    alias = AKK_TYPE_ALIASES.get(text.upper())
    return alias if alias is not None else AKK_TYPE.parse(text, 0, 8)
