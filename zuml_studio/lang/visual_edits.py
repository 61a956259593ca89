"""The edits of the visual editor, as pure functions: text (+ the Macro compiled from
it) in, new text out. No Qt here, so every edit is unit-tested on plain strings.

The visual editor is a view of the text: each edit made on a card is one of these
functions, and the widget turns old text -> new text into one minimal document patch
(``common_patch``), so the editor's undo history covers both views. An edit touches
only what it changes: a value rewrites its statement's span in canonical form; a new
condition is a new line; a moved phase is its whole line range (with the comment lines
directly above it); comments elsewhere are never touched. ``dropped_comments`` tells
which comments an edit removed (e.g. the comment on the line of a deleted condition).

Nodes are found again after a re-check with ``path_of`` / ``node_at``: a path such as
``("charge", 1, 0, "st", 2)`` is section, item, item inside a cycle, statement.
"""
from __future__ import annotations

import re
from collections import Counter
from dataclasses import dataclass

from ..errors import ZumlError
from ..i18n import N_, _
from . import opcodes as ops
from .ast import Arg, Cycle, Macro, Phase, Section, Span, Statement
from .formatter import INDENT, format_statement
from .opcodes import Op, Place, Role
from .operands import (AKK_TYPE, CELSIUS, CURRENT, INPUT_U16, RELATIVE_FLAG, TIME, VOLTAGE, OperandKind,
                       ValueProblem, format_scaled, parse_akk_type)


class EditError(ZumlError, ValueError):
    """An edit that cannot be made; the message is for the user."""


# -- finding nodes again ---------------------------------------------------------------------

Path = tuple


def path_of(macro: Macro, node: object) -> Path:
    """Where ``node`` (a Statement, Phase, Cycle) stands in ``macro``; LookupError if nowhere."""
    for i, st in enumerate(macro.intro):
        if st is node:
            return ("intro", i)
    for head in ("between", "conclusion"):
        for i, st in enumerate(getattr(macro, head)):
            if st is node:
                return (head, i)
    for section in macro.sections():
        found = _path_in(section.items, node, (section.kind,))
        if found is not None:
            return found
    raise LookupError(_("this part of the macro is no longer in the text"))


def _path_in(items: list, node: object, prefix: Path) -> Path | None:
    for i, item in enumerate(items):
        here = prefix + (i,)
        if item is node:
            return here
        if isinstance(item, Phase):
            for k, st in enumerate(item.statements):
                if st is node:
                    return here + ("st", k)
        elif isinstance(item, Cycle):
            found = _path_in(item.items, node, here)
            if found is not None:
                return found
    return None


def node_at(macro: Macro, path: Path):
    """The node at ``path`` (see ``path_of``); a Section for a one-element section path."""
    try:
        head, rest = path[0], list(path[1:])
        if head in ("intro", "between", "conclusion"):
            return getattr(macro, head)[rest[0]]
        node: object = getattr(macro, head)
        while rest:
            step = rest.pop(0)
            if step == "st":
                node = node.statements[rest.pop(0)]
            else:
                node = node.items[step]
        return node
    except (AttributeError, IndexError, TypeError, KeyError):
        raise LookupError(_("nothing at {path} in this macro").format(path=path)) from None


def shape(macro: Macro) -> tuple:
    """What the cards are made of: equal shapes can be refreshed in place."""
    def items(seq: list) -> tuple:
        out = []
        for item in seq:
            if isinstance(item, Phase):
                out.append(("phase", tuple(s.op.code for s in item.statements)))
            elif isinstance(item, Cycle):
                out.append(("cycle", items(item.items)))
            else:
                out.append(("cmd", item.op.code))
        return tuple(out)
    return (tuple(s.op.code for s in macro.intro), tuple(s.op.code for s in macro.between),
            tuple(s.op.code for s in macro.conclusion),
            tuple((s.present, items(s.items)) for s in macro.sections()))


# -- text geometry ---------------------------------------------------------------------------

_COMMENT = re.compile(r"//[^\n]*")


class _Text:
    """The text as lines ("\\n" separated, as the parser reads it) with span <-> offset."""

    def __init__(self, text: str):
        self.text = text
        self.lines = text.split("\n")
        self.starts = [0]
        for line in self.lines[:-1]:
            self.starts.append(self.starts[-1] + len(line) + 1)

    def offset(self, line: int, column: int) -> int:
        return self.starts[line - 1] + column - 1

    def span(self, span: Span) -> tuple[int, int]:
        return self.offset(span.line, span.column), self.offset(span.end_line, span.end_column)

    def line(self, number: int) -> str:
        return self.lines[number - 1]

    def indent(self, number: int) -> str:
        line = self.line(number)
        return line[:len(line) - len(line.lstrip(" \t"))]

    def before(self, line: int, column: int) -> str:
        return self.line(line)[:column - 1]

    def after(self, line: int, column: int) -> str:
        return self.line(line)[column - 1:]

    def starts_line(self, span: Span) -> bool:
        return not self.before(span.line, span.column).strip()

    def ends_line(self, span: Span) -> bool:
        """Only blanks or a comment after the span on its last line."""
        rest = self.after(span.end_line, span.end_column).strip()
        return not rest or rest.startswith("//")

    def line_range(self, first: int, last: int) -> tuple[int, int]:
        """Offsets of whole lines first..last (1-based, inclusive) with their line break."""
        start = self.starts[first - 1]
        if last < len(self.lines):
            return start, self.starts[last]
        # The last line of the text has no break after it: take the one before instead.
        return (start - 1 if first > 1 else start), len(self.text)


def _apply(text: str, changes: list[tuple[int, int, str]]) -> str:
    """Replace non-overlapping [start, end) ranges (any order)."""
    out = text
    last = None
    for start, end, new in sorted(changes, key=lambda c: (c[0], c[1]), reverse=True):
        if last is not None and end > last:
            raise EditError(_("overlapping edits"))
        out = out[:start] + new + out[end:]
        last = start
    return out


def comments(text: str) -> list[str]:
    return [m.group(0).rstrip() for m in _COMMENT.finditer(text)]


def dropped_comments(old: str, new: str) -> list[str]:
    """Comments of ``old`` that ``new`` no longer has (as a multiset, in order)."""
    missing = Counter(comments(old)) - Counter(comments(new))
    out = []
    for c in comments(old):
        if missing[c] > 0:
            out.append(c)
            missing[c] -= 1
    return out


def common_patch(old: str, new: str) -> tuple[int, int, str]:
    """The one replacement turning ``old`` into ``new``: (start, end in old, inserted text)."""
    limit = min(len(old), len(new))
    start = 0
    while start < limit and old[start] == new[start]:
        start += 1
    end = 0
    while end < limit - start and old[len(old) - 1 - end] == new[len(new) - 1 - end]:
        end += 1
    return start, len(old) - end, new[start:len(new) - end]


# -- values ----------------------------------------------------------------------------------

def parse_value(operand: ops.Operand, text: str, subject: str | None = None) -> tuple[int, str | None]:
    """Text of one operand -> (raw, note); EditError when it cannot be stored. A note says the
    value was rounded to what the charger keeps. ``subject`` names the value in messages."""
    subject = subject or _("The value")
    text = text.strip()
    if not text:
        raise EditError(_("{subject} is empty").format(subject=subject))
    try:
        if operand.kind is AKK_TYPE:
            return parse_akk_type(text), None
        return operand.kind.parse(text, operand.lo, operand.hi), None
    except ValueProblem as problem:
        message = problem.message.replace("{subject}", subject)
        if problem.warning_raw is not None:
            return problem.warning_raw, message
        raise EditError(message + (f" ({problem.hint})" if problem.hint else "")) from None


def statement_text(op: Op, raws: list[int] | tuple[int, ...]) -> str:
    return format_statement(Statement(op, [Arg(r) for r in raws]))


def new_statement_text(op: Op, texts: list[str]) -> str:
    """Canonical text of ``op`` with operand texts (checked): EditError when one cannot be stored."""
    raws = [parse_value(o, t, _subject(op, o))[0] for o, t in zip(op.operands, texts)]
    raws += [o.default for o in op.operands[len(texts):]]
    if any(r is None for r in raws):
        raise EditError(_("{keyword} needs {n_operands} values").format(
                keyword=op.keyword, n_operands=len(op.operands)))
    return statement_text(op, raws)


def _subject(op: Op, operand: ops.Operand) -> str:
    if op.condition:
        return _("The limit of {condition}").format(condition=op.signature().split(" ")[0])
    return (op.keyword if len(op.operands) == 1
            else _("{operand} of {keyword}").format(operand=operand.name, keyword=op.keyword))


# -- statements ------------------------------------------------------------------------------

def set_statement(text: str, stmt: Statement, new_stmt_text: str) -> str:
    """Replace exactly the statement's span (a comment after it on its line stays)."""
    t = _Text(text)
    start, end = t.span(stmt.span)
    return _apply(text, [(start, end, new_stmt_text)])


def set_value(text: str, stmt: Statement, index: int, value_text: str) -> str:
    """Operand ``index`` of ``stmt`` set to ``value_text``; the statement is rewritten canonically."""
    operand = stmt.op.operands[index]
    raw, _note = parse_value(operand, value_text, _subject(stmt.op, operand))
    raws = list(stmt.raws())
    raws[index] = raw
    return set_statement(text, stmt, statement_text(stmt.op, raws))


def set_action_value(text: str, stmt: Statement, index: int, value_text: str) -> str:
    """``set_value`` for an action (CONSTANT_I, CONSTANT_V, CHARGE_EX, TRICKLE)."""
    if stmt.op.role is not Role.ACTION:
        raise EditError(_("{keyword} is not an action").format(keyword=stmt.op.keyword))
    return set_value(text, stmt, index, value_text)


def _removal(t: _Text, span: Span) -> tuple[int, int]:
    """Range that removes a statement: its whole line(s) when it stands alone, else the
    statement and the blanks that separate it from its neighbour on the line."""
    if t.starts_line(span) and t.ends_line(span):
        return t.line_range(span.line, span.end_line)
    start, end = t.span(span)
    text = t.text
    if not t.ends_line(span):
        while end < len(text) and text[end] in " \t":
            end += 1
    else:
        while start > 0 and text[start - 1] in " \t":
            start -= 1
    return start, end


def remove_statement(text: str, stmt: Statement) -> str:
    """Delete a statement; its line goes with it when it stands alone on it."""
    t = _Text(text)
    start, end = _removal(t, stmt.span)
    return _apply(text, [(start, end, "")])


def _insert_after_statement(t: _Text, stmt_span: Span, new_text: str, indent: str) -> tuple[int, int, str]:
    """A change that puts ``new_text`` after a statement: on a new line below its line
    when nothing but a comment follows it there, else after it on the same line."""
    if t.ends_line(stmt_span):
        _, end = t.line_range(stmt_span.end_line, stmt_span.end_line)
        if stmt_span.end_line < len(t.lines):
            return (end, end, f"{indent}{new_text}\n")
        return (len(t.text), len(t.text), f"\n{indent}{new_text}")
    _, end = t.span(stmt_span)
    return (end, end, f" {new_text}")


def _content_indent(t: _Text, phase: Phase) -> str:
    """The indentation of the phase's statements (the file's own style)."""
    for st in phase.statements:
        if st.span and t.starts_line(st.span) and st.span.line != phase.span.line:
            return t.indent(st.span.line)
    return t.indent(phase.span.line) + INDENT


def add_condition(text: str, phase: Phase, op: Op, value_text: str) -> str:
    """A new ``IF(...)`` line after the phase's last statement, indented like its statements."""
    if op.condition is None or Place.PHASE not in op.places:
        raise EditError(_("{signature} is not a phase condition").format(signature=op.signature()))
    new = new_statement_text(op, [value_text])
    t = _Text(text)
    if not phase.statements:
        raise EditError(_("the phase is empty"))
    last = phase.statements[-1]
    if phase.end_span and last.span.end_line == phase.end_span.line:
        start, __ = t.span(phase.end_span)
        return _apply(text, [(start, start, f"{new} ")])
    return _apply(text, [_insert_after_statement(t, last.span, new, _content_indent(t, phase))])


# -- actions ---------------------------------------------------------------------------------

@dataclass(frozen=True)
class ActionKind:
    key: str
    label: str
    ops: tuple[Op, ...]


_ACTION_LABELS = {ops.CONSTANT_I: N_("Constant current"), ops.CONSTANT_V: N_("Constant voltage"),
                  ops.CHARGE_EX: N_("Pulse charge"), ops.TRICKLE: N_("Top up (trickle)")}


def action_kinds() -> list[ActionKind]:
    """The actions a phase may hold, from the opcode table, plus CC-CV (CONSTANT_I with CONSTANT_V)."""
    out = []
    for op in ops.ACTIONS:
        label = _(_ACTION_LABELS[op]) if op in _ACTION_LABELS else op.keyword.title()
        out.append(ActionKind(op.keyword, label, (op,)))
        if op is ops.CONSTANT_V:
            out.append(ActionKind("CC-CV", "CC-CV", (ops.CONSTANT_I, ops.CONSTANT_V)))
    return out


def phase_actions(phase: Phase) -> list[Statement]:
    return [s for s in phase.statements if s.op.role is Role.ACTION]


def phase_conditions(phase: Phase) -> list[Statement]:
    return [s for s in phase.statements if s.op.role is Role.CONDITION]


def action_key(phase: Phase) -> str:
    kinds = {s.op for s in phase_actions(phase)}
    if kinds == {ops.CONSTANT_I, ops.CONSTANT_V}:
        return "CC-CV"
    actions = phase_actions(phase)
    return actions[0].op.keyword if actions else ""


def chemistry_of(macro: Macro | None):
    """The declared chemistry's model (limits per cell), or None."""
    if macro is None:
        return None
    st = macro.declared(ops.AKK_TYPE)
    if st is None:
        return None
    from ..domain.chemistry import load_chemistry   # late: sim imports lang, lang never sim at import time
    try:
        return load_chemistry(AKK_TYPE.format(st.args[0].raw))
    except KeyError:    # LiS, New, Undef: no model; a broken data file raises DataFileError
        return None


def _volts(v: float) -> str:
    return format_scaled(round(v * 100), 100) + "S"


def default_value(op: Op, macro: Macro | None = None, section: str = "charge") -> str:
    """A sensible first value for a new condition or declaration (from the chemistry when declared)."""
    chem = chemistry_of(macro)
    if op.condition:
        var, cmp = op.condition.variables[0], op.condition.comparison
        if var == "V":
            if chem is None:
                return "INPUT"
            return _volts(chem.discharge_end_v if cmp == "<" else chem.charge_end_v)
        if var == "I":
            return "0.05C"
        if var == "DELTA_PEAK":
            return "0.01S"
        if var == "T":
            return "45"
        if var == "Tc":
            return "70" if cmp == ">" else "50"
        if var in ("tf", "tm"):
            return "2h" if var == "tf" else "6h"
        return op.operands[0].kind.example.split(" ")[0]
    return {ops.AKK_TYPE: "LiPo", ops.SERIES: "1", ops.CAPACITY: "INPUT"}.get(
        op, op.operands[0].kind.example.split(" ")[0] if op.operands else "")


def _action_texts(key: str, phase: Phase, macro: Macro | None, section: str) -> list[str]:
    current = voltage = None
    for st in phase_actions(phase):
        if st.op is ops.CONSTANT_I:
            current = st.args[0].raw
        elif st.op is ops.CONSTANT_V:
            voltage = st.args[0].raw
        elif st.op is ops.CHARGE_EX:
            current = st.args[1].raw
        elif st.op is ops.TRICKLE:
            current = current if current is not None else st.args[0].raw
            voltage = st.args[2].raw
    chem = chemistry_of(macro)
    cur = CURRENT.format(current) if current is not None else "1C"
    end_v = (chem.discharge_end_v if section == "discharge" else chem.charge_end_v) if chem else None
    volt = VOLTAGE.format(voltage) if voltage is not None else (_volts(end_v) if end_v else "INPUT")
    if key == "CONSTANT_I":
        return [f"CONSTANT_I={cur}"]
    if key == "CONSTANT_V":
        return [f"CONSTANT_V={volt}"]
    if key == "CC-CV":
        return [f"CONSTANT_I={cur}", f"CONSTANT_V={volt}"]
    if key == "CHARGE_EX":
        return [new_statement_text(ops.CHARGE_EX, ["30", cur, "1", cur])]
    if key == "TRICKLE":
        v2 = VOLTAGE.parse(volt)
        if v2 == INPUT_U16:
            v1_text = "INPUT"
        else:
            v1_text = VOLTAGE.format(max(1, (v2 & 0x7FFF) - 10) | (v2 & RELATIVE_FLAG))
        return [new_statement_text(ops.TRICKLE, ["0.1C", v1_text, volt])]
    raise EditError(_("unknown action {key!r}").format(key=key))


def set_action(text: str, phase: Phase, key: str, macro: Macro | None = None, section: str = "charge") -> str:
    """Change what the phase does (an ``action_kinds()`` key); values carry over where they fit."""
    if key == action_key(phase):
        return text
    new = _action_texts(key, phase, macro, section)
    actions = phase_actions(phase)
    if not actions:
        raise EditError(_("the phase has no action to change"))
    t = _Text(text)
    first = actions[0]
    start, end = t.span(first.span)
    indent = t.indent(first.span.line) if t.starts_line(first.span) else _content_indent(t, phase)
    replacement = new[0] + "".join(f"\n{indent}{n}" for n in new[1:])
    if len(new) > 1 and not t.ends_line(first.span):
        replacement = new[0] + "".join(f" {n}" for n in new[1:])
    changes = [(start, end, replacement)]
    changes += [(*_removal(t, st.span), "") for st in actions[1:]]
    return _apply(text, changes)


# -- blocks: phases, cycles, commands ---------------------------------------------------------

def _item_first_last(item) -> tuple[Span, Span]:
    return item.span, getattr(item, "end_span", None) or item.span


def _block(t: _Text, item) -> tuple[int, int]:
    """Lines (1-based, inclusive) of an item: from its first line, with the comment lines
    directly above it, to its last line. EditError when it shares a line with another statement."""
    first, last = _item_first_last(item)
    if not t.starts_line(first) or not t.ends_line(last):
        what = ("FAZE" if isinstance(item, Phase) else "CYCLE" if isinstance(item, Cycle) else
                getattr(getattr(item, "op", None), "keyword", None) or _("the section"))
        raise EditError(_("line {line}: {what} shares its line with other statements; put it on its own lines to "
                          "move it here").format(line=first.line, what=what))
    top = first.line
    while top > 1 and t.line(top - 1).strip().startswith("//"):
        top -= 1
    return top, last.end_line


def _lines_text(t: _Text, top: int, bottom: int) -> str:
    return "\n".join(t.lines[top - 1:bottom]) + "\n"


def move_item(text: str, container: Section | Cycle, from_index: int, to_index: int) -> str:
    """Move item ``from_index`` of a section or cycle so that it ends up at ``to_index``:
    whole lines move, with the comment lines directly above the item."""
    items = container.items
    if not (0 <= from_index < len(items) and 0 <= to_index < len(items)):
        raise EditError(_("no such position"))
    if from_index == to_index:
        return text
    t = _Text(text)
    top, bottom = _block(t, items[from_index])
    moved = _lines_text(t, top, bottom)
    if to_index < from_index:
        anchor_top, __ = _block(t, items[to_index])
        at = t.starts[anchor_top - 1]
    else:
        __, anchor_bottom = _block(t, items[to_index])
        if anchor_bottom >= len(t.lines):
            raise EditError(_("the section has no end line"))
        at = t.starts[anchor_bottom]
    start, end = t.starts[top - 1], t.starts[bottom] if bottom < len(t.lines) else len(text)
    return _apply(text, [(start, end, ""), (at, at, moved)])


def move_phase(text: str, section: Section, from_index: int, to_index: int) -> str:
    """Reorder the items of a section (phases, cycles, commands): indices into ``section.items``."""
    return move_item(text, section, from_index, to_index)


def _indent_lines(lines: list[str], unit: str) -> list[str]:
    return [unit + line if line.strip() else line for line in lines]


def _dedent_lines(lines: list[str], indent: str, unit: str) -> list[str]:
    """Remove ``unit`` just after ``indent`` from the lines that have both."""
    if not unit:
        return list(lines)
    return [indent + line[len(indent) + len(unit):] if line.startswith(indent + unit) else line
            for line in lines]


def _unit_inside(t: _Text, outer_line: int, inner_line: int) -> str:
    """The extra indentation of ``inner_line`` over ``outer_line`` ('' when not deeper)."""
    outer, inner = t.indent(outer_line), t.indent(inner_line)
    return inner[len(outer):] if inner.startswith(outer) else ""


def wrap_in_cycle(text: str, phase: Phase | list, count: int = 2) -> str:
    """Put ``CYCLE(count)`` / ``END_CYCLE`` lines around a phase (or consecutive items, given
    as a list), its lines indented one level more. Cycles do not nest: the check refuses that."""
    if not 1 <= count <= 255:
        raise EditError(_("a cycle repeats 1 to 255 times"))
    items = phase if isinstance(phase, list) else [phase]
    t = _Text(text)
    top, __ = _block(t, items[0])
    __, bottom = _block(t, items[-1])
    first_span = _item_first_last(items[0])[0]
    indent = t.indent(first_span.line)
    body = _indent_lines(t.lines[top - 1:bottom], "\t" if indent.endswith("\t") else INDENT)
    new = [f"{indent}CYCLE({count})"] + body + [f"{indent}END_CYCLE"]
    start, end = t.starts[top - 1], t.starts[bottom] if bottom < len(t.lines) else len(text)
    return _apply(text, [(start, end, "\n".join(new) + ("\n" if bottom < len(t.lines) else ""))])


def _strip_keyword_line(t: _Text, span: Span, indent: str) -> list[str]:
    """The lines that stay when a CYCLE(n) / END_CYCLE at ``span`` goes: none, or its
    comment (on a line of its own), or the other statements of its line."""
    line = t.line(span.line)
    rest = (line[:span.column - 1] + line[span.end_column - 1:]).strip()
    return [f"{indent}{rest}"] if rest else []


def unwrap_cycle(text: str, cycle: Cycle) -> str:
    """Remove a cycle's CYCLE(n) and END_CYCLE lines; its contents move out one level.
    A comment on either line stays, on a line of its own."""
    if cycle.end_span is None:
        raise EditError(_("the cycle has no END_CYCLE"))
    t = _Text(text)
    first, last = cycle.span.line, cycle.end_span.line
    if first == last:
        raise EditError(_("line {first}: the cycle is written on one line; split it to unwrap it here").format(
                first=first))
    indent = t.indent(first)
    inner = t.lines[first:last - 1]
    deeper = next((n for n in range(first + 1, last) if t.line(n).strip()), None)
    unit = _unit_inside(t, first, deeper) if deeper else ""
    body = _dedent_lines(inner, indent, unit)
    new = _strip_keyword_line(t, cycle.span, indent) + body + _strip_keyword_line(t, cycle.end_span, indent)
    start = t.starts[first - 1]
    end = t.starts[last] if last < len(t.lines) else len(text)
    tail = "\n" if last < len(t.lines) else ""
    return _apply(text, [(start, end, "\n".join(new) + (tail if new else ""))])


def set_cycle_count(text: str, cycle: Cycle, count: int | str) -> str:
    raw, __ = parse_value(ops.CYCLE.operands[0], str(count), _("The cycle count"))
    t = _Text(text)
    start, end = t.span(cycle.span)
    return _apply(text, [(start, end, f"CYCLE({raw})")])


def remove_from_cycle(text: str, cycle: Cycle, index: int) -> str:
    """Take item ``index`` out of its cycle: the only item unwraps the cycle; otherwise the
    item goes just above the cycle when it is the first one, else just below it."""
    if len(cycle.items) == 1:
        return unwrap_cycle(text, cycle)
    t = _Text(text)
    item = cycle.items[index]
    top, bottom = _block(t, item)
    indent = t.indent(cycle.span.line)
    unit = _unit_inside(t, cycle.span.line, _item_first_last(item)[0].line)
    moved = "\n".join(_dedent_lines(t.lines[top - 1:bottom], indent, unit)) + "\n"
    start, end = t.starts[top - 1], t.starts[bottom]
    if index == 0:
        ctop, _ = _block(t, cycle)
        at = t.starts[ctop - 1]
    else:
        _, cbottom = _block(t, cycle)
        at = t.starts[cbottom]
    return _apply(text, [(start, end, ""), (at, at, moved)])


def delete_item(text: str, item) -> str:
    """Delete a phase, cycle or command with its lines (and the comment lines directly above it)."""
    t = _Text(text)
    top, bottom = _block(t, item)
    start, end = t.line_range(top, bottom)
    return _apply(text, [(start, end, "")])


def delete_phase(text: str, phase: Phase) -> str:
    return delete_item(text, phase)


def _phase_lines(kind: str, macro: Macro | None, indent: str, inner: str) -> list[str]:
    chem = chemistry_of(macro)
    if kind == "discharge":
        stop = f"IF(V<{_volts(chem.discharge_end_v)}) STOP_FAZE" if chem else "IF(tf>1h) STOP_FAZE"
        action = "CONSTANT_I=1C" if chem else "CONSTANT_I=INPUT"
    else:
        stop = f"IF(V>{_volts(chem.charge_end_v)}) STOP_FAZE" if chem else "IF(tf>1h) STOP_FAZE"
        action = "CONSTANT_I=1C" if chem else "CONSTANT_I=INPUT"
    return [f"{indent}FAZE", f"{indent}{inner}{action}", f"{indent}{inner}{stop}", f"{indent}END_FAZE"]


def _style(t: _Text, macro: Macro) -> tuple[str, str]:
    """(indent of a phase's contents relative to FAZE, indent of a section relative to MACRO)."""
    inner = INDENT
    for section in macro.sections():
        for phase in section.phases():
            for st in phase.statements:
                if t.starts_line(st.span) and st.span.line != phase.span.line:
                    own, faze = t.indent(st.span.line), t.indent(phase.span.line)
                    inner = own[len(faze):] if own.startswith(faze) else ""
                    return inner, INDENT
    return inner, INDENT


def add_phase(text: str, macro: Macro, kind: str) -> str:
    """Append a phase to the ``kind`` ("discharge" or "charge") section, creating the section
    (in its place: discharge first) when the macro has none."""
    t = _Text(text)
    section: Section = getattr(macro, kind)
    inner, sec_indent = _style(t, macro)
    if section.present:
        if section.end_span is None or not t.starts_line(section.end_span):
            raise EditError(_("the section's END_SECTION shares its line; put it on its own line to add a phase"))
        indent = t.indent(section.span.line) + INDENT
        for item in section.items:
            indent = t.indent(_item_first_last(item)[0].line)
            break
        lines = _phase_lines(kind, macro, indent, inner)
        at = t.starts[section.end_span.line - 1]
        return _apply(text, [(at, at, "\n".join(lines) + "\n")])
    head = t.indent(macro.span.line) + sec_indent
    lines = ([f"{head}{'DISCHARGE_SECTION' if kind == 'discharge' else 'CHARGE_SECTION'}"] +
             _phase_lines(kind, macro, head + INDENT, inner) + [f"{head}END_SECTION"])
    block = "\n".join(lines) + "\n"
    other = macro.charge if kind == "discharge" else macro.discharge
    if kind == "discharge" and other.present:
        top, __ = _block(t, _SectionItem(other))
        at = t.starts[top - 1]
    elif kind == "charge" and other.present:
        __, bottom = _block(t, _SectionItem(other))
        at = t.starts[bottom]
    else:
        at = _after_intro(t, macro)
    return _apply(text, [(at, at, block)])


class _SectionItem:
    """A section seen as a block (its header line to END_SECTION)."""

    def __init__(self, section: Section):
        self.span, self.end_span = section.span, section.end_span or section.span


def _after_intro(t: _Text, macro: Macro) -> int:
    """Offset of the line after the introduction (after its last statement's line, else the header)."""
    line = macro.intro[-1].span.end_line if macro.intro else macro.span.end_line
    return t.starts[line] if line < len(t.lines) else len(t.text)


# -- the introduction -------------------------------------------------------------------------

def set_declaration(text: str, macro: Macro, op: Op, value_text: str) -> str:
    """Set a declaration or macro-wide condition (a Place.INTRO op): rewrite it when declared,
    else insert it in the introduction, in table order among the others."""
    if Place.INTRO not in op.places:
        raise EditError(_("{keyword} does not stand in the introduction").format(keyword=op.keyword))
    existing = macro.declared(op)
    if existing is not None:
        return set_value(text, existing, 0, value_text)
    new = new_statement_text(op, [value_text])
    t = _Text(text)
    later = next((st for st in macro.intro if st.op.code > op.code and t.starts_line(st.span)), None)
    if later is not None:
        at = t.starts[later.span.line - 1]
        return _apply(text, [(at, at, f"{t.indent(later.span.line)}{new}\n")])
    if macro.intro:
        last = macro.intro[-1]
        indent = t.indent(last.span.line) if t.starts_line(last.span) else INDENT
        return _apply(text, [_insert_after_statement(t, last.span, new, indent)])
    first_section = next((s for s in macro.sections() if s.present), None)
    indent = t.indent(first_section.span.line) if first_section else t.indent(macro.span.line) + INDENT
    line = macro.span.end_line
    if line >= len(t.lines):
        return text + f"\n{indent}{new}"
    at = t.starts[line]
    return _apply(text, [(at, at, f"{indent}{new}\n")])


def remove_declaration(text: str, macro: Macro, op: Op) -> str:
    st = macro.declared(op)
    return text if st is None else remove_statement(text, st)


def set_name(text: str, macro: Macro, name: str) -> str:
    name = name.strip()
    if not name:
        raise EditError(_("the macro needs a name"))
    t = _Text(text)
    start, end = t.span(macro.name_span)
    return _apply(text, [(start, end, name)])


# -- words for the cards -----------------------------------------------------------------------

def human_value(kind: OperandKind, raw: int) -> str:
    """A stored value for people: 1C, 0.1 A, 4.2 V/cell, 12.6 V, 2 h, 45 °C."""
    if kind in (CURRENT, VOLTAGE):
        if raw == INPUT_U16:
            return "INPUT"
        number = format_scaled(raw & 0x7FFF, 100)
        if raw & RELATIVE_FLAG:
            return f"{number}C" if kind is CURRENT else f"{number} V/cell"
        return f"{number} A" if kind is CURRENT else f"{number} V"
    if kind is TIME:
        for unit, tenths in (("h", 36000), ("min", 600)):
            if raw and raw % tenths == 0:
                return f"{raw // tenths} {unit}"
        return f"{format_scaled(raw, 10)} s"
    if kind is CELSIUS:
        return f"{raw} °C"
    return kind.format(raw)


# Words for the condition variables that are not symbols (V, I, T, −ΔV stay as they are).
_VARIABLE_WORDS = {"Tc": N_("heat-sink")}
CONDITION_LABELS = {"V": N_("Voltage"), "I": N_("Current"), "T": N_("Temperature"), "Tc": N_("Heat-sink"),
                    "tm": N_("Macro time"), "tf": N_("Phase time"), "DELTA_PEAK": N_("−ΔV from peak")}


def condition_label(op: Op) -> str:
    """'Voltage >' for the condition rows."""
    c = op.condition
    var = c.variables[0]
    return f"{_(CONDITION_LABELS[var]) if var in CONDITION_LABELS else var} {c.comparison}"


def condition_phrase(st: Statement) -> str:
    c = st.op.condition
    value = human_value(st.op.operands[0].kind, st.args[0].raw)
    var = c.variables[0]
    if var == "tf":
        return value
    if var == "tm":
        return _("macro time > {value}").format(value=value)
    if var == "DELTA_PEAK":
        return f"−ΔV > {value}"
    return f"{_(_VARIABLE_WORDS[var]) if var in _VARIABLE_WORDS else var} {c.comparison} {value}"


def intro_condition_phrase(st: Statement) -> str:
    c = st.op.condition
    value = human_value(st.op.operands[0].kind, st.args[0].raw)
    if c.variables[0] == "Tc":
        if c.comparison == ">":
            return _("Pause when heat-sink > {value}").format(value=value)
        return _("Resume when heat-sink {comparison} {value}").format(comparison=c.comparison, value=value)
    if c.variables[0] == "tm":
        return _("Stop the macro after {value}").format(value=value)
    return condition_phrase(st)


def _amount(kind: OperandKind, raw: int) -> str:
    if raw != INPUT_U16:
        return human_value(kind, raw)
    return _("the current entered at start") if kind is CURRENT else _("the voltage entered at start")


def describe_phase(phase: Phase, section: str = "charge", nbsp: bool = False) -> str:
    """The card's sentence: 'Charge at 1C until V > 4.1 V/cell or 2 h'. ``nbsp``: values and
    conditions do not break across lines (no-break spaces inside them)."""
    actions = {s.op: s for s in phase_actions(phase)}
    if ops.CONSTANT_I in actions and ops.CONSTANT_V in actions:
        i, v = actions[ops.CONSTANT_I].args[0].raw, actions[ops.CONSTANT_V].args[0].raw
        head = _("CC-CV {current} to {voltage}").format(current=_amount(CURRENT, i), voltage=_amount(VOLTAGE, v))
    elif ops.CONSTANT_I in actions:
        current = _amount(CURRENT, actions[ops.CONSTANT_I].args[0].raw)
        head = (_("Discharge at {current}") if section == "discharge" else _("Charge at {current}")).format(
            current=current)
    elif ops.CONSTANT_V in actions:
        head = _("Hold {voltage}").format(voltage=_amount(VOLTAGE, actions[ops.CONSTANT_V].args[0].raw))
    elif ops.CHARGE_EX in actions:
        tch, ich, tdis, idis, _tv = actions[ops.CHARGE_EX].raws()
        head = _("Pulse-charge {seconds} s at {current}").format(seconds=tch, current=human_value(CURRENT, ich))
        if tdis:
            head += _(", discharge {seconds} s at {current}").format(seconds=tdis, current=human_value(CURRENT, idis))
    elif ops.TRICKLE in actions:
        i, v1, v2 = actions[ops.TRICKLE].raws()
        low, high = human_value(VOLTAGE, v1), human_value(VOLTAGE, v2)
        if INPUT_U16 not in (v1, v2) and (v1 & RELATIVE_FLAG) == (v2 & RELATIVE_FLAG):
            low = low.split(" ")[0]
        head = _("Top up at {current} between {low} and {high}").format(current=human_value(CURRENT, i), low=low,
                                                                       high=high)
    else:
        head = _("No action")
    stops = phase_conditions(phase)
    conds = [condition_phrase(s) for s in stops]
    only_time = len(stops) == 1 and stops[0].op.condition.variables[0] == "tf"
    if nbsp:
        conds = [c.replace(" ", "\u00a0") for c in conds]
        head = re.sub(r"(\d) (A|V|V/cell|s|h|min|°C)\b", "\\1\u00a0\\2", head)
    if not conds:
        return _("{action}, with no stop condition").format(action=head)
    if only_time:
        return _("{action} for {time}").format(action=head, time=conds[0])
    return _("{action} until {conditions}").format(action=head, conditions=_(" or ").join(conds))


def missing_conditions(phase: Phase) -> list[Op]:
    """The phase conditions of the opcode table not yet in the phase."""
    present = {s.op for s in phase.statements}
    return [op for op in ops.CONDITIONS if Place.PHASE in op.places and op not in present]


def intro_conditions() -> list[Op]:
    return [op for op in ops.CONDITIONS if Place.INTRO in op.places]
