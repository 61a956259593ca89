"""Phase end reasons in the user's language.

The reason a phase or a run ended is a contract, not a text for people: the Python interpreter,
the C firmware and the device protocol all say it in the same English words ("end of macro",
"default: dT/dt>1C/min"), the differential test compares them byte for byte, and code tells a
default ending from the macro's own by its "default:"/"limit:" prefix. So they stay English where
they are made and are translated here, where a person is shown one. The macro's own conditions
(``DELTA_PEAK>0.2S``) are ZUML and stay as they are."""
from __future__ import annotations

import re

from ..i18n import _, ngettext

_DEFAULT_CAPACITY = re.compile(r"capacity (?P<factor>[\d.]+)x")
_EMPTY_DISCHARGE = re.compile(r"empty discharge section, (?P<condition>.+)")
_LIMIT_HOURS = re.compile(r"simulation stopped after (?P<hours>[\d.]+)h")
_STOPPED_FOR = re.compile(r"stopped: (?P<why>.+)")
_CEILING = re.compile(r"balancer: cell (?P<cell>\d+) reached (?P<volts>[\d.]+)V \(ceiling\)")
_PROTECTION = "protection: "        # a charger's own protection ended the run (firmware/core/app.c)
_LEAD_CELLS = re.compile(r"balance lead (\d+) cells?")


def shown_reason(reason: str, entered: int = 0, declared: int = 0) -> str:
    """``reason`` as a person reads it in the installed language ("" stays ""). ``entered``, ``declared``:
    the cells entered at start and the SERIES of the macro running (0: not known), for a charger's
    "balance lead 3 cells"."""
    if reason.startswith(_PROTECTION):
        return _("protection: {what}").format(what=lead_cells_text(reason[len(_PROTECTION):], entered, declared))
    if reason == "end of macro":
        return _("end of macro")
    if reason == "stopped":
        return _("stopped")
    if reason == "stopped: a new macro was started":
        return _("stopped: a new macro was started")
    if m := _STOPPED_FOR.fullmatch(reason):
        return _("stopped: {why}").format(why=m["why"])
    if reason.startswith("default: "):
        return _("default: {condition}").format(condition=_default_condition(reason[len("default: "):]))
    if m := _CEILING.fullmatch(reason):
        return _("balancer: cell {cell} reached {volts} V (ceiling)").format(cell=m["cell"], volts=m["volts"])
    if reason.startswith("limit: "):
        rest = reason[len("limit: "):]
        if m := _LIMIT_HOURS.fullmatch(rest):
            rest = _("simulation stopped after {hours}h").format(hours=m["hours"])
        return _("limit: {what}").format(what=rest)
    return reason


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


def _default_condition(condition: str) -> str:
    if m := _DEFAULT_CAPACITY.fullmatch(condition):
        return _("capacity {factor}x").format(factor=m["factor"])
    if m := _EMPTY_DISCHARGE.fullmatch(condition):
        return _("empty discharge section, {condition}").format(condition=m["condition"])
    return condition                    # T>60, dT/dt>1C/min: symbols and units


def end_advice(phase) -> str:
    """Why a phase ended the way a user should look at, and what to change, in words ("" when its
    end needs nothing): a default that ended it, or a timer that cut a charge before full.
    ``phase`` is a `PhaseResult`."""
    reason = phase.reason
    if phase.full_by_dtdt:
        return _("the pack was full and warmed faster than 1 °C/min: the charger's own end of a fast nickel charge "
                 "with a sensor (its -dV would come a few minutes later); nothing to change")
    if phase.timer_before_full:
        return _("a timer ended this charge before the pack was full: give the timer more time (a charge at xC "
                 "takes about 1/x hours, plus a fifth) or charge faster")
    if reason.startswith("default: T>"):
        return _("the battery reached the charger's 60 °C limit: charge slower, and end the phase yourself first "
                 "(IF(T>45) STOP_FAZE)")
    if reason.startswith("default: dT/dt"):
        return _("the battery warmed faster than 1 °C/min before it was full: charge slower, or check that the "
                 "sensor touches the pack and not the charger")
    if _DEFAULT_CAPACITY.fullmatch(reason[len("default: "):]) and reason.startswith("default: "):
        return _("no condition of the macro ended this charge before the charger's guard (1.5 × the capacity "
                 "without a sensor): add the chemistry's end, -dV (IF(DELTA_PEAK>0.01S)) for nickel or a voltage "
                 "(IF(V>…)) for lead and lithium, and a timer")
    if reason.startswith("default: empty discharge section"):
        return _("the discharge section is empty, so the charger discharged at 0.1 A to the chemistry's end "
                 "voltage: write a discharge phase to choose the current and the end")
    if reason.startswith("limit: simulation stopped"):
        return _("nothing ended the macro: give every phase an end it reaches, a timer at least "
                 "(IF(tf>…) STOP_FAZE)")
    if _CEILING.fullmatch(reason):
        return _("one cell reached the charger's per-cell ceiling before the macro's own end: the cells are "
                 "unequal and the weakest fills first, so the pack is not full; charge slower so the balancer "
                 "keeps up, or replace the weak cell")
    if phase.by_default:
        return _("the charger's limits ended this phase, not the macro: stay within what the charger can give")
    return ""
