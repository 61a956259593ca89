"""Safety lint: warnings about macros that are legal but likely to hurt a battery.

Rules are added here as (function) entries; each returns Findings on the AST.
"""
from __future__ import annotations

from .ast import Macro
from .checker import Finding


def lint(macro: Macro) -> list[Finding]:
    return []
