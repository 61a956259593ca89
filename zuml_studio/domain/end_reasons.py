"""Why a phase or a run ended: a code with its parameters, worded in English here and only here.

The English words are a contract, not a text for people: the C core says the same bytes
(firmware/core/text.c, ``zc_reason_text``), the device protocol carries them as the text of a
``phase_end`` or ``finish`` event and of STATUS's ``end_reason`` (docs/protocol.md, "Why a phase ended,
on the host"), the differential test compares them byte for byte, and users' JSON files hold them.
So an ``EndReason`` is that text — a ``str``: it compares, prints, pickles and serialises as the text —
and carries its ``code`` and ``params`` from where a run ends to where it is shown (``sim/reasons.py``
words the code in the user's language) or judged (``by_default``). Made by the simulator, it is never
read back; text that crossed the protocol or a file comes back to its code in ``read``, the one
decoder of the wording below."""
from __future__ import annotations

from enum import Enum
from typing import Any


class EndCode(Enum):
    """How it ended; the value is the English wording, ``str.format``-ed with the parameters."""

    CONDITION = "{condition}"          # the macro's own condition, in ZUML: "IF(V>4.2S) STOP_FAZE"
    END_OF_MACRO = "end of macro"
    STOPPED = "stopped"                # by the user
    CANCELLED = "cancelled"            # a simulation the user cancelled
    DEVICE_ERROR = "device error"      # the virtual charger's injected fault
    NEW_MACRO = "stopped: a new macro was started"   # made no more (a START while running is BUSY); still read
    DEFAULT_T = "default: T>{limit_c:g}"                        # the charger's own limits (docs/zuml-2.0.md §3)
    DEFAULT_DTDT = "default: dT/dt>{rate:g}C/min"
    DEFAULT_CAPACITY = "default: capacity {factor:g}x"
    DEFAULT_EMPTY_DISCHARGE = "default: empty discharge section, V<{end_v:.2f}V/cell"   # end_v per cell
    CEILING = "balancer: cell {cell} reached {volts:.2f}V (ceiling)"
    SIM_LIMIT = "limit: simulation stopped after {hours:g}h"    # the simulator's bound, not a charger's
    PROTECTION = "protection: {what}"  # a charger's own protection ended the run (firmware/core/app.c)
    OTHER = "{text}"                   # none of these: a text not ours

    @property
    def charger_default(self) -> bool:
        """One of the charger's default ends ("default: …"), which no macro can switch off."""
        return self in _DEFAULTS

    @property
    def by_default(self) -> bool:
        """The charger's (or the simulator's) limits ended it, not the macro."""
        return self in _DEFAULTS or self in (EndCode.CEILING, EndCode.SIM_LIMIT)


_DEFAULTS = frozenset({EndCode.DEFAULT_T, EndCode.DEFAULT_DTDT, EndCode.DEFAULT_CAPACITY,
                       EndCode.DEFAULT_EMPTY_DISCHARGE})


class EndReason(str):
    """The reason's English text, with the code and the parameters it was worded from."""

    code: EndCode
    params: dict[str, Any]

    def __new__(cls, code: EndCode, **params: Any) -> EndReason:
        self = super().__new__(cls, code.value.format(**params))
        self.code, self.params = code, params
        return self

    def __reduce__(self):
        return _rebuild, (self.code, self.params)

    @property
    def by_default(self) -> bool:
        return self.code.by_default


def _rebuild(code: EndCode, params: dict[str, Any]) -> EndReason:
    return EndReason(code, **params)


def condition(text: str) -> EndReason:
    """The macro's own condition ended it; ``text`` is the condition's canonical ZUML."""
    return EndReason(EndCode.CONDITION, condition=text)


END_OF_MACRO = EndReason(EndCode.END_OF_MACRO)
STOPPED = EndReason(EndCode.STOPPED)

# The fixed texts and the prefixes of the worded ones, for ``read``.
_FIXED = {code.value: code for code in (EndCode.END_OF_MACRO, EndCode.STOPPED, EndCode.NEW_MACRO, EndCode.CANCELLED,
                                        EndCode.DEVICE_ERROR)}
DEFAULT_PREFIX = "default: "          # what the charger's default ends begin with; the condition follows
_DEFAULT, _LIMIT, _PROTECTION = DEFAULT_PREFIX, "limit: ", "protection: "


def read(text: str) -> EndReason:
    """The reason a text says, as the wording above made it (the protocol's events and STATUS, a JSON
    file); a text it does not recognise is ``OTHER`` (a macro's condition keeps its ZUML as ``CONDITION``)."""
    if isinstance(text, EndReason):
        return text
    found = _read(text)
    # Read back only what words back the same: a text worded otherwise stays itself, byte for byte.
    return found if found is not None and found == text else EndReason(EndCode.OTHER, text=text)


def _read(text: str) -> EndReason | None:
    if text in _FIXED:
        return EndReason(_FIXED[text])
    if text.startswith("IF("):
        return condition(text)
    if text.startswith(_PROTECTION):
        return EndReason(EndCode.PROTECTION, what=text[len(_PROTECTION):])
    try:
        if text.startswith(_DEFAULT + "T>"):
            return EndReason(EndCode.DEFAULT_T, limit_c=float(text[len(_DEFAULT + "T>"):]))
        if text.startswith(_DEFAULT + "dT/dt>") and text.endswith("C/min"):
            return EndReason(EndCode.DEFAULT_DTDT, rate=float(text[len(_DEFAULT + "dT/dt>"):-len("C/min")]))
        if text.startswith(_DEFAULT + "capacity ") and text.endswith("x"):
            return EndReason(EndCode.DEFAULT_CAPACITY, factor=float(text[len(_DEFAULT + "capacity "):-1]))
        head = _DEFAULT + "empty discharge section, V<"
        if text.startswith(head) and text.endswith("V/cell"):
            return EndReason(EndCode.DEFAULT_EMPTY_DISCHARGE, end_v=float(text[len(head):-len("V/cell")]))
        head = "balancer: cell "
        if text.startswith(head) and text.endswith("V (ceiling)"):
            cell, _, volts = text[len(head):-len("V (ceiling)")].partition(" reached ")
            return EndReason(EndCode.CEILING, cell=int(cell), volts=float(volts))
        head = _LIMIT + "simulation stopped after "
        if text.startswith(head) and text.endswith("h"):
            return EndReason(EndCode.SIM_LIMIT, hours=float(text[len(head):-1]))
    except ValueError:
        pass
    return None
