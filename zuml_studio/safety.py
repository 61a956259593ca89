"""The one safety check on bytes bound for a charger.

Every path that puts a macro on a charger or starts one (``zuml flash`` of a .zuml or .bin,
``zuml image``, ``zuml restore``, ``zuml run``; the Device panel's Compile & Flash, Restore
and Start; the virtual charger's START as a last line) calls ``record_problems`` or
``image_problems``. They decode the record with the decoder, run the safety lint's errors
against the chemistry limits (with the start's cell count and capacity where the macro leaves
them open) and, given a passport, the lockout (``device.passport.conflicts``). An empty list
means "safe to write"; otherwise each line names one danger.

Before a start the passport check is complete (the lockout refuses a macro for another
chemistry). When only writing, the battery connected now need not be the one a macro is for:
the passport's limits are checked only for a macro of the passport's own chemistry.
"""
from __future__ import annotations

from .device.passport import Passport, conflicts
from .lang import opcodes as ops
from .lang.decoder import decode_record
from .lang.diagnostics import Severity
from .lang.eeprom import slots
from .lang.lint import lint
from .sim.interpreter import StartParams
from .i18n import _


class UnsafeMacro(Exception):
    """Bytes the safety check refuses; ``problems`` holds one line per danger."""

    def __init__(self, problems: list[str]):
        super().__init__("; ".join(problems))
        self.problems = problems


def record_problems(record: bytes, passport: Passport | None = None, start: StartParams | None = None, *,
                    charger_max_a: float | None = None) -> list[str]:
    """Why ``record`` must not be written (``start`` None) or started (with ``start``).

    Raises ``lang.record.DecodeError`` for bytes that are not a record (callers refuse those first)."""
    decoded = decode_record(record)
    series = start.series if start else None
    capacity = start.capacity_mah if start else None
    problems = [_lint_line(f) for f in lint(decoded.macro, series=series, capacity_mah=capacity)
                if f.severity is Severity.ERROR]
    if passport is not None:
        akk = decoded.macro.declared(ops.AKK_TYPE)
        if start is not None or (akk is not None and akk.args[0].raw == passport.type):
            # Before a start, the current a CONSTANT_V phase alone reaches is not known yet (the
            # current entered at start, else the charger's limit): it is checked at START.
            problems += conflicts(passport, record, start or StartParams("train"),
                                  charger_max_a=charger_max_a if start is not None else None)
    return problems


def image_problems(image: bytes, passport: Passport | None = None, *,
                   charger_max_a: float | None = None) -> list[str]:
    """``record_problems`` of every record in an EEPROM image that decodes, each line prefixed with
    its slot. Raises ``lang.eeprom.ImageError`` for a broken record list."""
    return [_("slot {index} ({name}): {problem}").format(index=s.index, name=s.name, problem=line)
            for s in slots(image) if s.ok
            for line in record_problems(s.record, passport, charger_max_a=charger_max_a)]


def _lint_line(finding) -> str:
    offset = getattr(finding.node, "offset", None)
    where = _(" (byte {offset})").format(offset=offset) if offset is not None else ""
    return f"{finding.code}{where}: {finding.message}"
