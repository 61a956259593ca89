"""The one table of ZUML 2.0 commands (docs/zuml-2.0.md §1, "Commands and their codes").

The parser, checker, encoder, decoder, listing, interpreter, highlighter, linter
and the generated docs all read this table; nothing else lists opcodes.
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache
from enum import Enum

from . import operands as k
from ..i18n import N_, _


class Form(Enum):
    """How a command is written in text."""

    KEYWORD = "keyword"        # FAZE
    ASSIGN = "assign"          # CONSTANT_I=1C
    CALL = "call"              # CHARGE_EX(30, 1C, 1, 0.1C)
    CONDITION = "condition"    # IF(V>4.1S) STOP_FAZE


class Role(Enum):
    STRUCTURE = "structure"
    DECLARATION = "declaration"
    ACTION = "action"
    CONDITION = "condition"
    COMMAND = "command"


class Place(Enum):
    """Where a statement may stand."""

    INTRO = N_("the introduction")
    PHASE = N_("a phase (FAZE … END_FAZE)")
    BETWEEN = N_("a section between phases")
    SECTIONS = N_("the gap between the two sections")
    CONCLUSION = N_("the conclusion")


@dataclass(frozen=True)
class Operand:
    name: str
    kind: k.OperandKind
    lo: int | None = None          # narrower raw range than the kind's
    hi: int | None = None
    default: int | None = None     # optional in text when set; always stored


@dataclass(frozen=True)
class Condition:
    variables: tuple[str, ...]     # accepted spellings, first is canonical
    case_sensitive: bool
    comparison: str                # ">" or "<"
    outcome: str                   # STOP_FAZE, PAUSE_MACRO, CONTINUE_MACRO, STOP_MACRO
    also_accepts: tuple[str, ...] = ()   # other comparison signs read as this one (seed: DELTA_PEAK=)


@dataclass(frozen=True, eq=False)   # singletons: identity is equality
class Op:
    code: int
    keyword: str
    mnemonic: str
    form: Form
    role: Role
    operands: tuple[Operand, ...]
    places: frozenset[Place]
    help_text: str                 # English, marked for the catalogue; `help` is it translated
    condition: Condition | None = None
    emitted: bool = True           # MACRO (code 1) is reserved, never in byte code

    @property
    def help(self) -> str:
        """What the command does, in the installed language (hover, completion, F1 help, tooltips)."""
        return _(self.help_text)

    @property
    def size(self) -> int:
        return 1 + sum(o.kind.size for o in self.operands)

    def signature(self) -> str:
        """How the command is written, for help and completion."""
        if self.condition:
            c = self.condition
            return f"IF({c.variables[0]}{c.comparison}x) {c.outcome}"
        names = ", ".join(o.name if o.default is None else f"[{o.name}]" for o in self.operands)
        if self.form is Form.ASSIGN:
            return f"{self.keyword}={names}"
        if self.form is Form.CALL:
            return f"{self.keyword}({names})"
        return self.keyword


_IN_PHASE = frozenset({Place.PHASE})
_INTRO = frozenset({Place.INTRO})
_BETWEEN = frozenset({Place.BETWEEN, Place.SECTIONS, Place.CONCLUSION})
_NOWHERE: frozenset[Place] = frozenset()


def _cond(code: int, var: tuple[str, ...], cs: bool, cmp: str, outcome: str, kind: k.OperandKind,
          places: frozenset[Place], help: str, mnemonic: str, also: tuple[str, ...] = ()) -> Op:
    return Op(code, "IF", mnemonic, Form.CONDITION, Role.CONDITION, (Operand("x", kind),), places, help,
              Condition(var, cs, cmp, outcome, also))


OPCODES: tuple[Op, ...] = (
    Op(1, "MACRO", "MACRO", Form.KEYWORD, Role.STRUCTURE, (), _NOWHERE,
       N_("Header: MACRO name (or MACRO(name)). The name, at most 16 characters, names the file "
       "and is shown in the charger's menu. Reserved code, never stored."), emitted=False),
    Op(2, "END_MACRO", "END_MACRO", Form.KEYWORD, Role.STRUCTURE, (), _NOWHERE,
       N_("End of the macro; stored as the last command.")),
    Op(3, "DISCHARGE_SECTION", "DISCHARGE_SECTION", Form.KEYWORD, Role.STRUCTURE, (), _NOWHERE,
       N_("Discharge section, always first. Empty or absent: discharge at 0.1 A to the chemistry's end voltage.")),
    Op(4, "CHARGE_SECTION", "CHARGE_SECTION", Form.KEYWORD, Role.STRUCTURE, (), _NOWHERE,
       N_("Charge section, always after the discharge section.")),
    Op(5, "END_SECTION", "END_SECTION", Form.KEYWORD, Role.STRUCTURE, (), _NOWHERE,
       N_("Closes a discharge or charge section.")),
    Op(6, "CYCLE", "CYCLE", Form.CALL, Role.STRUCTURE, (Operand("n", k.COUNT, 1, 255),), _NOWHERE,
       N_("Repeats the phases up to END_CYCLE n times (1..255). Cycles do not nest.")),
    Op(7, "END_CYCLE", "END_CYCLE", Form.KEYWORD, Role.STRUCTURE, (), _NOWHERE,
       N_("End of a cycle: counts down and repeats while non-zero.")),
    Op(8, "FAZE", "FAZE", Form.KEYWORD, Role.STRUCTURE, (), _NOWHERE,
       N_("Start of a phase: one action held until a stop condition holds.")),
    Op(9, "END_FAZE", "END_FAZE", Form.KEYWORD, Role.STRUCTURE, (), _NOWHERE,
       N_("End of a phase.")),
    Op(20, "START_SHABLON", "START_SHABLON", Form.ASSIGN, Role.DECLARATION, (Operand("n", k.COUNT),), _INTRO,
       N_("Run start template n when the macro starts.")),
    Op(21, "AKK_TYPE", "AKK_TYPE", Form.ASSIGN, Role.DECLARATION, (Operand("type", k.AKK_TYPE, 0, 8),), _INTRO,
       N_("Battery type: Undef, Pb, NiCd, NiMh, LiPo, LiIon, LiS, LiFe, New (or 0..8).")),
    Op(22, "SERIES", "SERIES", Form.ASSIGN, Role.DECLARATION, (Operand("cells", k.COUNT, 1, 255),), _INTRO,
       N_("Cells in series. Needed by voltages per cell (S) unless entered at start.")),
    Op(23, "CAPACITY", "CAPACITY", Form.ASSIGN, Role.DECLARATION, (Operand("mAh", k.CAPACITY, 2, 65534),), _INTRO,
       N_("Capacity of each cell in mAh (2..65534), INPUT (entered at start) or AUTO. Needed by currents in C.")),
    Op(60, "CONSTANT_I", "CONSTANT_I", Form.ASSIGN, Role.ACTION, (Operand("I", k.CURRENT),), _IN_PHASE,
       N_("Hold the current: 2A, 0.5C (times the capacity) or INPUT (entered at start). "
       "With CONSTANT_V in the same phase: CC-CV.")),
    Op(61, "CONSTANT_V", "CONSTANT_V", Form.ASSIGN, Role.ACTION, (Operand("V", k.VOLTAGE),), _IN_PHASE,
       N_("Hold the voltage: 12.6V for the pack, 4.2S per cell, or INPUT. The current is limited to the "
       "charge current entered at start, else to the charger's limit.")),
    Op(62, "CHARGE_EX", "CHARGE_EX", Form.CALL, Role.ACTION,
       (Operand("tch", k.SECONDS, 1, 255), Operand("Ich", k.CURRENT), Operand("tdis", k.SECONDS, 0, 255),
        Operand("Idis", k.CURRENT), Operand("tV", k.MEASURE_POINT, 0, 2, default=0)), _IN_PHASE,
       N_("Pulse charge: tch seconds at Ich, tdis seconds of discharge at Idis, then measure the voltage "
       "(tV: 0 power stage off, 1 end of the charge pulse, 2 end of the discharge pulse).")),
    Op(63, "TRICKLE", "TRICKLE", Form.CALL, Role.ACTION,
       (Operand("I", k.CURRENT), Operand("V1", k.VOLTAGE), Operand("V2", k.VOLTAGE)), _IN_PHASE,
       N_("Top-up: charge at I when the voltage falls to V1, switch off at V2.")),
    _cond(81, ("T",), True, ">", "STOP_FAZE", k.CELSIUS, _IN_PHASE,
          N_("End the phase when the battery temperature (°C) rises above x."), "IF_T_GT"),
    _cond(82, ("V",), False, "<", "STOP_FAZE", k.VOLTAGE, _IN_PHASE,
          N_("End the phase when the battery voltage falls below x."), "IF_V_LT"),
    _cond(83, ("V",), False, ">", "STOP_FAZE", k.VOLTAGE, _IN_PHASE,
          N_("End the phase when the battery voltage rises above x."), "IF_V_GT"),
    _cond(84, ("I",), False, "<", "STOP_FAZE", k.CURRENT, _IN_PHASE,
          N_("End the phase when the current falls below x (the end of a CV phase)."), "IF_I_LT"),
    _cond(85, ("Tc",), True, ">", "PAUSE_MACRO", k.CELSIUS, _INTRO,
          N_("Pause the macro when the power stage's heat-sink (°C) is above x."), "IF_TC_GT"),
    _cond(86, ("Tc",), True, "<", "CONTINUE_MACRO", k.CELSIUS, _INTRO,
          N_("Continue a paused macro once the heat-sink (°C) is below x."), "IF_TC_LT"),
    _cond(87, ("tm",), True, ">", "STOP_MACRO", k.TIME, _INTRO,
          N_("Stop the macro when it has run longer than x (tenths of a second, or 12s, 30min, 2h)."), "IF_TM_GT"),
    _cond(88, ("tf", "t"), True, ">", "STOP_FAZE", k.TIME, _IN_PHASE,
          N_("End the phase when it has run longer than x (tenths of a second, or 12s, 30min, 2h)."), "IF_TF_GT"),
    _cond(89, ("DELTA_PEAK",), False, ">", "STOP_FAZE", k.VOLTAGE, _IN_PHASE,
          N_("End the phase when the voltage has fallen x below its peak in this phase (-dV)."),
          "IF_DPEAK_GT", also=("=",)),
    Op(100, "MUSIC", "MUSIC", Form.CALL, Role.COMMAND, (Operand("n", k.MELODY, 1, 255),), _BETWEEN,
       N_("Play melody n once: START, STOP, ERROR, ATTENTION or a number.")),
    Op(101, "LIGHT", "LIGHT", Form.CALL, Role.COMMAND, (Operand("n", k.LIGHT, 1, 103),), _BETWEEN,
       N_("LED: n short blinks then a pause (1..99); SLOW, FAST, ON, or FAZE (blink the phase number).")),
)

BY_CODE: dict[int, Op] = {op.code: op for op in OPCODES}
BY_KEYWORD: dict[str, Op] = {op.keyword: op for op in OPCODES if op.form is not Form.CONDITION}
CONDITIONS: tuple[Op, ...] = tuple(op for op in OPCODES if op.condition)
ACTIONS: tuple[Op, ...] = tuple(op for op in OPCODES if op.role is Role.ACTION)
CONDITION_OUTCOMES: frozenset[str] = frozenset(op.condition.outcome for op in CONDITIONS)

MACRO, END_MACRO, DISCHARGE_SECTION, CHARGE_SECTION, END_SECTION = (BY_CODE[c] for c in (1, 2, 3, 4, 5))
CYCLE, END_CYCLE, FAZE, END_FAZE = (BY_CODE[c] for c in (6, 7, 8, 9))
CONSTANT_I, CONSTANT_V, CHARGE_EX, TRICKLE = (BY_CODE[c] for c in (60, 61, 62, 63))
START_SHABLON, AKK_TYPE, SERIES, CAPACITY = BY_CODE[20], BY_CODE[21], BY_CODE[22], BY_CODE[23]
IF_T_GT, IF_V_LT, IF_V_GT, IF_I_LT, IF_TC_GT, IF_TC_LT, IF_TM_GT, IF_TF_GT, IF_DPEAK_GT = (
    BY_CODE[c] for c in range(81, 90))
MUSIC, LIGHT = BY_CODE[100], BY_CODE[101]


@lru_cache(maxsize=1)
def condition_variables() -> dict[str, tuple[Op, ...]]:
    """Spelling (as written for case-sensitive ones, upper case otherwise) -> conditions on it."""
    table: dict[str, list[Op]] = {}
    for op in CONDITIONS:
        for var in op.condition.variables:
            key = var if op.condition.case_sensitive else var.upper()
            table.setdefault(key, []).append(op)
    return {key: tuple(ops) for key, ops in table.items()}


def find_condition(variable: str) -> tuple[Op, ...]:
    """Conditions on ``variable`` as written: T, t, Tc, tm, tf are case-sensitive; V, I, DELTA_PEAK not."""
    table = condition_variables()
    return table.get(variable) or table.get(variable.upper(), ())


def canonical_text(op: Op, args: list[str]) -> str:
    """One statement in canonical text, from already formatted operand texts."""
    if op.condition:
        c = op.condition
        return f"IF({c.variables[0]}{c.comparison}{args[0]}) {c.outcome}"
    if op.form is Form.ASSIGN:
        return f"{op.keyword}={args[0]}"
    if op.form is Form.CALL:
        return f"{op.keyword}({', '.join(args)})"
    return op.keyword
