"""Flat statements -> typed AST: keywords resolved through the opcode table,
values converted to their stored form, blocks matched with a stack so that an
unclosed block is reported where it was opened."""
from __future__ import annotations

import difflib
from dataclasses import dataclass

from . import opcodes as ops
from .ast import Arg, Cycle, Macro, Phase, Section, Span, Statement
from .diagnostics import Diagnostic, Severity
from .operands import AKK_TYPE, ValueProblem, parse_akk_type
from .opcodes import Form, Op
from .parser import Located, RawMacro, Tok
from ..i18n import _


@dataclass
class _Frame:
    kind: str                      # "section" | "cycle" | "phase"
    node: Section | Cycle | Phase
    keyword: str
    detached: bool = False         # opened where it may not stand; its contents are still checked


class Builder:
    def __init__(self, raw: RawMacro):
        self.raw = raw
        self.diagnostics: list[Diagnostic] = []
        self.macro = Macro(raw.name, name_span=raw.name_span, span=raw.header_span)
        self.stack: list[_Frame] = []
        self.seen_section = False
        self.after_section: list[Statement] = []
        self.ended: Span | None = None

    # -- reporting --------------------------------------------------------------
    def error(self, span: Span, code: str, message: str, hint: str = "",
              severity: Severity = Severity.ERROR, fix: str = "") -> None:
        self.diagnostics.append(Diagnostic(severity, span.line, span.column, (span.end_line, span.end_column),
                                           code, message, hint, fix))

    # -- driver -----------------------------------------------------------------
    def build(self) -> Macro:
        for st in self.raw.statements:
            if self.ended is not None:
                self.error(st.span, "E138", _("Text after END_MACRO"), _("END_MACRO must be the last statement"))
                continue
            self.statement(st)
        if self.ended is None:
            line, col = self.raw.end
            end = Span(line, col, line, col)
            self.close_all(end, None)
            self.error(end, "E139", _("END_MACRO is missing at the end"), _("add END_MACRO as the last line"))
        else:
            self.macro.end_span = self.ended
        self.macro.conclusion = self.after_section
        return self.macro

    def statement(self, st: Located) -> None:
        if st.raw.shape == "condition":
            node = self.condition(st)
            if node:
                self.place(node)
            else:
                self.mark_incomplete()
            return
        keyword = st.raw.name.value.upper()
        op = ops.BY_KEYWORD.get(keyword)
        if op is None:
            self.unknown(st)
            self.mark_incomplete()
            return
        if op.role is ops.Role.STRUCTURE:
            self.structure(st, op)
            return
        node = self.command(st, op)
        if node:
            self.place(node)
        else:
            self.mark_incomplete()

    # -- blocks -----------------------------------------------------------------
    def structure(self, st: Located, op: Op) -> None:
        if op is ops.MACRO:
            self.error(st.span, "E106", _("MACRO may only start the text"), _("one macro per file"))
            return
        if op is ops.CYCLE:
            if st.raw.shape != "call":
                self.error(st.span, "E111", _("CYCLE needs its count: CYCLE(3)"))
                return
            self.close_phase(st)
            arg = self.args(st, op)
            cycle = Cycle(arg[0] if arg else Arg(1), [], span=st.span)
            self.open("cycle", cycle, st, "CYCLE")
            return
        if st.raw.shape != "bare":
            self.error(st.span, "E111", _("{keyword} takes no value").format(
                    keyword=op.keyword), _("write {keyword} alone on its line").format(
                    keyword=op.keyword))
            return
        if op in (ops.DISCHARGE_SECTION, ops.CHARGE_SECTION):
            self.open_section(st, op)
        elif op is ops.END_SECTION:
            self.close_until("section", st, "END_SECTION", "E134", _("END_SECTION without an open section"))
        elif op is ops.FAZE:
            self.close_phase(st)
            self.open("phase", Phase([], span=st.span), st, "FAZE")
        elif op is ops.END_FAZE:
            if self.stack and self.stack[-1].kind == "phase":
                self.stack.pop().node.end_span = st.span
            else:
                self.error(st.span, "E136", _("END_FAZE without FAZE"))
        elif op is ops.END_CYCLE:
            self.close_until("cycle", st, "END_CYCLE", "E137", _("END_CYCLE without CYCLE"), stop_at="section")
        elif op is ops.END_MACRO:
            self.close_all(st.span, "END_MACRO")
            self.ended = st.span

    def open_section(self, st: Located, op: Op) -> None:
        self.close_all(st.span, op.keyword)
        kind = "discharge" if op is ops.DISCHARGE_SECTION else "charge"
        section = getattr(self.macro, kind)
        detached = False
        if section.present:
            self.error(st.span, "E131", _("A second {keyword}").format(
                    keyword=op.keyword), _("the first one is at line {line}").format(
                    line=section.span.line))
            detached = True
        elif kind == "discharge" and self.macro.charge.present:
            self.error(st.span, "E132", _("DISCHARGE_SECTION must come before CHARGE_SECTION"),
                       _("move the discharge section up"))
            detached = True
        if kind == "charge" and not detached and self.macro.discharge.present and not self.macro.charge.present:
            # Seed 000, byte layout item 8: commands may stand between the sections; they run where they stand.
            self.macro.between = self.after_section
        else:
            for stray in self.after_section:
                self.error(stray.span, "E133", _("{keyword} stands between sections").format(keyword=stray.op.keyword),
                           _("commands go inside a section, between the discharge and the charge section, or "
                             "after the last one"))
        self.after_section = []
        self.seen_section = True
        if detached:
            section = Section(kind, [], span=st.span)
        else:
            section.present, section.span = True, st.span
        self.open("section", section, st, op.keyword, detached)

    def open(self, kind: str, node, st: Located, keyword: str, detached: bool = False) -> None:
        if kind != "section" and not any(f.kind == "section" for f in self.stack):
            self.error(st.span, "E135", _("{keyword} outside a section").format(keyword=keyword),
                       _("phases and cycles belong in DISCHARGE_SECTION or CHARGE_SECTION"))
            detached = True
        if not detached and self.stack:
            parent = self.stack[-1].node
            (parent.items if not isinstance(parent, Phase) else parent.statements).append(node)
        self.stack.append(_Frame(kind, node, keyword, detached or bool(self.stack and self.stack[-1].detached)))

    def close_phase(self, st: Located) -> None:
        if self.stack and self.stack[-1].kind == "phase":
            self.unclosed(self.stack.pop(), st.span, st.raw.name.value.upper())

    def close_until(self, kind: str, st: Located, keyword: str, code: str, message: str,
                    stop_at: str | None = None) -> None:
        kinds = [f.kind for f in self.stack]
        if kind not in kinds or (stop_at and stop_at in kinds and kinds[::-1].index(stop_at) < kinds[::-1].index(kind)):
            self.error(st.span, code, message)
            return
        while self.stack[-1].kind != kind:
            self.unclosed(self.stack.pop(), st.span, keyword)
        self.stack.pop().node.end_span = st.span

    def close_all(self, span: Span, before: str | None) -> None:
        while self.stack:
            self.unclosed(self.stack.pop(), span, before)

    def unclosed(self, frame: _Frame, at: Span, before: str | None) -> None:
        """``before``: the keyword that closed it too early, None for the end of the text."""
        closer = {"phase": "END_FAZE", "cycle": "END_CYCLE", "section": "END_SECTION"}[frame.kind]
        where = (_("{keyword} at line {line}").format(keyword=before, line=at.line) if before is not None
                 else _("the end of the text"))
        self.error(frame.node.span, "E130", _("{keyword} is not closed").format(
                keyword=frame.keyword), _("{closer} expected before {where}").format(
                closer=closer, where=where))

    def mark_incomplete(self) -> None:
        if self.stack and isinstance(self.stack[-1].node, Phase):
            self.stack[-1].node.incomplete = True

    def place(self, node: Statement) -> None:
        if self.stack:
            frame = self.stack[-1]
            if frame.detached:
                return
            parent = frame.node
            (parent.statements if isinstance(parent, Phase) else parent.items).append(node)
        elif self.seen_section:
            self.after_section.append(node)
        else:
            self.macro.intro.append(node)

    # -- statements -------------------------------------------------------------
    def unknown(self, st: Located) -> None:
        word = st.raw.name.value
        known = list(ops.BY_KEYWORD) + sorted(ops.CONDITION_OUTCOMES)
        close = difflib.get_close_matches(word.upper(), known, n=1, cutoff=0.6)
        if word.upper() in ops.CONDITION_OUTCOMES:
            self.error(st.span, "E104", _("{word} must follow a condition").format(
                    word=word), _("write IF(...) {upper}").format(
                    upper=word.upper()))
        else:
            self.error(st.at(st.raw.name), "E110", _("Unknown command '{word}'").format(word=word),
                       _("did you mean {close}?").format(
                               close=close[0]) if close else _("see Help > Commands for the list"),
                       fix=close[0] if close else "")

    def command(self, st: Located, op: Op) -> Statement | None:
        if op.form is Form.ASSIGN and st.raw.shape != "assign":
            example = f"{op.keyword}={op.operands[0].kind.example.split(' ')[0]}"
            self.error(st.span, "E111", _("{keyword} needs '=' and a value").format(
                    keyword=op.keyword), f"write {example}")
            return None
        if op.form is Form.CALL and st.raw.shape != "call":
            self.error(st.span, "E111", _("{keyword} takes its values in parentheses").format(keyword=op.keyword),
                       f"write {op.signature()}")
            return None
        args = self.args(st, op)
        return None if args is None else Statement(op, args, span=st.span)

    def args(self, st: Located, op: Op) -> list[Arg] | None:
        given = st.raw.args
        required = sum(1 for o in op.operands if o.default is None)
        if not required <= len(given) <= len(op.operands):
            count = str(required) if required == len(op.operands) else f"{required} or {len(op.operands)}"
            noun = "value" if len(op.operands) == 1 else "values"
            self.error(st.span, "E112", _("{keyword} takes {count} {noun}, not {n_given}").format(
                    keyword=op.keyword, count=count, noun=noun, n_given=len(given)),
                       f"write {op.signature()}")
            return None
        out: list[Arg] = []
        ok = True
        for operand, tok in zip(op.operands, given):
            subject = (op.keyword if len(op.operands) == 1
                       else _("{operand} of {keyword}").format(operand=operand.name, keyword=op.keyword))
            raw = self.value(st, tok, operand, subject)
            ok = ok and raw is not None
            out.append(Arg(raw if raw is not None else 0, st.at(tok), tok.value))
        for operand in op.operands[len(given):]:
            out.append(Arg(operand.default))
        return out if ok else None

    def value(self, st: Located, tok: Tok, operand: ops.Operand, subject: str) -> int | None:
        try:
            if operand.kind is AKK_TYPE:
                return parse_akk_type(tok.value)
            return operand.kind.parse(tok.value, operand.lo, operand.hi)
        except ValueProblem as problem:
            severity = Severity.WARNING if problem.warning_raw is not None else Severity.ERROR
            self.error(st.at(tok), problem.code, problem.message.format(subject=subject), problem.hint,
                       severity)
            return problem.warning_raw

    def condition(self, st: Located) -> Statement | None:
        var, cmp = st.raw.name.value, st.raw.cmp.value
        candidates = ops.find_condition(var)
        if not candidates:
            sensitive = [v for o in ops.CONDITIONS for v in o.condition.variables if o.condition.case_sensitive]
            near = [v for v in sensitive if v.upper() == var.upper()]
            hint = (_("did you mean {name}? T, t, Tc, tm and tf are case-sensitive").format(name=near[0]) if near
                    else _("conditions test T, V, I, Tc, tm, tf (or t) and DELTA_PEAK"))
            self.error(st.at(st.raw.name), "E120", _("Unknown condition variable '{var}'").format(var=var), hint,
                       fix=near[0] if near else "")
            return None
        op = next((o for o in candidates
                   if cmp == o.condition.comparison or cmp in o.condition.also_accepts), None)
        if op is None:
            allowed = _(" or ").join(o.signature() for o in candidates)
            self.error(st.at(st.raw.cmp), "E121", _("IF({var}{cmp}x) is not a condition ZUML knows").format(
                    var=var, cmp=cmp),
                       _("allowed: {allowed}").format(allowed=allowed))
            return None
        shown = f"IF({var}{op.condition.comparison}x)"
        if st.raw.outcome is None:
            self.error(st.span, "E122", _("{shown} needs what to do when it holds").format(shown=shown),
                       _("write {statement}").format(
                           statement=f"{shown.replace('x', st.raw.args[0].value)} {op.condition.outcome}"))
            return None
        if st.raw.outcome.value.upper() != op.condition.outcome:
            self.error(st.at(st.raw.outcome), "E123",
                       _("{shown} can only {outcome}, not {written}").format(
                               shown=shown, outcome=op.condition.outcome, written=st.raw.outcome.value),
                       _("write {statement}").format(statement=op.condition.outcome))
            return None
        raw = self.value(st, st.raw.args[0], op.operands[0], _("The limit of {condition}").format(condition=shown))
        if raw is None:
            return None
        return Statement(op, [Arg(raw, st.at(st.raw.args[0]), st.raw.args[0].value)], span=st.span)


def build(raw: RawMacro) -> tuple[Macro, list[Diagnostic]]:
    builder = Builder(raw)
    macro = builder.build()
    return macro, builder.diagnostics
