"""Safety lint: macros that are legal but likely to hurt a battery or surprise its owner.

Each rule is a function over the checked AST that reports Findings (warnings,
or errors where a value is plainly dangerous). Limits come from the chemistry
data files (spec §5 values, resources/chemistries/*.toml), from the thesis
seed 001 (-dV needs a fast enough charge; a timer alone is no end for a fast one;
trickle at most 0.1C; a 0.1C charge takes 14-16 h; lithium charges within 0-45 °C;
NiMH is not ended by a voltage cut-off), and, when one is given, from the charger
model's limits (what it will give of a current the macro asks).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, Iterator

from . import opcodes as ops
from .ast import Cycle, Macro, Phase, Statement
from .checker import Finding
from .diagnostics import Severity
from .opcodes import Role
from .operands import DISPLAY_NAMES, INPUT_U16, RELATIVE_FLAG, TIME, relative_value
from ..i18n import _

# -dV per cell that a charger can tell from noise, and that a cell really shows (seed 001; spec §5).
DPEAK_MIN_V = 0.003
DPEAK_MAX_V = 0.02
# Slowest charge whose -dV is reliable (seed 001: NiCd from about 0.5C, NiMH from 0.2-0.3C).
DPEAK_MIN_RATE = {"NICD": 0.5, "NIMH": 0.3}
# Fastest charge (seed 001 §5.1.4: 1-4C "very fast" charging is for sintered NiCd cells; NiMH 0.5-2C).
NICKEL_MAX_RATE = {"NICD": 4.0, "NIMH": 2.0}
TIMER_ONLY_MAX_RATE = 0.2
# Seed 001 §5.1.3: a fast charge (0.5-1C) is allowed between +10 and +40 °C and is ended by
# temperature or voltage; above 2C (§5.1.4's very fast 1-4C, for sintered NiCd) with the charger's
# sensor off at start, nothing can stop a cell that overheats: refused.
NICKEL_FAST_RATE = 0.5
NICKEL_FAST_T_MAX = 40
NICKEL_NO_SENSOR_MAX_RATE = 2.0
# Seed 001 §5.1.5-5.1.6: a permanent top-up is 0.025-0.06C, at most 0.1C for cells made for it.
TRICKLE_MAX_RATE = 0.1
# Seed 001 §5.1.1, §5.3.1: the normal charge is 0.1C for 14-16 h.
NORMAL_RATE = 0.1
NORMAL_MAX_S = 16 * 3600
# Seed 001 §5.2: lithium charges between 0 and 45 °C here (the thesis: 0-50 °C, makers differ).
LITHIUM_T_MAX = 45
LITHIUM = ("LIPO", "LIION", "LIFE", "LIS")
NO_DEFAULTS = ("UNDEF", "LIS", "NEW")


@dataclass
class Context:
    macro: Macro
    chemistry: str                     # AKK_TYPE name upper case, "UNDEF" when absent
    limits: object | None              # domain.chemistry.Chemistry, None without data
    series: int | None
    capacity_mah: int | None
    charger: object | None = None      # sim.charger_model.ChargerLimits, when the charger is known
    current_a: float | None = None     # the current entered at start (for CONSTANT_I=INPUT)
    sensor: bool | None = None         # the temperature sensor at start (None: not started yet)

    @property
    def chem_name(self) -> str:
        """The chemistry as the spec spells it (NiCd, NiMh, LiPo, ...)."""
        return DISPLAY_NAMES.get(self.chemistry, self.chemistry)

    def per_cell(self, raw: int) -> float | None:
        """A stored voltage in V per cell, when it can be known before start."""
        return relative_value(raw, self.series)

    def c_rate(self, raw: int) -> float | None:
        """A stored current as a multiple of the capacity, when it can be known before start."""
        return relative_value(raw, self.capacity_mah / 1000 if self.capacity_mah else None)

    def charge_rate(self, raw: int) -> float | None:
        """``c_rate``, and for a current entered at start the value entered, when both are known."""
        if raw == INPUT_U16:
            return self.current_a * 1000 / self.capacity_mah if self.current_a and self.capacity_mah else None
        return self.c_rate(raw)

def _context(macro: Macro, charger=None, given_series: int | None = None,
             given_capacity: float | None = None, current_a: float | None = None,
             sensor: bool | None = None) -> Context:
    akk = macro.declared(ops.AKK_TYPE)
    name = ops.AKK_TYPE.operands[0].kind.name_of(akk.args[0].raw) if akk else None
    limits = None
    if name and name not in NO_DEFAULTS:
        from ..domain.chemistry import load_chemistry   # data files: resources/chemistries
        # No handler: a missing or broken data file (DataFileError) must stop the check, never
        # let it pass without the chemistry's limits.
        limits = load_chemistry(name)
    series = macro.declared(ops.SERIES)
    capacity = macro.declared(ops.CAPACITY)
    cap = capacity.args[0].raw if capacity and capacity.args[0].raw not in (0, 0xFFFF) else None
    declared = series.args[0].raw if series else None
    return Context(macro, name or "UNDEF", limits, declared or given_series, cap or given_capacity, charger,
                   current_a, sensor)


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


def _note(node, code: str, message: str, hint: str = "") -> Finding:
    """What the author should know about a value left to the start (the start check judges the
    value entered): a note, not a warning, so a generic macro is clean."""
    return Finding(node, Severity.NOTE, code, message, hint)


def rule_chemistry_declared(ctx: Context) -> Iterator[Finding]:
    akk = ctx.macro.declared(ops.AKK_TYPE)
    if akk is None:
        yield _warn("name", "W301", _("No AKK_TYPE: the charger cannot check the battery against the macro"),
                    _("declare the chemistry, e.g. AKK_TYPE=LiPo"))
    elif ctx.chemistry in NO_DEFAULTS:
        message = _("AKK_TYPE={format} has no reference limits, so nothing here is checked against the "
                    "chemistry").format(
            format=ops.AKK_TYPE.operands[0].kind.format(akk.args[0].raw))
        hint = _("give explicit voltage limits in every phase")
        yield _warn(akk, "W301", message, hint)


def rule_charge_ends_only_by_default(ctx: Context) -> Iterator[Finding]:
    for phase in _phases(ctx.macro.charge.items):
        if not any(s.op.role is Role.CONDITION for s in phase.statements):
            yield _warn(phase, "W302", _("This charge phase has no end of its own: only the charger's defaults "
                                         "(temperature, or 1.5 x the capacity without a sensor) will stop it"),
                        _("add a stop condition such as IF(V>4.2S), IF(I<0.05C) or IF(DELTA_PEAK>0.01S)"))


def _voltage_limits(ctx: Context) -> Iterator[tuple[Statement, int, str]]:
    """Every voltage a charge may reach: (statement, raw, what)."""
    for phase in _phases(ctx.macro.charge.items):
        for st in phase.statements:
            if st.op is ops.CONSTANT_V:
                yield st, st.args[0].raw, _("holds")
            elif st.op.code == 83:
                yield st, st.args[0].raw, _("charges to")
            elif st.op is ops.TRICKLE:
                yield st, st.args[2].raw, _("tops up to")


def rule_charge_voltage(ctx: Context) -> Iterator[Finding]:
    if not ctx.limits:
        return
    lim = ctx.limits
    for st, raw, what in _voltage_limits(ctx):
        v = ctx.per_cell(raw)
        if v is None:
            continue
        if v > lim.max_v + 1e-9:
            message = _("This {what} {v:.2f} V per cell: above the absolute maximum for {name}, {max_v:.2f} V").format(
                what=what, v=v, name=lim.name, max_v=lim.max_v)
            hint = _("{name} charges to {charge_end_v:.2f} V per cell").format(
                name=lim.name, charge_end_v=lim.charge_end_v)
            yield Finding(st, Severity.ERROR, "E303", message, hint)
        elif v > lim.charge_end_v + 1e-9:
            message = _("This {what} {v:.2f} V per cell, above {name}'s usual {charge_end_v:.2f} V").format(
                what=what, v=v, name=lim.name, charge_end_v=lim.charge_end_v)
            hint = _("the absolute limit is {max_v:.2f} V per cell").format(max_v=lim.max_v)
            yield _warn(st, "W303", message, hint)


def rule_discharge_voltage(ctx: Context) -> Iterator[Finding]:
    if not ctx.limits:
        return
    lim = ctx.limits
    for phase in _phases(ctx.macro.discharge.items):
        st = _code(phase, 82)
        v = ctx.per_cell(st.args[0].raw) if st else None
        if v is not None and v < lim.discharge_end_v - 1e-9:
            message = _("Discharging to {v:.2f} V per cell goes below {name}'s minimum, "
                        "{discharge_end_v:.2f} V").format(
                v=v, name=lim.name, discharge_end_v=lim.discharge_end_v)
            hint = _("write IF(V<{discharge_end_v:g}S) STOP_FAZE").format(discharge_end_v=lim.discharge_end_v)
            yield _warn(st, "W304", message, hint)


def _current_raw(st: Statement) -> int:
    """The charge current a CONSTANT_I, CHARGE_EX (its Ich) or TRICKLE statement stores."""
    return st.args[1].raw if st.op is ops.CHARGE_EX else st.args[0].raw


def rule_delta_peak(ctx: Context) -> Iterator[Finding]:
    for phase in _phases(ctx.macro.charge.items):
        st = _code(phase, 89)
        if st is None:
            continue
        v = ctx.per_cell(st.args[0].raw)
        if v is not None and not DPEAK_MIN_V <= v <= DPEAK_MAX_V:
            message = _("A -dV of {v:.0f} mV per cell is implausible: real cells dip "
                        "{dpeak_min_v:.0f}-{dpeak_max_v:.0f} mV").format(
                v=v * 1000, dpeak_min_v=DPEAK_MIN_V * 1000, dpeak_max_v=DPEAK_MAX_V * 1000)
            hint = _("NiMh about 0.005-0.01 V per cell, NiCd 0.01-0.015 V; without a real -dV the charge ends "
                     "only by a default")
            yield _warn(st, "W305", message, hint)
        min_rate = DPEAK_MIN_RATE.get(ctx.chemistry)
        current = _find(phase, ops.CONSTANT_I) or _find(phase, ops.CHARGE_EX)
        if not min_rate or current is None:
            continue
        yield from _dpeak_rate(ctx, st, _current_raw(current), min_rate)


def _dpeak_rate(ctx: Context, st: Statement, raw: int, min_rate: float) -> Iterator[Finding]:
    """W306: the -dV is unreliable below min_rate; said for a known rate, and for a current entered at
    start (or in amperes without a declared capacity) as the current where it stops being reliable."""
    name = ctx.chem_name
    hint = _("charge faster, or end by time and temperature instead")
    rate = ctx.c_rate(raw)
    if rate is not None:
        if rate < min_rate:
            yield _warn(st, "W306", _("At {rate:g}C a {name} cell shows no reliable -dV (it needs about "
                                      "{min_rate:g}C or more)").format(rate=rate, name=name, min_rate=min_rate), hint)
        return
    if raw == INPUT_U16:
        if ctx.capacity_mah:
            amps = min_rate * ctx.capacity_mah / 1000
            message = _("The current is entered at start: below {amps:.2f} A ({min_rate:g}C of the declared "
                        "{capacity_mah} mAh) a {name} cell shows no reliable -dV").format(
                amps=amps, min_rate=min_rate, capacity_mah=ctx.capacity_mah, name=name)
            yield _note(st, "W306", message, hint)
        else:
            message = _("The current is entered at start: below {min_rate:g}C ({amps:g} A for a 2000 mAh pack) a "
                        "{name} cell shows no reliable -dV; the simulator and the device panel check the values "
                        "entered").format(min_rate=min_rate, amps=min_rate * 2, name=name)
            yield _note(st, "W306", message, hint)
    elif not raw & RELATIVE_FLAG:
        amps = raw / 100
        message = _("At {amps:g} A the -dV of a {name} cell is reliable only up to {capacity:.0f} mAh "
                    "({min_rate:g}C); the capacity is not declared").format(
            amps=amps, name=name, capacity=amps / min_rate * 1000, min_rate=min_rate)
        yield _warn(st, "W306", message, hint)


def rule_nickel_rate(ctx: Context) -> Iterator[Finding]:
    top = NICKEL_MAX_RATE.get(ctx.chemistry)
    if top is None:
        return
    for phase in _phases(ctx.macro.charge.items):
        st = _charge_current(phase)
        rate = ctx.c_rate(_current_raw(st)) if st else None
        if rate is not None and rate > top:
            hint = (_("1-4C is for sintered NiCd cells made for very fast charging") if ctx.chemistry == "NICD"
                    else _("fast-charge NiMh cells take 0.5-2C"))
            message = _("Charging {chem_name} at {rate:g}C is above {top:g}C").format(
                chem_name=ctx.chem_name, rate=rate, top=top)
            yield _warn(st, "W307", message, hint)


def rule_nickel_temperature(ctx: Context) -> Iterator[Finding]:
    """W320: a fast nickel charge (0.5C or more) with no IF(T>x) of its own; E320: above 2C started with
    the sensor off (no temperature end can work then)."""
    if ctx.chemistry not in NICKEL_MAX_RATE:
        return
    for phase in _phases(ctx.macro.charge.items):
        st = _charge_current(phase)
        rate = ctx.charge_rate(_current_raw(st)) if st is not None and st.op is not ops.TRICKLE else None
        if rate is None or rate < NICKEL_FAST_RATE:
            continue
        if ctx.sensor is False and rate > NICKEL_NO_SENSOR_MAX_RATE + 1e-9:
            message = _("A {rate:g}C {chem_name} charge started with the temperature sensor off: above {top:g}C "
                        "only the battery's temperature can end it safely").format(
                rate=rate, chem_name=ctx.chem_name, top=NICKEL_NO_SENSOR_MAX_RATE)
            hint = _("connect the sensor and start with it on, or charge at {top:g}C or less").format(
                top=NICKEL_NO_SENSOR_MAX_RATE)
            yield Finding(st, Severity.ERROR, "E320", message, hint)
        elif _code(phase, 81) is None:
            message = _("This {rate:g}C {chem_name} charge has no temperature limit: a fast nickel charge that "
                        "misses its -dV overheats the cells until the charger's default stops at 60 °C").format(
                rate=rate, chem_name=ctx.chem_name)
            hint = _("add IF(T>{t_max}) STOP_FAZE; seed 001: a fast charge (0.5-1C) runs between +10 and "
                     "+{t_max} °C, ended by temperature or voltage").format(t_max=NICKEL_FAST_T_MAX)
            yield _warn(st, "W320", message, hint)


def rule_timer_only(ctx: Context) -> Iterator[Finding]:
    for phase in _phases(ctx.macro.charge.items):
        conditions = [s for s in phase.statements if s.op.role is Role.CONDITION]
        current = _find(phase, ops.CONSTANT_I)
        rate = ctx.c_rate(current.args[0].raw) if current else None
        if conditions and all(s.op.code == 88 for s in conditions) and rate is not None \
                and rate > TIMER_ONLY_MAX_RATE and not _find(phase, ops.CONSTANT_V):
            message = _("Only a timer ends this {rate:g}C charge: above {timer_only_max_rate:g}C the battery "
                        "needs a voltage, -dV or temperature end").format(
                rate=rate, timer_only_max_rate=TIMER_ONLY_MAX_RATE)
            hint = _("add IF(V>…) or IF(DELTA_PEAK>…)")
            yield _warn(conditions[0], "W308", message, hint)


def rule_bare_time(ctx: Context) -> Iterator[Finding]:
    for st in _statements(ctx.macro):
        if not st.op.condition or st.op.operands[0].kind is not TIME:
            continue
        arg = st.args[0]
        if arg.text is not None and arg.text.strip().isdigit():
            tenths = arg.raw
            human = TIME.format(tenths)
            shown = human if not human.isdigit() else f"{tenths / 10:g} s"
            message = _("A bare {text} is in tenths of a second: {shown}, not {text} seconds or minutes").format(
                text=arg.text, shown=shown)
            hint = _("write {replace} to say so, or {text}min if minutes were meant").format(
                replace=shown.replace(' ', ''), text=arg.text)
            yield _warn(arg, "W309", message, hint)


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
        message = _("Currents in C need the capacity, which is not declared: it must be entered at start")
        hint = _("declare CAPACITY=… in the introduction if it is always the same")
        yield _note(needs_capacity, "W310", message, hint)
    if needs_series is not None and ctx.series is None:
        message = _("Voltages per cell (S) need the cell count, which is not declared: it must be entered at "
                    "start")
        hint = _("declare SERIES=… if it is always the same")
        yield _note(needs_series, "W310", message, hint)


def rule_trickle_lithium(ctx: Context) -> Iterator[Finding]:
    if ctx.chemistry not in LITHIUM:
        return
    for st in _statements(ctx.macro):
        if st.op is ops.TRICKLE:
            yield Finding(st, Severity.ERROR, "E311", _("Lithium cells must never be trickle-charged"),
                          _("end the charge with CONSTANT_V and IF(I<…) instead"))


def rule_unreachable_phase(ctx: Context) -> Iterator[Finding]:
    for section, code, better in ((ctx.macro.charge, 83, lambda new, old: new <= old),
                                  (ctx.macro.discharge, 82, lambda new, old: new >= old)):
        previous = None
        for phase in _phases(section.items):
            st = _code(phase, code)
            actions = {s.op for s in phase.statements if s.op.role is Role.ACTION}
            if st and previous and actions == {ops.CONSTANT_I} and _same_unit(st, previous) \
                    and better(st.args[0].raw & 0x7FFF, previous.args[0].raw & 0x7FFF):
                message = _("This phase can never run: the phase before it already ended beyond its limit "
                            "({text})").format(text=_text(previous))
                hint = _("lower or remove one of the two limits")
                yield _warn(phase, "W312", message, hint)
            previous = st if st is not None else previous
    for st in ctx.macro.intro:
        if st.op.code == 87 and st.args[0].raw == 0:
            yield _warn(st, "W312", _("IF(tm>0) stops the macro before any phase can run"))
    for phase in _phases(ctx.macro.discharge.items + ctx.macro.charge.items):
        st = _code(phase, 88)
        if st is not None and st.args[0].raw == 0:
            yield _warn(st, "W312", _("IF(tf>0) ends this phase before it does anything"))


def _same_unit(a: Statement, b: Statement) -> bool:
    return INPUT_U16 not in (a.args[0].raw, b.args[0].raw) and \
        (a.args[0].raw & RELATIVE_FLAG) == (b.args[0].raw & RELATIVE_FLAG)


def _text(st: Statement) -> str:
    from .formatter import format_statement
    return format_statement(st)


def rule_trickle_rate(ctx: Context) -> Iterator[Finding]:
    for st in _statements(ctx.macro):
        rate = ctx.c_rate(st.args[0].raw) if st.op is ops.TRICKLE else None
        if rate is not None and rate > TRICKLE_MAX_RATE + 1e-9:
            message = _("A trickle of {rate:g}C is above {trickle_max_rate:g}C: held for long it overcharges the "
                        "cell").format(rate=rate, trickle_max_rate=TRICKLE_MAX_RATE)
            hint = _("seed 001: a permanent top-up is 0.025-0.06C, at most 0.1C for cells made for it")
            yield _warn(st, "W313", message, hint)


def rule_slow_charge_time(ctx: Context) -> Iterator[Finding]:
    if ctx.chemistry not in DPEAK_MIN_RATE:
        return
    for phase in _phases(ctx.macro.charge.items):
        current = _find(phase, ops.CONSTANT_I)
        rate = ctx.c_rate(current.args[0].raw) if current else None
        if rate is None or rate > NORMAL_RATE + 1e-9:
            continue
        timer = _code(phase, 88)
        if timer is None or timer.args[0].raw > NORMAL_MAX_S * 10:
            what = (_("its timer allows {time}").format(time=TIME.format(timer.args[0].raw)) if timer
                    else _("no timer ends it"))
            message = _("This {rate:g}C charge may run well past 16 h: {what}").format(rate=rate, what=what)
            hint = _("seed 001: a 0.1C charge takes 14-16 h; add IF(tf>16h) STOP_FAZE")
            yield _warn(timer or current, "W314", message, hint)


def rule_lithium_temperature(ctx: Context) -> Iterator[Finding]:
    if ctx.chemistry not in LITHIUM:
        return
    for phase in _phases(ctx.macro.charge.items):
        t_max = _code(phase, 81)
        if t_max is None or t_max.args[0].raw > LITHIUM_T_MAX:
            message = _("This lithium charge has no temperature limit at or below {lithium_t_max} °C: the "
                        "charger's default stops only at 60 °C").format(lithium_t_max=LITHIUM_T_MAX)
            hint = _("add IF(T>{lithium_t_max}) STOP_FAZE; lithium charges between 0 and {lithium_t_max} °C "
                     "(ZUML cannot test T<0: do not start a charge below 0 °C)").format(lithium_t_max=LITHIUM_T_MAX)
            yield _warn(t_max or phase, "W315", message, hint)


def rule_delta_peak_misplaced(ctx: Context) -> Iterator[Finding]:
    for phase in _phases(ctx.macro.discharge.items):
        st = _code(phase, 89)
        if st is not None:
            yield _warn(st, "W316", _("-dV in a discharge phase: a discharging cell shows no -dV peak, so this "
                                      "never ends the phase as meant"), _("end a discharge with IF(V<…)"))
    if ctx.chemistry in LITHIUM:
        for phase in _phases(ctx.macro.charge.items):
            st = _code(phase, 89)
            if st is not None:
                message = _("-dV on {chem_name}: lithium cells show no -dV at full charge").format(
                    chem_name=ctx.chem_name)
                hint = _("end with CONSTANT_V and IF(I<…)")
                yield _warn(st, "W316", message, hint)


def rule_nimh_voltage_only(ctx: Context) -> Iterator[Finding]:
    """W317: a NiMh charge whose only end is IF(V>x) (no -dV, temperature or timer)."""
    if ctx.chemistry != "NIMH":
        return
    for phase in _phases(ctx.macro.charge.items):
        cut_off = _code(phase, 83)
        if cut_off is not None and _charge_current(phase) is not None and not _code(phase, 89) \
                and not _code(phase, 81) and not _code(phase, 88):
            yield _warn(cut_off, "W317", _("NiMh charged to a voltage limit only: its voltage at full charge "
                                           "moves with current and temperature, so the limit ends it early or "
                                           "late"),
                        _("seed 001: end NiMh by -dV or temperature (IF(DELTA_PEAK>0.01S), IF(T>45)); keep the "
                          "voltage as a backup"))


def rule_charger_limits(ctx: Context) -> Iterator[Finding]:
    """W318: a current the charger model will not give (its A limit, or its W limit at the nominal voltage)."""
    lim = ctx.charger
    if lim is None:
        return
    nominal = ctx.limits.nominal_v * ctx.series if ctx.limits and ctx.series else None
    for section in (ctx.macro.discharge, ctx.macro.charge):
        charging = section.kind == "charge"
        max_a, max_w = (lim.max_charge_a, lim.max_charge_w) if charging else (lim.max_discharge_a, lim.max_discharge_w)
        what = "charge" if charging else "discharge"
        for phase in _phases(section.items):
            st = _charge_current(phase)
            amps = _amps(ctx, _current_raw(st)) if st else None
            if amps is None:
                continue
            if amps > max_a + 1e-9:
                message = _("The macro asks {amps:.2f} A; the {name} gives at most {max_a:g} A ({what})").format(
                    amps=amps, name=lim.name, max_a=max_a, what=what)
                hint = _("the phase runs at the charger's limit and takes longer")
                yield _warn(st, "W318", message, hint)
            elif nominal and amps * nominal > max_w + 1e-9:
                message = _("The macro asks {amps:.2f} A; at the nominal {nominal:.1f} V that is {amps2:.0f} W, "
                            "the {name} gives at most {max_w:g} W ({what}): about {max_w2:.2f} A").format(
                    amps=amps, nominal=nominal, amps2=amps * nominal, name=lim.name, max_w=max_w, what=what,
                    max_w2=max_w / nominal)
                hint = _("the phase runs at the charger's limit and takes longer")
                yield _warn(st, "W318", message, hint)


def rule_pack_voltage_without_balancer(ctx: Context) -> Iterator[Finding]:
    """W319: a lithium charge of more than one cell (or a cell count entered at start) that ends on the pack's
    voltage (CONSTANT_V, IF(V>x)) on a charger model without a balancer: no cell is watched on its own."""
    lim = ctx.charger
    if lim is None or getattr(lim, "balancer", None) is not None or ctx.chemistry not in LITHIUM \
            or ctx.series == 1:
        return
    for phase in _phases(ctx.macro.charge.items):
        st = _find(phase, ops.CONSTANT_V) or _code(phase, 83)
        if st is not None:
            message = _("This {chem_name} charge of more than one cell ends on the pack's voltage, and the {name} "
                        "has no balancer: a weak cell can pass its limit while the pack is below its own").format(
                chem_name=ctx.chem_name, name=lim.name)
            hint = _("charge on a balancing charger, or keep the pack balanced and its end voltage below the "
                     "chemistry's usual end")
            yield _warn(st, "W319", message, hint)
            return


def _amps(ctx: Context, raw: int) -> float | None:
    if raw == INPUT_U16:
        return None
    if raw & RELATIVE_FLAG:
        return ctx.c_rate(raw) * ctx.capacity_mah / 1000 if ctx.capacity_mah else None
    return raw / 100


RULES: tuple[Rule, ...] = (
    rule_chemistry_declared, rule_charge_ends_only_by_default, rule_charge_voltage, rule_discharge_voltage,
    rule_delta_peak, rule_nickel_rate, rule_nickel_temperature, rule_timer_only, rule_bare_time, rule_relative_units_at_start,
    rule_trickle_lithium, rule_unreachable_phase, rule_trickle_rate, rule_slow_charge_time,
    rule_lithium_temperature, rule_delta_peak_misplaced, rule_nimh_voltage_only, rule_charger_limits,
    rule_pack_voltage_without_balancer,
)


def lint(macro: Macro, charger=None, *, series: int | None = None, capacity_mah: float | None = None,
         current_a: float | None = None, sensor: bool | None = None) -> list[Finding]:
    """``charger``: the charger model's ``ChargerLimits`` when known (adds W318 and W319). ``series``,
    ``capacity_mah``, ``current_a`` and ``sensor``: values entered at start, for what the macro leaves
    open (``sensor`` None: not a start; False adds E320)."""
    ctx = _context(macro, charger, series, capacity_mah, current_a, sensor)
    return [finding for rule in RULES for finding in rule(ctx)]
