"""Phase end reasons in the user's language.

The reason a phase or a run ended is a contract, not a text for people: the Python interpreter,
the C firmware and the device protocol all say it in the same English words ("end of macro",
"default: dT/dt>1C/min"), the differential test compares them byte for byte, and code tells a
default ending from the macro's own by its "default:"/"limit:" prefix. So they stay English where
they are made and are translated here, where a person is shown one. The macro's own conditions
(``DELTA_PEAK>0.2S``) are ZUML and stay as they are."""
from __future__ import annotations

import re

from ..i18n import _

_DEFAULT_CAPACITY = re.compile(r"capacity (?P<factor>[\d.]+)x")
_EMPTY_DISCHARGE = re.compile(r"empty discharge section, (?P<condition>.+)")
_LIMIT_HOURS = re.compile(r"simulation stopped after (?P<hours>[\d.]+)h")
_STOPPED_FOR = re.compile(r"stopped: (?P<why>.+)")


def shown_reason(reason: str) -> str:
    """``reason`` as a person reads it in the installed language ("" stays "")."""
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
    if reason.startswith("limit: "):
        rest = reason[len("limit: "):]
        if m := _LIMIT_HOURS.fullmatch(rest):
            rest = _("simulation stopped after {hours}h").format(hours=m["hours"])
        return _("limit: {what}").format(what=rest)
    return reason


def _default_condition(condition: str) -> str:
    if m := _DEFAULT_CAPACITY.fullmatch(condition):
        return _("capacity {factor}x").format(factor=m["factor"])
    if m := _EMPTY_DISCHARGE.fullmatch(condition):
        return _("empty discharge section, {condition}").format(condition=m["condition"])
    return condition                    # T>60, dT/dt>1C/min: symbols and units
