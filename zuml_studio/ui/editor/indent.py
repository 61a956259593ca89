"""Indentation and comment rules of the editor, as plain functions over line texts (no Qt).

Which words open and close a block is read from the opcode table: every STRUCTURE
keyword that does not start with ``END_`` opens one (MACRO, DISCHARGE_SECTION,
CHARGE_SECTION, CYCLE, FAZE), and ``END_X`` closes the opener named ``X`` or ``…_X``
(END_SECTION closes either section). Only words in statement position count: ``FAZE`` in
``LIGHT(FAZE)`` is a value, and the rest of a ``MACRO name`` line is the name.
"""
from __future__ import annotations

import re
from typing import Iterable, Sequence

from ...lang import opcodes

INDENT_WIDTH = 2
INDENT = " " * INDENT_WIDTH
COMMENT = "//"

_STRUCTURE = [op.keyword for op in opcodes.OPCODES if op.role is opcodes.Role.STRUCTURE]
OPENERS: frozenset[str] = frozenset(kw for kw in _STRUCTURE if not kw.startswith("END_"))
CLOSERS: dict[str, frozenset[str]] = {
    kw: frozenset(o for o in OPENERS if o == kw[4:] or o.endswith("_" + kw[4:]))
    for kw in _STRUCTURE if kw.startswith("END_")
}

# Words, numbers (with their unit, so "1C" is no word C), and the punctuation that decides
# whether a word stands where a statement starts.
_TOKEN = re.compile(r"[A-Za-z_][A-Za-z0-9_]*|-?(?:\d+(?:\.\d*)?|\.\d+)[A-Za-z]*|[()=]|//")
_FIRST_WORD = re.compile(r"\s*([A-Za-z_][A-Za-z0-9_]*)")


def leading_indent(line: str) -> str:
    """The whitespace a line starts with."""
    return line[: len(line) - len(line.lstrip(" \t"))]


def code_part(line: str) -> str:
    """The line without its ``//`` comment."""
    at = line.find(COMMENT)
    return line if at < 0 else line[:at]


def first_word(line: str) -> str:
    """The line's first word, upper-cased ('' when the line does not start with one)."""
    m = _FIRST_WORD.match(line)
    return m.group(1).upper() if m else ""


def structure_words(line: str) -> list[str]:
    """Block openers and closers in statement position on a line, upper-cased, in order."""
    words: list[str] = []
    depth = 0
    after_equals = False
    for m in _TOKEN.finditer(line):
        tok = m.group()
        if tok == "//":
            break
        if tok == "(":
            depth += 1
        elif tok == ")":
            depth = max(0, depth - 1)
        elif tok == "=":
            after_equals = True
            continue
        elif depth == 0 and not after_equals and (tok[0].isalpha() or tok[0] == "_"):
            word = tok.upper()
            if word in OPENERS or word in CLOSERS:
                words.append(word)
            if word == "MACRO" and not line[m.end():].lstrip().startswith("("):
                break                       # "MACRO name": the rest of the line is the name
        after_equals = False
    return words


def _unclosed(words: Iterable[str]) -> list[str]:
    """Openers left open after these words (closers of earlier lines are ignored)."""
    stack: list[str] = []
    for word in words:
        if word in OPENERS:
            stack.append(word)
        elif stack and stack[-1] in CLOSERS[word]:
            stack.pop()
    return stack


def indent_after(line: str) -> str:
    """Indentation for a new line typed after ``line`` (the text before the cursor):
    the same as ``line``, one level more for each block it opens and does not close."""
    return leading_indent(line) + INDENT * len(_unclosed(structure_words(line)))


def opener_indent(closer_line: str, lines_above: Iterable[str]) -> str | None:
    """Indentation of the opener that the closer starting ``closer_line`` matches.

    ``lines_above`` are the lines before it, nearest first (read lazily: the scan stops at
    the opener). None when the line does not start with a closer or no opener is found.
    """
    closer = first_word(code_part(closer_line))
    if closer not in CLOSERS:
        return None
    pending: list[str] = []                 # closers met on the way up, innermost last
    for line in lines_above:
        for word in reversed(structure_words(line)):
            if word in CLOSERS:
                pending.append(word)
            elif pending:
                pending.pop()               # an opener closed further down
            elif word in CLOSERS[closer]:
                return leading_indent(line)
            # an unclosed opener of another kind (a missing END_…): look further out
    return None


def closer_indent(lines: Sequence[str], index: int) -> str | None:
    """Indentation line ``index`` should have if it starts with a closer, else None."""
    return opener_indent(lines[index], (lines[i] for i in range(index - 1, -1, -1)))


def backspace_column(column: int) -> int:
    """Backspace with only spaces before the cursor at 0-based ``column``: the previous
    multiple of the indent width."""
    if column <= 0:
        return 0
    return (column - 1) // INDENT_WIDTH * INDENT_WIDTH


def next_tab_column(column: int) -> int:
    return (column // INDENT_WIDTH + 1) * INDENT_WIDTH


Edit = tuple[int, int, int, str]            # (line index, column, characters removed, text inserted)


def comment_edits(lines: Sequence[str]) -> list[Edit]:
    """Edits toggling ``// `` on these lines.

    When every non-blank line is commented, the comment marks (and one space after them)
    are removed; otherwise ``// `` is added to each non-blank line at the smallest
    indentation among them, so the block keeps its shape. Blank lines are left alone.
    """
    filled = [(i, line) for i, line in enumerate(lines) if line.strip()]
    if not filled:
        return []
    if all(line.lstrip().startswith(COMMENT) for _, line in filled):
        edits = []
        for i, line in filled:
            col = len(leading_indent(line))
            width = len(COMMENT) + (1 if line[col + len(COMMENT):col + len(COMMENT) + 1] == " " else 0)
            edits.append((i, col, width, ""))
        return edits
    col = min(len(leading_indent(line)) for _, line in filled)
    return [(i, col, 0, COMMENT + " ") for i, _ in filled]


def apply_edits(lines: Sequence[str], edits: Iterable[Edit]) -> list[str]:
    out = list(lines)
    for i, col, removed, inserted in edits:
        out[i] = out[i][:col] + inserted + out[i][col + removed:]
    return out


def toggle_comment(lines: Sequence[str]) -> list[str]:
    return apply_edits(lines, comment_edits(lines))
