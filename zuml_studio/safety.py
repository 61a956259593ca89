"""The one safety check on bytes bound for a charger: ``judge``.

Every path that puts a macro on a charger or starts one calls it (or ``judge_image`` for a whole
EEPROM image): ``zuml flash`` of a .zuml or .bin and ``zuml restore`` (over a serial line or through
an iMAX B6's ISP programmer, device/install/isp_store.py), ``zuml image``, ``zuml run``,
``zuml templates set``; the Device panel's Compile & Flash (the toolbar's Upload), Restore and
Start; the virtual charger's START as a last line; the slot lists (panel and ``zuml slots``, and
``zuml image --list`` offline) mark what it refuses, judged again on the bytes read back. Raw bytes
typed by hand (the serial monitor) go through ``RawSendGuard``. docs/safety.md states the policy.

The check judges the values the charger will run with: a macro that names a start template
(START_SHABLON=n) runs with the template's values, not the ones typed, so the caller passes the
charger's own templates (read from it). A macro the check cannot judge (no AKK_TYPE, or one with no
reference limits) counts as one that failed it. Errors refuse; warnings ask (the window asks once,
Cancel the default; the command line prints them). A battery's passport refuses a macro through
``conflicts`` (the lockout) at the end of this module.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Mapping

from .protocol import messages as m
from .protocol.crc import crc16
from .protocol.frames import MAX_FRAME, MAX_PAYLOAD, OVERHEAD, SYNC
from .protocol.passport import Passport, akk_name
from .lang import opcodes as ops
from .lang.decoder import decode_record
from .lang.diagnostics import Severity
from .lang.eeprom import Slot, slots
from .lang.formatter import format_args
from .lang.lint import lint
from .lang.opcodes import canonical_text
from .lang.operands import absolute_value
from .sim.interpreter import StartError, StartParams, with_template
from .sim.program import DefaultDischarge, PhaseCode, Program
from .domain.start_templates import StartTemplate, factory_templates
from .i18n import _

UNCHECKABLE = "W301"        # the lint's "no chemistry to check against": refused like an error


@dataclass(frozen=True)
class Verdict:
    """``errors``: why the bytes must not reach a charger (one line each, the code first);
    ``warnings``: what the user is asked about before they do."""

    errors: tuple[str, ...] = ()
    warnings: tuple[str, ...] = ()

    @property
    def safe(self) -> bool:
        return not self.errors

    def check(self) -> str:
        """The one word a slot list shows for these bytes, everywhere (panel, ``zuml slots``,
        ``zuml image --list``): "ok" or "UNSAFE (E303, W301)"."""
        return _("ok") if self.safe else _("UNSAFE ({codes})").format(codes=", ".join(self.codes()))

    def codes(self) -> list[str]:
        """The errors' codes in order, each once ("E303", "W301", "PASSPORT")."""
        found: list[str] = []
        for line in self.errors:
            code = line.split(" ", 1)[0].split(":", 1)[0] if line[:1] in "EW" or line[:4] == "RAW:" else "PASSPORT"
            if code not in found:
                found.append(code)
        return found


def judge(record: bytes, passport: Passport | None = None, start: StartParams | None = None, *,
          templates: Mapping[int, StartTemplate] | None = None, charger_max_a: float | None = None) -> Verdict:
    """Whether ``record`` may be written (``start`` None) or started with ``start``.

    ``templates``: the charger's start templates (None: the factory table). A macro naming one
    is judged with its values, also when only writing (whatever is typed at start, the charger
    takes the template's). Raises ``lang.record.DecodeError`` for bytes that are not a record."""
    decoded = decode_record(record)
    params, template_note, missing = _effective(record, start, templates)
    errors: list[str] = [missing] if missing else []
    warnings: list[str] = []
    for finding in lint(decoded.macro, series=params.series if params else None,
                        capacity_mah=params.capacity_mah if params else None,
                        current_a=params.current_a if params else None,
                        sensor=params.sensor if start is not None else None):
        line = _lint_line(finding) + template_note
        if finding.severity is Severity.ERROR:
            errors.append(line)
        elif finding.code == UNCHECKABLE:
            errors.append(line + _(" (a macro the check cannot judge is refused)"))
        elif finding.severity is Severity.WARNING and finding.code.startswith("W3"):
            warnings.append(line)           # notes (values left to the start) are never asked
    if passport is not None:
        akk = decoded.macro.declared(ops.AKK_TYPE)
        if (start is not None and not missing) or (akk is not None and akk.args[0].raw == passport.type):
            # Before a start, the current a CONSTANT_V phase alone reaches is not known yet (the
            # current entered at start, else the charger's limit): it is checked at START.
            errors += conflicts(passport, record, params or StartParams("train"),
                                charger_max_a=charger_max_a if start is not None else None)
    return Verdict(tuple(errors), tuple(warnings))


def judge_image(image: bytes, passport: Passport | None = None, *,
                templates: Mapping[int, StartTemplate] | None = None,
                charger_max_a: float | None = None) -> Verdict:
    """``judge`` of every record in an EEPROM image that decodes, each line prefixed with its slot.
    Raises ``lang.eeprom.ImageError`` for a broken record list."""
    errors: list[str] = []
    warnings: list[str] = []
    for s in slots(image):
        if not s.ok:
            continue
        verdict = judge(s.record, passport, templates=templates, charger_max_a=charger_max_a)
        where = _("slot {index} ({name}): ").format(index=s.index, name=s.name)
        errors += [where + line for line in verdict.errors]
        warnings += [where + line for line in verdict.warnings]
    return Verdict(tuple(errors), tuple(warnings))


def judge_slots(client, found: list[Slot]) -> list[Verdict | None]:
    """``judge`` of each slot read back from a charger (``client``: a ``device.zuml.client.ChargerClient``)
    with its battery's passport and its own start templates; None for a slot that does not decode.
    The slot lists show this, so a macro forced onto a charger is marked on every later read."""
    passport = client.passport_if_any()
    templates = client.templates_named(named_template(s.record) for s in found if s.ok)
    return [judge(s.record, passport, templates=templates, charger_max_a=client.info.max_charge_a) if s.ok else None
            for s in found]


def named_template(record: bytes) -> int | None:
    """The start template a record names (START_SHABLON=n), None if it names none or does not decode."""
    try:
        return Program(record).intro.declarations.get(ops.START_SHABLON.code)
    except Exception:   # noqa: BLE001 - bytes that are not a record are refused by their own check
        return None


def _effective(record: bytes, start: StartParams | None,
               templates: Mapping[int, StartTemplate] | None) -> tuple[StartParams | None, str, str]:
    """The start values the charger will use, a note naming the template they came from, and why
    the start cannot happen ("" if it can).

    Only writing, a missing template leaves the values open (the macro cannot start until it is
    stored, and storing it is judged); before a start it is a refusal, as the charger's."""
    number = named_template(record)
    if number is None:
        return start, "", ""
    try:
        params = with_template(Program(record), start or StartParams(), templates)
    except StartError:
        missing = _("start template {number} (START_SHABLON={number}) is not stored on this charger: the charger "
                    "refuses the start (store it first)").format(number=number)
        return start, "", (missing if start is not None else "")
    table = factory_templates() if templates is None else templates
    return params, _(" [start template {number}: {values}]").format(number=number,
                                                                     values=table[number].describe()), ""


def _lint_line(finding) -> str:
    offset = getattr(finding.node, "offset", None)
    where = _(" (byte {offset})").format(offset=offset) if offset is not None else ""
    return f"{finding.code}{where}: {finding.message}"


# The requests raw bytes may make: they read, stop or drop. Every other one writes or commits the
# EEPROM, starts a macro, stores a template or a calibration, holds a current or talks to the battery:
# only the paths that judge the macro (and the battery) may send those.
RAW_ALLOWED = frozenset(m.BY_NAME[name].code for name in (
    "IDENTIFY", "READ_EEPROM", "ABORT", "STOP", "STATUS", "SET_TELEMETRY_RATE", "GET_EVENT", "LIST_TEMPLATES",
    "GET_TEMPLATE", "CAL_READ", "CAL_MEASURE"))


class RawSendGuard:
    """``judge`` of raw bytes sent by hand to a port a ZUML charger may be on (the serial monitor).

    The charger's frame parser keeps its state between reads, so a request split over several sends
    (or typed partly as text, partly as hex) is assembled all the same. The guard judges the stream:
    the bytes already sent that a frame still under way could begin with (the last MAX_FRAME - 1),
    then the new ones. Whatever frame ends in the new bytes is found, whichever sync byte the
    charger's parser is at (after garbage, after an inter-byte timeout dropped a false start): every
    frame a parser can assemble is a run of the stream with a good CRC."""

    def __init__(self) -> None:
        self._tail = b""

    def judge(self, data: bytes) -> Verdict:
        """Refuses ``data`` if it completes a request outside RAW_ALLOWED; ``sent`` records it once it went."""
        stream = self._tail + bytes(data)
        errors: list[str] = []
        for at in range(len(stream)):
            if stream[at] != SYNC or at + OVERHEAD > len(stream):
                continue
            length, code = stream[at + 1], stream[at + 2]
            end = at + OVERHEAD + length
            if length > MAX_PAYLOAD or end > len(stream) or end <= len(self._tail) or code in RAW_ALLOWED:
                continue
            if crc16(stream[at + 1:end - 2]) != int.from_bytes(stream[end - 2:end], "little"):
                continue
            known = m.BY_CODE.get(code)
            errors.append(_("RAW: these bytes complete a {request} request (type 0x{code:02x}) the charger would "
                            "act on").format(request=known.name if known else "ZUML", code=code))
        return Verdict(tuple(errors))

    def sent(self, data: bytes) -> None:
        self._tail = (self._tail + bytes(data))[-(MAX_FRAME - 1):]


# -- the battery passport's lockout (docs/protocol.md, *Battery passport*) ---------------------

def conflicts(passport: Passport, record: bytes, start, *, charger_max_a: float | None = None) -> list[str]:
    """Why the macro in ``record`` must not run on the battery this passport describes.

    ``start`` is a ``sim.interpreter.StartParams``. Values are resolved by the interpreter's
    rules (C with the capacity, S with the series, INPUT with the start values); a value that
    cannot be resolved is skipped (the start itself will fail on it). ``charger_max_a`` is the
    current a CONSTANT_V phase alone may reach when no current was entered.
    """
    program = Program(record)          # DecodeError for bytes that are not a record
    out: list[str] = []
    if passport.crit:
        out.append(_("the battery reports {n} critical error(s) (CRIT={n}): it is not fit for use").format(
            n=passport.crit))
    akk = program.intro.declarations.get(ops.AKK_TYPE.code, 0)
    if akk != passport.type:
        if akk == 0:
            out.append(_("the macro sets no battery type (AKK_TYPE Undef); the battery is {battery}").format(
                battery=akk_name(passport.type)))
        else:
            out.append(_("the macro is for {macro}; the battery is {battery}").format(
                macro=akk_name(akk), battery=akk_name(passport.type)))
    capacity_ah = program.intro.capacity_ah(start.capacity_mah)
    series = program.intro.series(start.series)

    def current(raw: int) -> float | None:
        return absolute_value(raw, start.current_a, capacity_ah)

    def voltage(raw: int) -> float | None:
        return absolute_value(raw, start.voltage_v, series)

    a_lim, v_lim = passport.a_limit, passport.v_limit
    seen: set[str] = set()

    def add(text: str) -> None:
        if text not in seen:
            seen.add(text)
            out.append(text)

    def text(ins) -> str:
        return canonical_text(ins.op, format_args(ins.op, ins.raws))

    for step in program.steps(start.task, 1):
        if isinstance(step, DefaultDischarge) or not isinstance(step, PhaseCode):
            continue
        by_op = {a.op: a for a in step.actions}
        charging = step.section == "charge" or ops.CHARGE_EX in by_op or ops.TRICKLE in by_op
        if not charging:
            continue
        where = (_("charge phase {index}") if step.section == "charge"
                 else _("discharge phase {index}")).format(index=step.index)
        if a_lim:
            charge_currents = []
            if ops.CHARGE_EX in by_op:
                charge_currents.append((by_op[ops.CHARGE_EX].raws[1], by_op[ops.CHARGE_EX]))
            elif ops.TRICKLE in by_op:
                charge_currents.append((by_op[ops.TRICKLE].raws[0], by_op[ops.TRICKLE]))
            elif ops.CONSTANT_I in by_op:
                charge_currents.append((by_op[ops.CONSTANT_I].raws[0], by_op[ops.CONSTANT_I]))
            for raw, ins in charge_currents:
                amps = current(raw)
                if amps is not None and amps > a_lim + 1e-9:
                    add(_("the macro charges at {amps:.2f} A ({where}: {statement}); the battery allows {limit} "
                          "A").format(amps=amps, where=where, statement=text(ins), limit=a_lim))
            if ops.CONSTANT_V in by_op and ops.CONSTANT_I not in by_op:
                amps = start.current_a if start.current_a else charger_max_a
                if amps is not None and amps > a_lim + 1e-9:
                    how = (_("the current entered at start") if start.current_a
                           else _("the charger's limit, no current entered"))
                    add(_("the macro charges at up to {amps:.2f} A ({where}: {statement} limited to {how}); the "
                          "battery allows {limit} A").format(amps=amps, where=where,
                                                             statement=text(by_op[ops.CONSTANT_V]), how=how,
                                                             limit=a_lim))
        if v_lim:
            checks = []
            if ops.CONSTANT_V in by_op:
                checks.append((by_op[ops.CONSTANT_V].raws[0], by_op[ops.CONSTANT_V],
                               _("the macro holds {volts:.2f} V ({where}: {statement}); the battery allows {limit} V")))
            if ops.TRICKLE in by_op:
                checks.append((by_op[ops.TRICKLE].raws[2], by_op[ops.TRICKLE],
                               _("the macro tops up to {volts:.2f} V ({where}: {statement}); the battery allows "
                                 "{limit} V")))
            for ins in step.conditions:
                if ins.op is ops.IF_V_GT:
                    checks.append((ins.raws[0], ins, _("the macro lets the voltage rise to {volts:.2f} V ({where}: "
                                                       "{statement}); the battery allows {limit} V")))
            for raw, ins, sentence in checks:
                volts = voltage(raw)
                if volts is not None and volts > v_lim + 1e-9:
                    add(sentence.format(volts=volts, where=where, statement=text(ins), limit=v_lim))
    return out
