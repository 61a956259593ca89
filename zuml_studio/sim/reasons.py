"""Phase end reasons in the user's language.

The reason a phase or a run ended is a contract, not a text for people: the interpreter, the C core
and the device protocol say it in the same English words (``domain/end_reasons.py`` words them from
a code), and they stay English where they are made. Here, where a person is shown one, the code is
worded again in the installed language. The macro's own conditions (``DELTA_PEAK>0.2S``) are ZUML
and stay as they are."""
from __future__ import annotations

import re

from ..domain.end_reasons import DEFAULT_PREFIX, EndCode, read
from ..i18n import _, ngettext

_LEAD_CELLS = re.compile(r"balance lead (\d+) cells?")     # a charger's protection text (firmware/boards)


def shown_reason(reason: str, entered: int = 0, declared: int = 0) -> str:
    """``reason`` as a person reads it in the installed language ("" stays ""). ``entered``, ``declared``:
    the cells entered at start and the SERIES of the macro running (0: not known), for a charger's
    "balance lead 3 cells"."""
    reason = read(reason)
    code, p = reason.code, reason.params
    if code is EndCode.PROTECTION:
        return _("protection: {what}").format(what=lead_cells_text(p["what"], entered, declared))
    if code is EndCode.END_OF_MACRO:
        return _("end of macro")
    if code is EndCode.STOPPED:
        return _("stopped")
    if code is EndCode.NEW_MACRO:
        return _("stopped: a new macro was started")
    if code is EndCode.DEFAULT_CAPACITY:
        return _("default: {condition}").format(condition=_("capacity {factor}x").format(
            factor=f"{p['factor']:g}"))
    if code is EndCode.DEFAULT_EMPTY_DISCHARGE:
        return _("default: {condition}").format(condition=_("empty discharge section, {condition}").format(
            condition=f"V<{p['end_v']:.2f}V/cell"))
    if code in (EndCode.DEFAULT_T, EndCode.DEFAULT_DTDT):      # T>60, dT/dt>1C/min: symbols and units
        return _("default: {condition}").format(condition=reason[len(DEFAULT_PREFIX):])
    if code is EndCode.CEILING:
        return _("balancer: cell {cell} reached {volts} V (ceiling)").format(cell=p["cell"],
                                                                             volts=f"{p['volts']:.2f}")
    if code is EndCode.SIM_LIMIT:
        return _("limit: {what}").format(what=_("simulation stopped after {hours}h").format(
            hours=f"{p['hours']:g}"))
    return str(reason)


def lead_cells_text(line: str, entered: int, declared: int) -> str:
    """The charger's "balance lead 3 cells" (it knows only what its port shows) said with the count
    the PC asked for: "you entered 4 cells; the balance lead shows 3"."""
    found = _LEAD_CELLS.search(line)
    if found is None or not (entered or declared):
        return line
    shown = int(found.group(1))
    if declared:
        said = ngettext("the macro declares {n} cell (SERIES); the balance lead shows {shown}",
                        "the macro declares {n} cells (SERIES); the balance lead shows {shown}", declared)
    else:
        said = ngettext("you entered {n} cell; the balance lead shows {shown}",
                        "you entered {n} cells; the balance lead shows {shown}", entered)
    return line[:found.start()] + said.format(n=declared or entered, shown=shown) + line[found.end():]


def end_advice(phase) -> str:
    """Why a phase ended the way a user should look at, and what to change, in words ("" when its
    end needs nothing): a default that ended it, or a timer that cut a charge before full.
    ``phase`` is a `PhaseResult`."""
    code = read(phase.reason).code
    if phase.full_by_dtdt:
        return _("the pack was full and warmed faster than 1 °C/min: the charger's own end of a fast nickel charge "
                 "with a sensor (its -dV would come a few minutes later); nothing to change")
    if phase.timer_before_full:
        return _("a timer ended this charge before the pack was full: give the timer more time (a charge at xC "
                 "takes about 1/x hours, plus a fifth) or charge faster")
    if code is EndCode.DEFAULT_T:
        return _("the battery reached the charger's 60 °C limit: charge slower, and end the phase yourself first "
                 "(IF(T>45) STOP_FAZE)")
    if code is EndCode.DEFAULT_DTDT:
        return _("the battery warmed faster than 1 °C/min before it was full: charge slower, or check that the "
                 "sensor touches the pack and not the charger")
    if code is EndCode.DEFAULT_CAPACITY:
        return _("no condition of the macro ended this charge before the charger's guard (1.5 × the capacity "
                 "without a sensor): add the chemistry's end, -dV (IF(DELTA_PEAK>0.01S)) for nickel or a voltage "
                 "(IF(V>…)) for lead and lithium, and a timer")
    if code is EndCode.DEFAULT_EMPTY_DISCHARGE:
        return _("the discharge section is empty, so the charger discharged at 0.1 A to the chemistry's end "
                 "voltage: write a discharge phase to choose the current and the end")
    if code is EndCode.SIM_LIMIT:
        return _("nothing ended the macro: give every phase an end it reaches, a timer at least "
                 "(IF(tf>…) STOP_FAZE)")
    if code is EndCode.CEILING:
        return _("one cell reached the charger's per-cell ceiling before the macro's own end: the cells are "
                 "unequal and the weakest fills first, so the pack is not full; charge slower so the balancer "
                 "keeps up, or replace the weak cell")
    if phase.by_default:
        return _("the charger's limits ended this phase, not the macro: stay within what the charger can give")
    return ""
