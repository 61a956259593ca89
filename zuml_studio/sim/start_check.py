"""Warnings about the values entered at start, before a run: what the lint could not know while
they were INPUT (seed 001: the -dV of a nickel charge shows only from 0.3C/0.5C; the charger's
limits cut a current that is too large). The simulator panel, ``zuml simulate`` and the device
panel show them; none stops a start."""
from __future__ import annotations

from ..domain.units import MAH_PER_AH
from ..lang import opcodes as ops
from ..lang.lint import DPEAK_MIN_RATE
from ..lang.operands import DISPLAY_NAMES, absolute_value
from .charger_model import ChargerLimits
from .interpreter import AKK_NAMES, StartParams, with_template
from .program import PhaseCode, Program
from ..i18n import _


def start_warnings(record: bytes, params: StartParams, charger: ChargerLimits | None = None,
                   templates=None) -> list[str]:
    """One sentence per finding, in the order the phases run. A record that does not decode, or a
    value that cannot be resolved, gives no warning here (the start itself reports it)."""
    try:
        program = Program(record)
        params = with_template(program, params, templates)
    except Exception:   # noqa: BLE001 - a start that cannot happen is reported by the start
        return []
    capacity_ah = program.intro.capacity_ah(params.capacity_mah)
    akk = AKK_NAMES.get(program.intro.declarations.get(ops.AKK_TYPE.code, 0), "UNDEF")
    min_rate = DPEAK_MIN_RATE.get(akk)
    out: list[str] = []
    for step in program.steps(params.task):
        if not isinstance(step, PhaseCode):
            continue
        by_op = {a.op: a for a in step.actions}
        where = (_("charge phase {index}") if step.section == "charge"
                 else _("discharge phase {index}")).format(index=step.index)
        if ops.CHARGE_EX in by_op:
            raw = by_op[ops.CHARGE_EX].raws[1]
        elif ops.CONSTANT_I in by_op:
            raw = by_op[ops.CONSTANT_I].raws[0]
        else:
            continue
        amps = absolute_value(raw, params.current_a, capacity_ah)
        if amps is None:
            continue
        charging = step.section == "charge" or ops.CHARGE_EX in by_op
        has_dpeak = any(c.op is ops.IF_DPEAK_GT for c in step.conditions)
        if charging and has_dpeak and min_rate and capacity_ah and amps / capacity_ah < min_rate - 1e-9:
            out.append(_("{where}: {amps:.2f} A is {rate:.2f}C of {capacity:g} mAh; {chemistry} shows no reliable -dV "
                         "below {min_rate:g}C ({min_amps:.2f} A): a timer or a default will end this charge").format(
                where=where, amps=amps, rate=amps / capacity_ah, capacity=capacity_ah * MAH_PER_AH,
                chemistry=DISPLAY_NAMES[akk], min_rate=min_rate, min_amps=min_rate * capacity_ah))
        if charger is not None:
            top = charger.max_charge_a if charging else charger.max_discharge_a
            if amps > top + 1e-9:
                direction = _("charge") if charging else _("discharge")
                out.append(_("{where}: asks {amps:.2f} A; the {charger} gives at most {top:g} A ({direction})").format(
                    where=where, amps=amps, charger=charger.name, top=top, direction=direction))
    return out
