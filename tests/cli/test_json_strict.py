"""Every ``--json`` output is strict JSON (RFC 8259: no NaN, no Infinity); a figure that is no finite
number is ``null`` (issue 27: ``zuml compare --json`` printed ``Infinity``, ``zuml log info --json`` NaN).

One case per command that has ``--json``: the command runs on a real input with a non-finite figure
slipped into what it computed, and its output must parse with a parser that refuses NaN and Infinity.
A command that gains ``--json`` fails
``test_every_command_with_json_has_a_case`` until it has a case here."""
import argparse
import json
import math

import pytest

from helpers import MACROS, ROOT
from zuml_studio.cli import fit_commands, log_commands
from zuml_studio.cli.main import build_parser, main
from zuml_studio.sim import compare as compare_module
from zuml_studio.sim import simulate as simulate_module

CURVE = ROOT / "tests" / "data" / "curves" / "lipo_4s_406duo_3c.csv"
LOG = ROOT / "tests" / "data" / "logs" / "308DUO_LiFe_2.3Ah_Laden_0_CH1.txt"
HOSTILE = (math.nan, math.inf, -math.inf)


def _poison(value: dict) -> dict:
    return {**value, "hostile": list(HOSTILE), "nested": {"figure": math.nan}}


def _simulate(monkeypatch):
    real = simulate_module.SimResult.to_json
    monkeypatch.setattr(simulate_module.SimResult, "to_json", lambda self: _poison(real(self)))
    return "simulate", str(MACROS / "LiPo.zuml"), "--series", "3", "--capacity", "1000", "--current", "1"


def _log_info(monkeypatch):
    real = log_commands.summarize
    monkeypatch.setattr(log_commands, "summarize", lambda log: _poison(real(log)))
    return "log", "info", str(LOG)


def _fit(monkeypatch):
    real = fit_commands.fit_curve

    def poisoned(*args, **kwargs):
        result = real(*args, max_nfev=2, only_capacity=True, **kwargs)
        result.figures.update(_poison({}))
        return result
    monkeypatch.setattr(fit_commands, "fit_curve", poisoned)
    return "fit", str(CURVE), "--chemistry", "LiPo", "--cells", "4"


def _compare(monkeypatch):
    real = compare_module.compare

    def poisoned(*args, **kwargs):
        result = real(*args, **kwargs)
        result.report.update(_poison({}))
        return result
    monkeypatch.setattr(compare_module, "compare", poisoned)
    return "compare", str(CURVE), str(MACROS / "LiPo.zuml"), "--cells", "4", "--capacity", "1500"


def _pack(words: tuple[str, ...]):
    """A pack with one real log in it (the data folder is the test session's, tests/conftest.py)."""
    def setup(monkeypatch, tmp_path):
        from zuml_studio.cli import pack_commands
        monkeypatch.setenv("ZUML_STUDIO_DATA_DIR", str(tmp_path))
        assert main(["pack", "add", "P", "--chemistry", "LiFe", "--cells", "2", "--capacity", "2300"]) == 0
        assert main(["pack", "import", str(LOG), "--pack", "P"]) == 0
        real = pack_commands.pack_summary
        monkeypatch.setattr(pack_commands, "pack_summary", lambda book, pack: _poison(real(book, pack)))
        return (*words, "P") if words[-1] == "show" else words
    return setup


# (command words as argparse names them) -> a setup that patches and returns the arguments
CASES = {("simulate",): _simulate, ("log", "info"): _log_info, ("fit",): _fit, ("compare",): _compare,
         ("pack", "list"): _pack(("pack", "list")), ("pack", "show"): _pack(("pack", "show"))}


def _commands_with_json(parser, words=()) -> set[tuple[str, ...]]:
    found = set()
    for action in parser._actions:
        if "--json" in getattr(action, "option_strings", ()):
            found.add(words)
        if isinstance(action, argparse._SubParsersAction):
            for name, child in action.choices.items():
                found |= _commands_with_json(child, words + (name,))
    return found


def _strict(text: str):
    def refuse(constant):
        raise AssertionError(f"not JSON: {constant}")
    return json.loads(text, parse_constant=refuse)


def test_every_command_with_json_has_a_case():
    assert _commands_with_json(build_parser()) == set(CASES)


@pytest.mark.parametrize("words", sorted(CASES), ids=" ".join)
def test_json_is_strict_and_a_missing_figure_is_null(zuml, monkeypatch, tmp_path, words):
    setup = CASES[words]
    args = setup(monkeypatch, tmp_path) if words[0] == "pack" else setup(monkeypatch)
    code, out, err = zuml(*args, "--json")
    assert code == 0, err
    data = _strict(out)
    data = data["packs"][0] if words == ("pack", "list") else data
    assert data["hostile"] == [None, None, None] and data["nested"] == {"figure": None}
