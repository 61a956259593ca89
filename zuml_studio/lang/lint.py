"""Safety lint: macros that are legal but likely to hurt a battery or surprise its owner.

Each rule is a function over the checked AST that reports Findings (warnings,
or errors where a value is plainly dangerous). Limits come from the chemistry
data files (spec §5 values, resources/chemistries/*.toml) and from the thesis
seed 001 (-dV needs a fast enough charge; a timer alone is no end for a fast one).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Iterator

from . import opcodes as ops
from .ast import Cycle, Macro, Phase, Statement
from .checker import Finding
from .diagnostics import Severity
from .opcodes import Role
from .operands import INPUT_U16, RELATIVE_FLAG, TIME, relative_value

# -dV per cell that a charger can tell from noise, and that a cell really shows (seed 001; spec §5).
DPEAK_MIN_V = 0.003
DPEAK_MAX_V = 0.02
# Slowest charge whose -dV is reliable (seed 001: NiCd from about 0.5C, NiMH from 0.2-0.3C).
DPEAK_MIN_RATE = {"NICD": 0.5, "NIMH": 0.3}
NICKEL_MAX_RATE = 2.0
TIMER_ONLY_MAX_RATE = 0.2
LITHIUM = ("LIPO", "LIION", "LIFE", "LIS")
NO_DEFAULTS = ("UNDEF", "LIS", "NEW")


@dataclass
class Context:
    macro: Macro
    chemistry: str                     # AKK_TYPE name upper case, "UNDEF" when absent
    limits: object | None              # sim.chemistry.Chemistry, None without data
    series: int | None
    capacity_mah: int | None

    def per_cell(self, raw: int) -> float | None:
        """A stored voltage in V per cell, when it can be known before start."""
        return relative_value(raw, self.series)

    def c_rate(self, raw: int) -> float | None:
        """A stored current as a multiple of the capacity, when it can be known before start."""
        return relative_value(raw, self.capacity_mah / 1000 if self.capacity_mah else None)

def _context(macro: Macro, given_series: int | None, given_capacity: float | None) -> Context:
    akk = macro.declared(ops.AKK_TYPE)
    name = ops.AKK_TYPE.operands[0].kind.name_of(akk.args[0].raw) if akk else None
    limits = None
    if name and name not in NO_DEFAULTS:
        from ..sim.chemistry import load_chemistry   # data files: resources/chemistries
        try:
            limits = load_chemistry(name)
        except (KeyError, OSError, ValueError):
            limits = None
    series = macro.declared(ops.SERIES)
    capacity = macro.declared(ops.CAPACITY)
    cap = capacity.args[0].raw if capacity and capacity.args[0].raw not in (0, 0xFFFF) else None
    declared = series.args[0].raw if series else None
    return Context(macro, name or "UNDEF", limits, declared or given_series, cap or given_capacity)


def _phases(items) -> Iterator[Phase]:
    for item in items:
        if isinstance(item, Phase):
            yield item
        elif isinstance(item, Cycle):
            yield from _phases(item.items)


def _statements(macro: Macro) -> Iterator[Statement]:
    yield from macro.intro
    for section in macro.sections():
        for item in section.items:
            if isinstance(item, Phase):
                yield from item.statements
            elif isinstance(item, Cycle):
                for phase in _phases(item.items):
                    yield from phase.statements
            else:
                yield item
    yield from macro.conclusion


def _find(phase: Phase, op: ops.Op) -> Statement | None:
    return next((s for s in phase.statements if s.op is op), None)


def _code(phase: Phase, code: int) -> Statement | None:
    return next((s for s in phase.statements if s.op.code == code), None)


def _charge_current(phase: Phase) -> Statement | None:
    return _find(phase, ops.CONSTANT_I) or _find(phase, ops.CHARGE_EX) or _find(phase, ops.TRICKLE)


Rule = Callable[[Context], Iterator[Finding]]


def _warn(node, code: str, message: str, hint: str = "") -> Finding:
    return Finding(node, Severity.WARNING, code, message, hint)


def rule_chemistry_declared(ctx: Context) -> Iterator[Finding]:
    akk = ctx.macro.declared(ops.AKK_TYPE)
    if akk is None:
        yield _warn("name", "W301", "No AKK_TYPE: the charger cannot check the battery against the macro",
                    "declare the chemistry, e.g. AKK_TYPE=LiPo")
    elif ctx.chemistry in NO_DEFAULTS:
        yield _warn(akk, "W301", f"AKK_TYPE={ops.AKK_TYPE.operands[0].kind.format(akk.args[0].raw)} has no "
                    "reference limits, so nothing here is checked against the chemistry",
                    "give explicit voltage limits in every phase")


def rule_charge_ends_only_by_default(ctx: Context) -> Iterator[Finding]:
    for phase in _phases(ctx.macro.charge.items):
        if not any(s.op.role is Role.CONDITION for s in phase.statements):
            yield _warn(phase, "W302", "This charge phase has no end of its own: only the charger's defaults "
                        "(temperature, or 1.5 x the capacity without a sensor) will stop it",
                        "add a stop condition such as IF(V>4.2S), IF(I<0.05C) or IF(DELTA_PEAK>0.01S)")


def _voltage_limits(ctx: Context) -> Iterator[tuple[Statement, int, str]]:
    """Every voltage a charge may reach: (statement, raw, what)."""
    for phase in _phases(ctx.macro.charge.items):
        for st in phase.statements:
            if st.op is ops.CONSTANT_V:
                yield st, st.args[0].raw, "holds"
            elif st.op.code == 83:
                yield st, st.args[0].raw, "charges to"
            elif st.op is ops.TRICKLE:
                yield st, st.args[2].raw, "tops up to"


def rule_charge_voltage(ctx: Context) -> Iterator[Finding]:
    if not ctx.limits:
        return
    lim = ctx.limits
    for st, raw, what in _voltage_limits(ctx):
        v = ctx.per_cell(raw)
        if v is None:
            continue
        if v > lim.max_v + 1e-9:
            yield Finding(st, Severity.ERROR, "E303", f"This {what} {v:.2f} V per cell: above the absolute "
                          f"maximum for {lim.name}, {lim.max_v:.2f} V", f"{lim.name} charges to "
                          f"{lim.charge_end_v:.2f} V per cell")
        elif v > lim.charge_end_v + 1e-9:
            yield _warn(st, "W303", f"This {what} {v:.2f} V per cell, above {lim.name}'s usual "
                        f"{lim.charge_end_v:.2f} V", f"the absolute limit is {lim.max_v:.2f} V per cell")


def rule_discharge_voltage(ctx: Context) -> Iterator[Finding]:
    if not ctx.limits:
        return
    lim = ctx.limits
    for phase in _phases(ctx.macro.discharge.items):
        st = _code(phase, 82)
        v = ctx.per_cell(st.args[0].raw) if st else None
        if v is not None and v < lim.discharge_end_v - 1e-9:
            yield _warn(st, "W304", f"Discharging to {v:.2f} V per cell goes below {lim.name}'s minimum, "
                        f"{lim.discharge_end_v:.2f} V", f"write IF(V<{lim.discharge_end_v:g}S) STOP_FAZE")


def rule_delta_peak(ctx: Context) -> Iterator[Finding]:
    for phase in _phases(ctx.macro.charge.items):
        st = _code(phase, 89)
        if st is None:
            continue
        v = ctx.per_cell(st.args[0].raw)
        if v is not None and not DPEAK_MIN_V <= v <= DPEAK_MAX_V:
            yield _warn(st, "W305", f"A -dV of {v * 1000:.0f} mV per cell is implausible: real cells dip "
                        f"{DPEAK_MIN_V * 1000:.0f}-{DPEAK_MAX_V * 1000:.0f} mV", "NiMH about 0.005-0.01 V per "
                        "cell, NiCd 0.01-0.015 V; without a real -dV the charge ends only by a default")
        min_rate = DPEAK_MIN_RATE.get(ctx.chemistry)
        current = _find(phase, ops.CONSTANT_I)
        rate = ctx.c_rate(current.args[0].raw) if current else None
        if min_rate and rate is not None and rate < min_rate:
            yield _warn(st, "W306", f"At {rate:g}C a {ctx.chemistry.title()} cell shows no reliable -dV "
                        f"(it needs about {min_rate:g}C or more)", "charge faster, or end by time and "
                        "temperature instead")


def rule_nickel_rate(ctx: Context) -> Iterator[Finding]:
    if ctx.chemistry not in DPEAK_MIN_RATE:
        return
    for phase in _phases(ctx.macro.charge.items):
        st = _charge_current(phase)
        rate = ctx.c_rate(st.args[0].raw if st.op is not ops.CHARGE_EX else st.args[1].raw) if st else None
        if rate is not None and rate > NICKEL_MAX_RATE:
            yield _warn(st, "W307", f"Charging {ctx.chemistry.title()} at {rate:g}C is above "
                        f"{NICKEL_MAX_RATE:g}C", "fast-charge cells take 1-2C at most")


def rule_timer_only(ctx: Context) -> Iterator[Finding]:
    for phase in _phases(ctx.macro.charge.items):
        conditions = [s for s in phase.statements if s.op.role is Role.CONDITION]
        current = _find(phase, ops.CONSTANT_I)
        rate = ctx.c_rate(current.args[0].raw) if current else None
        if conditions and all(s.op.code == 88 for s in conditions) and rate is not None \
                and rate > TIMER_ONLY_MAX_RATE and not _find(phase, ops.CONSTANT_V):
            yield _warn(conditions[0], "W308", f"Only a timer ends this {rate:g}C charge: above "
                        f"{TIMER_ONLY_MAX_RATE:g}C the battery needs a voltage, -dV or temperature end",
                        "add IF(V>…) or IF(DELTA_PEAK>…)")


def rule_bare_time(ctx: Context) -> Iterator[Finding]:
    for st in _statements(ctx.macro):
        if not st.op.condition or st.op.operands[0].kind is not TIME:
            continue
        arg = st.args[0]
        if arg.text is not None and arg.text.strip().isdigit():
            tenths = arg.raw
            human = TIME.format(tenths)
            shown = human if not human.isdigit() else f"{tenths / 10:g} s"
            yield _warn(arg, "W309", f"A bare {arg.text} is in tenths of a second: {shown}, not "
                        f"{arg.text} seconds or minutes", f"write {shown.replace(' ', '')} to say so, "
                        f"or {arg.text}min if minutes were meant")


def rule_relative_units_at_start(ctx: Context) -> Iterator[Finding]:
    needs_capacity = needs_series = None
    for st in _statements(ctx.macro):
        for operand, arg in zip(st.op.operands, st.args):
            if arg.raw != INPUT_U16 and arg.raw & RELATIVE_FLAG:
                if operand.kind.name == "current" and needs_capacity is None:
                    needs_capacity = st
                elif operand.kind.name == "voltage" and needs_series is None:
                    needs_series = st
    if needs_capacity is not None and ctx.capacity_mah is None:
        yield _warn(needs_capacity, "W310", "Currents in C need the capacity, which is not declared: it must "
                    "be entered at start", "declare CAPACITY=… in the introduction if it is always the same")
    if needs_series is not None and ctx.series is None:
        yield _warn(needs_series, "W310", "Voltages per cell (S) need the cell count, which is not declared: "
                    "it must be entered at start", "declare SERIES=… if it is always the same")


def rule_trickle_lithium(ctx: Context) -> Iterator[Finding]:
    if ctx.chemistry not in LITHIUM:
        return
    for st in _statements(ctx.macro):
        if st.op is ops.TRICKLE:
            yield Finding(st, Severity.ERROR, "E311", "Lithium cells must never be trickle-charged",
                          "end the charge with CONSTANT_V and IF(I<…) instead")


def rule_unreachable_phase(ctx: Context) -> Iterator[Finding]:
    for section, code, better in ((ctx.macro.charge, 83, lambda new, old: new <= old),
                                  (ctx.macro.discharge, 82, lambda new, old: new >= old)):
        previous = None
        for phase in _phases(section.items):
            st = _code(phase, code)
            actions = {s.op for s in phase.statements if s.op.role is Role.ACTION}
            if st and previous and actions == {ops.CONSTANT_I} and _same_unit(st, previous) \
                    and better(st.args[0].raw & 0x7FFF, previous.args[0].raw & 0x7FFF):
                yield _warn(phase, "W312", "This phase can never run: the phase before it already ended beyond "
                            f"its limit ({_text(previous)})", "lower or remove one of the two limits")
            previous = st if st is not None else previous
    for st in ctx.macro.intro:
        if st.op.code == 87 and st.args[0].raw == 0:
            yield _warn(st, "W312", "IF(tm>0) stops the macro before any phase can run")
    for phase in _phases(ctx.macro.discharge.items + ctx.macro.charge.items):
        st = _code(phase, 88)
        if st is not None and st.args[0].raw == 0:
            yield _warn(st, "W312", "IF(tf>0) ends this phase before it does anything")


def _same_unit(a: Statement, b: Statement) -> bool:
    return INPUT_U16 not in (a.args[0].raw, b.args[0].raw) and \
        (a.args[0].raw & RELATIVE_FLAG) == (b.args[0].raw & RELATIVE_FLAG)


def _text(st: Statement) -> str:
    from .formatter import format_statement
    return format_statement(st)


RULES: tuple[Rule, ...] = (
    rule_chemistry_declared, rule_charge_ends_only_by_default, rule_charge_voltage, rule_discharge_voltage,
    rule_delta_peak, rule_nickel_rate, rule_timer_only, rule_bare_time, rule_relative_units_at_start,
    rule_trickle_lithium, rule_unreachable_phase,
)


def lint(macro: Macro, *, series: int | None = None, capacity_mah: float | None = None) -> list[Finding]:
    """``series`` and ``capacity_mah``: values entered at start, for what the macro leaves open."""
    ctx = _context(macro, series, capacity_mah)
    return [finding for rule in RULES for finding in rule(ctx)]
