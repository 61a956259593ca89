"""Hypothesis strategies: random valid macros built from the opcode table."""
from functools import cache

from hypothesis import strategies as st

from zuml_studio.lang import opcodes as ops
from zuml_studio.lang.ast import Arg, Cycle, Macro, Phase, Section, Statement
from zuml_studio.lang.opcodes import Place, Role
from zuml_studio.lang.operands import INPUT_U16, RELATIVE_FLAG

NAME_CHARS = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789_-+.#"


def raw_for(operand: ops.Operand):
    kind = operand.kind
    lo, hi = kind.raw_limits()
    lo = lo if operand.lo is None else operand.lo
    hi = hi if operand.hi is None else operand.hi
    values = st.integers(lo, hi)
    if kind.reserved_ok:
        values = values | st.sampled_from(sorted(kind.reserved_ok))
    return values


@cache
def statement(op: ops.Op):
    return st.tuples(*(raw_for(o) for o in op.operands)).map(
        lambda raws: Statement(op, [Arg(r) for r in raws])).filter(_trickle_ok)


def _trickle_ok(s: Statement) -> bool:
    if s.op is not ops.TRICKLE:
        return True
    _, v1, v2 = s.raws()
    return INPUT_U16 in (v1, v2) or (v1 & RELATIVE_FLAG) != (v2 & RELATIVE_FLAG) or v1 < v2


def ops_in(place: Place, role: Role | None = None):
    return [op for op in ops.OPCODES if place in op.places and (role is None or op.role is role)]


# The strategies below are made once, not at every draw (the same examples, found in half the time).
phase_actions = st.sampled_from(ops_in(Place.PHASE, Role.ACTION)).flatmap(statement)
phase_conditions = st.lists(st.sampled_from(ops_in(Place.PHASE, Role.CONDITION)), max_size=3, unique=True)


@cache
@st.composite
def phases(draw):
    if draw(st.booleans()):
        actions = [draw(statement(ops.CONSTANT_I)), draw(statement(ops.CONSTANT_V))]
    else:
        actions = [draw(phase_actions)]
    body = actions + [draw(statement(op)) for op in draw(phase_conditions)]
    return Phase(draw(st.permutations(body)))


commands = st.sampled_from(ops_in(Place.BETWEEN)).flatmap(statement)
cycle_items = st.lists(phases() | commands, min_size=1, max_size=2)


@cache
@st.composite
def cycles(draw):
    return Cycle(Arg(draw(st.integers(1, 255))), draw(cycle_items))


section_items = st.lists(phases() | cycles() | commands, max_size=3)


@cache
@st.composite
def sections(draw, kind):
    items = draw(section_items)
    return Section(kind, items, present=bool(items) or draw(st.booleans()))


intro_ops = st.lists(st.sampled_from(ops_in(Place.INTRO)), max_size=4, unique=True)
names = st.text(NAME_CHARS, min_size=1, max_size=16)
few_commands = st.lists(commands, max_size=2)


@cache
@st.composite
def macros(draw):
    intro = draw(intro_ops)
    name = draw(names)
    return Macro(name, [draw(statement(op)) for op in intro], draw(sections("discharge")), draw(sections("charge")),
                 draw(few_commands), between=draw(few_commands))
