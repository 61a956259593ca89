"""Text -> flat list of statements (lark LALR). Syntax errors become one Diagnostic.

Only the shape of each statement is decided here; ``builder`` gives it meaning.
Statements never span lines, so every line is parsed on its own and the parse
of a line is cached by its text: while the user types, only the edited line is
parsed again (see benchmarks/bench_compile.py).
"""
from __future__ import annotations

import dataclasses

from dataclasses import dataclass
from functools import lru_cache
from importlib import resources
import re

from lark import Lark, Token, Transformer
from lark.exceptions import UnexpectedCharacters, UnexpectedEOF, UnexpectedInput, UnexpectedToken

from ..user_dirs import cache_file
from .ast import Span
from .diagnostics import Diagnostic, Severity
from .opcodes import CONDITION_OUTCOMES
from .record import MAX_RECORD
from ..errors import ZumlError
from ..i18n import N_, _


@dataclass(frozen=True, slots=True)
class Tok:
    """A token on its line (the line number lives on the statement, so cached lines can move)."""

    type: str
    value: str
    column: int
    end_column: int


@dataclass(frozen=True, slots=True)
class RawStatement:
    shape: str                     # "bare" | "assign" | "call" | "condition"
    name: Tok                      # keyword as written (the variable for a condition)
    args: tuple[Tok, ...]
    column: int
    end_column: int
    cmp: Tok | None = None
    outcome: Tok | None = None


@dataclass(frozen=True, slots=True)
class Located:
    line: int
    raw: RawStatement

    @property
    def span(self) -> Span:
        return Span(self.line, self.raw.column, self.line, self.raw.end_column)

    def at(self, tok: Tok) -> Span:
        return Span(self.line, tok.column, self.line, tok.end_column)


@dataclass
class RawMacro:
    name: str
    name_span: Span
    header_span: Span
    statements: list[Located]
    end: tuple[int, int]           # position just past the text, for "missing END_MACRO"


class SyntaxProblem(ZumlError):
    def __init__(self, diagnostic: Diagnostic):
        super().__init__(diagnostic.message)
        self.diagnostic = diagnostic


@lru_cache(maxsize=1)
def _lark() -> Lark:
    outcomes = "|".join(sorted(CONDITION_OUTCOMES))
    grammar = (resources.files(__package__) / "grammar.lark").read_text(encoding="utf-8")
    grammar = grammar.replace("@OUTCOMES@", f"/({outcomes})(?![A-Za-z0-9_])/i")
    # lark checks the cached analysis against the grammar, the options and its own version,
    # and rebuilds (and rewrites) it when they differ or the file is unreadable.
    return Lark(grammar, parser="lalr", start=["first", "line"], maybe_placeholders=True,
                transformer=_ToRaw(), cache=cache_file("grammar.lark-cache") or False)


def _tok(t: Token) -> Tok:
    return Tok(t.type, str(t), t.column, t.end_column)


def _stmt(shape: str, name: Token, args: list, first: Token, last: Token, cmp=None, outcome=None) -> RawStatement:
    return RawStatement(shape, _tok(name), tuple(_tok(a) for a in args if a is not None), first.column,
                        last.end_column, cmp and _tok(cmp), outcome and _tok(outcome))


class _ToRaw(Transformer):
    """Runs inside the LALR parser (no tree is built): each rule -> a RawStatement.
    A span that ends with ')' is extended over it later (the grammar drops that token)."""

    def first(self, children):
        return children

    def line(self, children):
        return children

    def paren_header(self, children):
        return ("header", children[0], children[1])

    def line_header(self, children):
        return ("header", children[0], children[1])

    def bare(self, c):
        return _stmt("bare", c[0], [], c[0], c[0])

    def assign(self, c):
        return _stmt("assign", c[0], [c[1]], c[0], c[1])

    def call(self, c):
        name, *args = c
        return _stmt("call", name, args, name, next((a for a in reversed(args) if a is not None), name))

    def condition(self, c):
        if_tok, var, cmp, value, outcome, parens = c
        return _stmt("condition", var, [value], if_tok, parens or outcome or value, cmp, outcome)


_COMMENT = re.compile(r"//.*")
# A record holds 255 bytes of code, so no real macro comes near this; past it the text is
# refused at once instead of parsed for minutes.
MAX_TEXT_CHARS = 1_000_000
# The line cache is bounded by the text it holds (a parse costs memory in proportion); a line
# longer than _CACHE_LINE_MAX is not worth keeping (no macro has one, each keystroke changes it).
_CACHE: dict[tuple[str, bool], list] = {}
_CACHE_MAX_CHARS = 2_000_000
_CACHE_LINE_MAX = 2_000
_cache_chars = 0


def _parse_line(text: str, first: bool) -> list:
    """Cached: statements of one line (line number 1), or a SyntaxProblem to raise."""
    global _cache_chars
    key = (text, first)
    hit = _CACHE.get(key)
    if hit is None:
        try:
            hit = _close_spans(text, _lark().parse(text, start="first" if first else "line"))
        except UnexpectedInput as exc:
            hit = SyntaxProblem(_syntax_diagnostic(exc, text))
        if len(text) <= _CACHE_LINE_MAX:
            if _cache_chars + len(text) > _CACHE_MAX_CHARS:
                _CACHE.clear()
                _cache_chars = 0
            _CACHE[key] = hit
            _cache_chars += len(text)
    if isinstance(hit, SyntaxProblem):
        raise hit
    return hit


def _close_spans(text: str, items: list) -> list:
    """Extend call/condition spans over their closing ')' (the grammar drops that token)."""
    out = []
    for item in items:
        if isinstance(item, RawStatement) and (item.shape == "call" or
                                               (item.shape == "condition" and item.outcome is None)):
            close = text.find(")", item.end_column - 1)     # 0-based index of the ')'
            item = RawStatement(item.shape, item.name, item.args, item.column, close + 2, item.cmp, item.outcome)
        out.append(item)
    return out


def parse_raw(text: str) -> RawMacro:
    """Raises SyntaxProblem for the first syntax error (one error, no cascade). Stops after
    MAX_RECORD statements: no record holds that many (the compiler reports E160)."""
    if len(text) > MAX_TEXT_CHARS:
        raise SyntaxProblem(_error(1, 1, 1, 1, "E161", _("The text is {n_text:,} characters long: no macro is (a "
                                                         "record holds 255 bytes), so it is not checked past "
                                                         "{max_text_chars:,}").format(
                n_text=len(text), max_text_chars=MAX_TEXT_CHARS),
                                   _("is this the right file?")))
    statements: list[Located] = []
    header = None
    header_line = 0
    lines = text.split("\n")
    for number, line in enumerate(lines, start=1):
        bare = line.lstrip()
        if not bare or bare.startswith("//"):      # nothing to parse: skipped fast (long files)
            continue
        if header is None and not _COMMENT.sub("", line).strip():
            continue
        try:
            items = _parse_line(line, first=header is None)
        except SyntaxProblem as problem:
            raise SyntaxProblem(_moved_diagnostic(problem.diagnostic, number)) from None
        if header is None:
            header, header_line = items[0], number
            items = items[1:]
        statements.extend(Located(number, item) for item in items)
        if len(statements) >= MAX_RECORD:     # each takes a byte or more: it cannot fit, parse no further
            break
    last_line = len(lines)
    if header is None:
        raise SyntaxProblem(_error(last_line, 1, last_line, 1, "E101", _("A macro starts with its header: MACRO name"),
                                   _("for example: MACRO LiPo")))
    __, macro_tok, name_tok = header
    stripped = str(name_tok).rstrip()
    name_span = Span(header_line, name_tok.column, header_line, name_tok.column + len(stripped))
    header_span = Span(header_line, macro_tok.column, header_line, name_span.end_column)
    return RawMacro(stripped.strip(), name_span, header_span, statements, (last_line, len(lines[-1]) + 1))


def _moved_diagnostic(d: Diagnostic, line: int) -> Diagnostic:
    return dataclasses.replace(d, line=line, end=(line, d.end[1]))


_WORDS = {
    "NAME": N_("a command"), "NUMBER": N_("a number"), "RPAR": "')'", "LPAR": "'('", "COMMA": "','",
    "EQUAL": "'='", "CMP": N_("a comparison such as > or <"), "IF": "IF", "MACRO": "MACRO",
    "OUTCOME": N_("STOP_FAZE, PAUSE_MACRO, CONTINUE_MACRO or STOP_MACRO"), "$END": N_("the end of the line"),
    "LINE_NAME": N_("the macro's name"), "PAREN_NAME": N_("the macro's name"), "EMPTY_PARENS": "'()'",
}


def _syntax_diagnostic(exc: UnexpectedInput, text: str) -> Diagnostic:
    """One line's syntax error, in words (line number 1: the caller moves it)."""
    end_of_line = len(text.rstrip()) + 1
    if isinstance(exc, UnexpectedCharacters):
        col = exc.column
        char = text[exc.pos_in_stream] if exc.pos_in_stream < len(text) else ""
        if "MACRO" in exc.allowed:
            return _error(1, col, 1, col + 1, "E101", _("A macro starts with its header: MACRO name"),
                          _("for example: MACRO LiPo"))
        return _error(1, col, 1, col + 1, "E102", _("Unexpected character '{char}'").format(char=char),
                      _("ZUML uses letters, digits, = ( ) , . < > and // comments"))
    if isinstance(exc, UnexpectedEOF):
        return _error(1, end_of_line, 1, end_of_line, "E103", _("The line ends in the middle of a statement"),
                      _("{expected} (a statement never continues on the next line)").format(
                          expected=_expected(exc.expected)))
    assert isinstance(exc, UnexpectedToken)
    tok = exc.token
    expected = set(exc.expected)
    if tok.type == "$END":
        return _error(1, end_of_line, 1, end_of_line, "E103", _("The line ends in the middle of a statement"),
                      _("{expected} (a statement never continues on the next line)").format(
                          expected=_expected(expected)))
    col = tok.column
    end_col = getattr(tok, "end_column", None) or col + 1
    if "MACRO" in expected:
        return _error(1, col, 1, end_col, "E101", _("A macro starts with its header: MACRO name"),
                      _("for example: MACRO LiPo"))
    if tok.type in ("PAREN_NAME", "LINE_NAME"):
        # The lexer fell back to a name pattern: the real problem is the first character.
        char = tok.value[0]
        if char in "()=,<>":
            return _error(1, col, 1, col + 1, "E100", _("Unexpected '{char}'").format(char=char), _expected(expected))
        return _error(1, col, 1, col + 1, "E102", _("Unexpected character '{char}'").format(char=char),
                      _("ZUML uses letters, digits, = ( ) , . < > and // comments"))
    if tok.type == "OUTCOME":
        return _error(1, col, 1, end_col, "E104", _("{value} must follow a condition").format(value=tok.value),
                      _("write IF(...) {upper}").format(upper=tok.value.upper()))
    if tok.type == "NUMBER" and expected >= {"NAME"} and "RPAR" not in expected:
        return _error(1, col, 1, end_col, "E105", _("A number cannot start a statement: '{value}'").format(
                value=tok.value),
                      _("values follow '=' or stand inside ( )"))
    return _error(1, col, 1, end_col, "E100", _("Unexpected '{value}'").format(value=tok.value), _expected(expected))


def _expected(expected) -> str:
    expected = set(expected)
    if expected >= {"NAME", "NUMBER"} and len(expected) == 2:
        return _("expected a value such as 2A, 4.2S, 60 or INPUT")
    words = sorted({_(_WORDS[e]) if e in _WORDS else e for e in expected})
    return _("expected {words}").format(words=_(" or ").join(words)) if words else ""


def _error(line: int, col: int, end_line: int, end_col: int, code: str, message: str, hint: str) -> Diagnostic:
    return Diagnostic(Severity.ERROR, line, col, (end_line, end_col), code, message, hint)
