"""Syntax colouring driven by the opcode table: the words come from ``lang.opcodes`` and the
symbolic values from the operand kinds' ``names``, so a command added to the table is
coloured (and completed, and explained on hover) without touching this file.

``classify_line`` is plain Python (one line in, coloured spans out); hover help uses it too,
so a word means the same thing to the colours and to the help.
"""
from __future__ import annotations

import re
from typing import NamedTuple

from PySide6.QtGui import QColor, QFont, QSyntaxHighlighter, QTextCharFormat, QTextDocument

from ...i18n import _
from ...lang import opcodes, operands
from ...lang.opcodes import Role
from ..base.theme import LIGHT, Colours

# -- what the words mean (built once, at import) ------------------------------------------

STRUCTURE = "structure"
DECLARATION = "declaration"
ACTION = "action"
CONDITION = "condition"        # IF
OUTCOME = "outcome"            # STOP_FAZE, PAUSE_MACRO, …
VARIABLE = "variable"          # T, t, Tc, tm, tf, V, I, DELTA_PEAK inside IF(…)
COMMAND = "command"            # MUSIC, LIGHT
NUMBER = "number"              # 1C, 4.2S, 500mA, 2h, 60
VALUE = "value"                # INPUT, AUTO, LiPo, STOP, FAST, …
NAME = "name"                  # the macro's name after MACRO
COMMENT = "comment"

CATEGORIES = (STRUCTURE, DECLARATION, ACTION, CONDITION, OUTCOME, VARIABLE, COMMAND, NUMBER, VALUE, NAME,
              COMMENT)

_ROLE_CATEGORY = {Role.STRUCTURE: STRUCTURE, Role.DECLARATION: DECLARATION, Role.ACTION: ACTION,
                  Role.CONDITION: CONDITION, Role.COMMAND: COMMAND}

#: Statement words, upper-cased (keywords are case-insensitive) -> category.
KEYWORDS: dict[str, str] = {op.keyword.upper(): _ROLE_CATEGORY[op.role] for op in opcodes.OPCODES}
KEYWORDS.update({word.upper(): OUTCOME for word in opcodes.CONDITION_OUTCOMES})

# Words every u16 current/voltage/capacity operand accepts besides numbers. The kinds keep them
# as reserved raw values rather than in ``names``, so they are listed here and checked against
# the kinds below: a word no kind accepts any more would fail at import.
_RESERVED_WORDS = ("INPUT", "AUTO")


def _kinds() -> list[operands.OperandKind]:
    seen: dict[str, operands.OperandKind] = {}
    for op in opcodes.OPCODES:
        for operand in op.operands:
            seen.setdefault(operand.kind.name, operand.kind)
    return list(seen.values())


def _accepted_by_some_kind(word: str) -> bool:
    for kind in _kinds():
        try:
            kind.parse(word)
            return True
        except operands.ValueProblem:
            pass
    return False


def _symbolic_values() -> dict[str, str]:
    """Upper-case key -> how it is written (``LIPO`` -> ``LiPo``)."""
    values = {w: w for w in _RESERVED_WORDS if _accepted_by_some_kind(w)}
    assert len(values) == len(_RESERVED_WORDS), "an operand kind no longer accepts INPUT/AUTO"
    for kind in _kinds():
        for key in kind.names:
            values.setdefault(key, operands.DISPLAY_NAMES.get(key, key))
    return values


#: Symbolic operand values, upper-case -> canonical spelling (what completion offers).
SYMBOLIC_VALUES: dict[str, str] = _symbolic_values()
#: Upper-case words coloured as values: those and the accepted aliases (the seed's "Lilon").
VALUE_WORDS: frozenset[str] = frozenset(SYMBOLIC_VALUES) | {a.upper() for a in operands.AKK_TYPE_ALIASES}

_TOKEN = re.compile(r"""
    (?P<comment>//.*)
  | (?P<number>(?<![\w.])-?(?:\d+(?:\.\d*)?|\.\d+)[A-Za-z]*)
  | (?P<word>[A-Za-z_][A-Za-z0-9_]*)
  | (?P<open>\()
  | (?P<close>\))
  | (?P<eq>=)
  | (?P<space>\s+)
  | (?P<other>.)
""", re.VERBOSE)
_LINE_NAME = re.compile(r"\s*([^\s(/][^/]*?)\s*(?=//|$)")
_PAREN_NAME = re.compile(r"\s*\(\s*([^)]*?)\s*(?=\)|$)")


class Span(NamedTuple):
    start: int
    end: int              # exclusive
    category: str
    word: str             # the text of the span


def _variable(word: str) -> bool:
    """T, t, Tc, tm, tf as written; V, I, DELTA_PEAK in any case (the table's rule)."""
    return bool(opcodes.find_condition(word))


def classify_line(text: str) -> list[Span]:
    """The coloured spans of one line of ZUML, in order."""
    spans: list[Span] = []
    depth = 0
    value_next = False          # after "=": a value, not a statement word
    if_pending = False          # IF seen at depth 0, waiting for its "("
    variable_next = False       # the first word inside IF(
    pos, n = 0, len(text)
    while pos < n:
        m = _TOKEN.match(text, pos)
        kind, tok = m.lastgroup, m.group()
        start, pos = m.start(), m.end()
        if kind == "space":
            continue
        if kind == "comment":
            spans.append(Span(start, pos, COMMENT, tok))
            break
        if kind == "number":
            spans.append(Span(start, pos, NUMBER, tok))
        elif kind == "word":
            upper = tok.upper()
            category = None
            if variable_next:
                category = VARIABLE if _variable(tok) else None
            elif depth == 0 and not value_next:
                category = KEYWORDS.get(upper) or (VALUE if upper in VALUE_WORDS else None)
            elif upper in VALUE_WORDS:
                category = VALUE
            if category:
                spans.append(Span(start, pos, category, tok))
            if category is STRUCTURE and upper == "MACRO" and depth == 0:
                name = _PAREN_NAME.match(text, pos) or _LINE_NAME.match(text, pos)
                if name and name.group(1):
                    spans.append(Span(name.start(1), name.end(1), NAME, name.group(1)))
                    pos = name.end(1)        # a name is never a keyword, whatever it spells
            if_pending = category is CONDITION and depth == 0
            variable_next = False
            value_next = False
            continue
        elif kind == "open":
            depth += 1
            variable_next = if_pending
        elif kind == "close":
            depth = max(0, depth - 1)
            variable_next = False
        elif kind == "eq":
            value_next = depth == 0
            if_pending = variable_next = False
            continue
        else:
            variable_next = False
        if_pending = False
        value_next = False
    return spans


# -- hover help --------------------------------------------------------------------------------

_COMPARISON = re.compile(r"\s*(>=|<=|==|!=|<>|>|<|=)")


def _op_help(op: opcodes.Op) -> str:
    return f"{op.signature()}\n{op.help}"


def _condition_ops(text: str, spans: list[Span], at: int) -> tuple[opcodes.Op, ...]:
    """The conditions the IF(...) statement whose IF, variable or outcome is ``spans[at]`` can
    be: one when variable and comparison are written, all of them when nothing is known."""
    i = at
    while i >= 0 and spans[i].category is not CONDITION:
        i -= 1
    ops: tuple[opcodes.Op, ...] = ()
    if i >= 0 and i + 1 < len(spans) and spans[i + 1].category is VARIABLE:
        var = spans[i + 1]
        ops = opcodes.find_condition(var.word)
        cmp = _COMPARISON.match(text, var.end)
        if cmp:
            sign = cmp.group(1)
            same = tuple(op for op in ops if sign == op.condition.comparison or sign in op.condition.also_accepts)
            ops = same or ops
    if spans[at].category is OUTCOME and not ops:
        ops = tuple(op for op in opcodes.CONDITIONS if op.condition.outcome == spans[at].word.upper())
    return ops or opcodes.CONDITIONS


def ops_at(text: str, column: int) -> tuple[opcodes.Op, ...]:
    """The opcode table's entries for the word at 0-based ``column`` of a line (a condition
    may be several until its variable and comparison are written); () off a keyword."""
    spans = classify_line(text)
    for at, span in enumerate(spans):
        if span.start <= column < span.end:
            break
    else:
        return ()
    if span.category in (CONDITION, VARIABLE, OUTCOME):
        return _condition_ops(text, spans, at)
    if span.category in (STRUCTURE, DECLARATION, ACTION, COMMAND):
        op = opcodes.BY_KEYWORD.get(span.word.upper())
        return (op,) if op else ()
    return ()


def help_text(text: str, column: int) -> str:
    """Hover help for 0-based ``column`` of a line: the command's signature and help from the
    opcode table ('' when the column is not on a keyword)."""
    ops = ops_at(text, column)
    if ops == opcodes.CONDITIONS:
        return _("IF(variable comparison x) outcome") + "\n" + "\n".join(op.signature() for op in ops)
    return "\n\n".join(_op_help(op) for op in ops)


# -- colours ----------------------------------------------------------------------------------

def make_formats(scheme: Colours) -> dict[str, QTextCharFormat]:
    formats = {}
    for category, (colour, bold, italic) in scheme.syntax.items():
        fmt = QTextCharFormat()
        fmt.setForeground(QColor(colour))
        if bold:
            fmt.setFontWeight(QFont.Weight.Bold)
        fmt.setFontItalic(italic)
        formats[category] = fmt
    return formats


class ZumlHighlighter(QSyntaxHighlighter):
    """Colours one block (line) at a time: a keystroke re-highlights only its own line,
    since no state carries from one line to the next."""

    def __init__(self, document: QTextDocument):
        self.scheme = LIGHT
        self.formats = make_formats(LIGHT)
        super().__init__(document)

    def set_scheme(self, scheme: Colours) -> None:
        """Colour with the light or the dark set (the editor's palette changed)."""
        if scheme is not self.scheme:
            self.scheme = scheme
            self.formats = make_formats(scheme)
            self.rehighlight()

    def highlightBlock(self, text: str) -> None:  # noqa: N802 (Qt's name)
        formats = self.formats
        for span in classify_line(text):
            self.setFormat(span.start, span.end - span.start, formats[span.category])
