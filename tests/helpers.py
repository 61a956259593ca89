"""Shared test helpers: paths of the project's files, seed macros compiled, platform marks."""
import os
import re
import time
from pathlib import Path

import pytest

from zuml_studio.data import standard_macros_dir
from zuml_studio.lang.compiler import compile_source

ROOT = Path(__file__).resolve().parent.parent
MACROS = standard_macros_dir()
SEED_MACROS = ("Pb", "NiCd", "NiMh", "LiPo", "LiIon", "LiFe")


def seed_text(name: str) -> str:
    return (MACROS / f"{name}.zuml").read_text()


def bare_seed(name: str) -> str:
    """A seed macro's text without the comments that say why its warnings are right (for tests that
    edit its lines and compare them)."""
    return re.sub(r"  //[^\n]*", "", seed_text(name))


def compiled(name_or_text: str) -> bytes:
    """The record of a standard macro (by name), or of a macro's text."""
    result = compile_source(name_or_text if "\n" in name_or_text else seed_text(name_or_text))
    assert result.ok, result.diagnostics
    return result.record


needs_pty = pytest.mark.skipif(os.name != "posix", reason="ptys need POSIX")


# A LiIon macro that charges to 4.96 V per cell: E303 (the absolute maximum is 4.25 V), yet a
# 1-cell LiIon passport's whole-volt V_LIMIT (5 V) lets it through.
HOT_LIION = """MACRO Hot
  AKK_TYPE=LiIon
  SERIES=1
  CHARGE_SECTION
    FAZE
      CONSTANT_I=1A
      IF(V>4.96S) STOP_FAZE
    END_FAZE
    FAZE
      CONSTANT_V=4.96S
      IF(I<0.1A) STOP_FAZE
    END_FAZE
  END_SECTION
END_MACRO
"""


def unsafe_record(text: str = HOT_LIION) -> bytes:
    """The bytes of a macro the safety lint refuses (compiled with the user's override)."""
    result = compile_source(text, unsafe_ok=True)
    assert result.ok, result.diagnostics
    return result.record


def lose_link_after_commit(monkeypatch, commit_arrives=True, confirmed=True):
    """Once: the link fails right after COMMIT (its answer lost or not), as a pulled cable would."""
    from zuml_studio.device.zuml.client import ChargerClient
    from zuml_studio.device.errors import Disconnected
    real = ChargerClient.request
    state = {"done": False, "committed": False}

    def request(self, name, payload, **kw):
        if state["done"]:
            return real(self, name, payload, **kw)
        if name == "COMMIT":
            if commit_arrives:
                real(self, name, payload, **kw)
            state["committed"] = True
            if not confirmed:
                state["done"] = True
                raise Disconnected("the connection was lost")
            return real(self, name, payload, **kw)      # a repeated COMMIT: answered, not done twice
        if name == "READ_EEPROM" and state["committed"]:
            state["done"] = True
            raise Disconnected("the connection was lost")
        return real(self, name, payload, **kw)
    monkeypatch.setattr(ChargerClient, "request", request)


def contrast_ratio(a, b) -> float:
    """WCAG contrast ratio of two QColors (4.5 is the least for normal text)."""
    def lum(c) -> float:
        def ch(v: float) -> float:
            return v / 12.92 if v <= 0.03928 else ((v + 0.055) / 1.055) ** 2.4
        return 0.2126 * ch(c.redF()) + 0.7152 * ch(c.greenF()) + 0.0722 * ch(c.blueF())
    hi, lo = sorted((lum(a), lum(b)), reverse=True)
    return (hi + 0.05) / (lo + 0.05)


# A bound on a wait for a GUI state (qtbot.waitUntil / waitSignal), far above what a loaded machine takes:
# a wait returns as soon as the state comes, so a generous bound costs nothing and a hang still fails.
WAIT_MS = 30_000


def until(predicate, timeout_s: float = 30.0) -> bool:
    """Poll for a state another thread or process brings about; False if it has not come by the (generous)
    bound. Tests wait for states, never for a time."""
    deadline = time.monotonic() + timeout_s
    while not predicate():
        if time.monotonic() > deadline:
            return False
        time.sleep(0.01)
    return True
