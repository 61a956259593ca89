"""Shared test helpers: paths of the project's files, seed macros compiled, platform marks."""
import os
from pathlib import Path

import pytest

from zuml_studio.data import standard_macros_dir
from zuml_studio.lang.compiler import compile_source

ROOT = Path(__file__).resolve().parent.parent
MACROS = standard_macros_dir()
SEED_MACROS = ("Pb", "NiCd", "NiMh", "LiPo", "LiIon", "LiFe")


def seed_text(name: str) -> str:
    return (MACROS / f"{name}.zuml").read_text()


def compiled(name_or_text: str) -> bytes:
    """The record of a standard macro (by name), or of a macro's text."""
    result = compile_source(name_or_text if "\n" in name_or_text else seed_text(name_or_text))
    assert result.ok, result.diagnostics
    return result.record


needs_pty = pytest.mark.skipif(os.name != "posix", reason="ptys need POSIX")
