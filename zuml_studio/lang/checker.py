"""Rules a macro must keep to be stored, checked on the AST.

Text (nodes with spans) and byte code (nodes with offsets) go through the same
rules, so the decoder accepts exactly what the compiler can produce.
"""
from __future__ import annotations

from dataclasses import dataclass

from . import opcodes as ops
from .ast import Cycle, Macro, Phase, Section, Statement
from .diagnostics import Severity
from .operands import INPUT_U16, RELATIVE_FLAG
from .opcodes import Place, Role
from .record import MAX_NAME, MAX_RECORD, RecordTooLarge, encode, encoded_size
from ..i18n import _

FORBIDDEN_NAME_CHARS = set('<>:"/\\|?*')


@dataclass(frozen=True)
class Finding:
    node: object                  # Statement | Phase | Cycle | Section | Macro | "name"
    severity: Severity
    code: str
    message: str
    hint: str = ""


def name_problem(name: str) -> tuple[str, str, str] | None:
    """(code, message, hint) when the name cannot be stored and shown, else None."""
    if not name:
        return "E140", _("The macro needs a name"), _("write MACRO LiPo")
    if len(name) > MAX_NAME:
        return "E141", _("The name '{name}' is {n_name} characters long; at most {max_name}").format(
                name=name, n_name=len(name), max_name=MAX_NAME), _("shorten it")
    bad = sorted({c for c in name if not " " <= c <= "~" or c in FORBIDDEN_NAME_CHARS})
    if bad or name != name.strip() or name.startswith("("):
        shown = " ".join(repr(c) for c in bad) or _("spaces at the ends or a leading '('")
        return ("E142", _("The name '{name}' has characters the charger cannot store: {shown}").format(
                name=name, shown=shown),
                _('use printable ASCII without < > : " / \\ | ? *'))
    return None


class Checker:
    def __init__(self, macro: Macro):
        self.macro = macro
        self.findings: list[Finding] = []

    def report(self, node: object, code: str, message: str, hint: str = "",
               severity: Severity = Severity.ERROR) -> None:
        self.findings.append(Finding(node, severity, code, message, hint))

    def run(self) -> list[Finding]:
        problem = name_problem(self.macro.name)
        if problem:
            self.report("name", *problem)
        self.intro()
        self.section(self.macro.discharge)
        for st in self.macro.between:
            self.placed(st, Place.SECTIONS)
        self.section(self.macro.charge)
        for st in self.macro.conclusion:
            self.placed(st, Place.CONCLUSION)
        if not any(f.severity is Severity.ERROR for f in self.findings):
            self.size()
        return self.findings

    def placed(self, st: Statement, place: Place) -> bool:
        if place in st.op.places:
            return True
        where = _(" or ").join(_(p.value) for p in st.op.places)
        if st.op.role is Role.CONDITION:
            shown = st.op.signature()
        else:
            shown = st.op.keyword
        self.report(st, "E150", _("{shown} cannot stand in {place}").format(
                shown=shown, place=_(place.value)), _("it belongs in {where}").format(
                where=where))
        return False

    def intro(self) -> None:
        seen: dict[int, Statement] = {}
        for st in self.macro.intro:
            if not self.placed(st, Place.INTRO):
                continue
            if st.op.code in seen:
                self.report(st, "E151", _("{statement} is declared twice").format(
                        statement=st.op.signature() if st.op.condition else st.op.keyword), _("keep one"))
            seen[st.op.code] = st

    def section(self, section: Section) -> None:
        for item in section.items:
            self.item(item, in_cycle=False)

    def item(self, item: object, in_cycle: bool) -> None:
        if isinstance(item, Phase):
            self.phase(item)
        elif isinstance(item, Cycle):
            if in_cycle:
                self.report(item, "E152", _("Cycles do not nest"), _("close the outer CYCLE first, or merge the two"))
            if not any(isinstance(i, (Phase, Cycle)) for i in item.items):
                self.report(item, "W153", _("This CYCLE repeats no phase"), _("put FAZE … END_FAZE inside it"),
                            Severity.WARNING)
            for inner in item.items:
                self.item(inner, in_cycle=True)
        else:
            self.placed(item, Place.BETWEEN)

    def phase(self, phase: Phase) -> None:
        actions: list[Statement] = []
        conditions: dict[int, Statement] = {}
        for st in phase.statements:
            if not self.placed(st, Place.PHASE):
                continue
            if st.op.role is Role.ACTION:
                actions.append(st)
            elif st.op.code in conditions:
                self.report(st, "W156", _("A second {signature} in this phase").format(signature=st.op.signature()),
                            _("only one of them can end it first; keep one"), Severity.WARNING)
            else:
                conditions[st.op.code] = st
            if st.op is ops.TRICKLE:
                self.trickle(st)
        if not actions and not phase.incomplete:
            self.report(phase, "E155", _("This phase has no action"),
                        _("add CONSTANT_I, CONSTANT_V, CHARGE_EX or TRICKLE"))
        kinds = [a.op for a in actions]
        cc_cv = sorted(op.code for op in kinds) == [ops.CONSTANT_I.code, ops.CONSTANT_V.code]
        if len(actions) > 1 and not cc_cv:
            self.report(actions[1], "E154", _("A phase holds one action; this one already has {keyword}").format(
                    keyword=kinds[0].keyword),
                        _("CONSTANT_I and CONSTANT_V together make CC-CV; anything else needs its own FAZE"))

    def trickle(self, st: Statement) -> None:
        __, v1, v2 = st.raws()
        if INPUT_U16 in (v1, v2) or (v1 & RELATIVE_FLAG) != (v2 & RELATIVE_FLAG):
            return
        if v1 >= v2:
            self.report(st, "E157", _("TRICKLE switches on at V1 and off at V2, so V1 must be below V2"),
                        _("for example TRICKLE(0.1C, 2.3S, 2.4S)"))

    def size(self) -> None:
        if encoded_size(self.macro) <= MAX_RECORD:
            return
        try:
            encode(self.macro)
        except RecordTooLarge as too_large:
            self.report(too_large.node, "E160",
                        _("The macro needs {size} bytes; a record holds at most {max_record}").format(
                                size=too_large.size, max_record=MAX_RECORD),
                        _("this is where it stops fitting: shorten the macro or split it"))


def check(macro: Macro) -> list[Finding]:
    return Checker(macro).run()
