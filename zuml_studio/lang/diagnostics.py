"""Diagnostics: what is wrong, where, and what to do about it."""
from __future__ import annotations

from dataclasses import dataclass
from enum import Enum

from ..i18n import _


class Severity(str, Enum):
    """ERROR: nothing compiles or flashes. WARNING: the macro may be wrong or dangerous as written.
    NOTE: a fact the author should know that needs no change (a value left to be entered at start)."""
    ERROR = "error"
    WARNING = "warning"
    NOTE = "note"


@dataclass(frozen=True)
class Diagnostic:
    """``line``/``column`` are 1-based; ``end`` is (line, column) just past the marked text."""

    severity: Severity
    line: int
    column: int
    end: tuple[int, int]
    code: str
    message: str
    hint: str = ""
    fix: str = ""           # text that replaces the marked text ("did you mean X?": X), '' for none

    @property
    def is_error(self) -> bool:
        return self.severity is Severity.ERROR

    @property
    def is_warning(self) -> bool:
        return self.severity is Severity.WARNING

    def render(self, filename: str) -> str:
        """``FILE:LINE:COL: error: MESSAGE [CODE]`` as ``zuml check`` prints it."""
        severity = _("error") if self.is_error else _("warning") if self.is_warning else _("note")
        text = f"{filename}:{self.line}:{self.column}: {severity}: {self.message} [{self.code}]"
        return text + ("\n    " + _("hint: {hint}").format(hint=self.hint) if self.hint else "")


RANK = {Severity.ERROR: 0, Severity.WARNING: 1, Severity.NOTE: 2}      # the worst first


def sort_key(d: Diagnostic) -> tuple[int, int, int]:
    return (d.line, d.column, RANK[d.severity])
