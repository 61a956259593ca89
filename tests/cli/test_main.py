"""The command table: ``zuml --help`` lists every command without importing its module, and
each module registers exactly the commands (and help lines) the table says."""
import argparse
import importlib
import subprocess
import sys

import pytest

from helpers import MACROS
from zuml_studio.cli.main import AREAS, build_parser


@pytest.mark.parametrize("module", sorted(AREAS))
def test_each_module_registers_the_commands_and_help_of_its_table_entry(module):
    parser = argparse.ArgumentParser()
    sub = parser.add_subparsers()
    importlib.import_module(f"zuml_studio.cli.{module}").register(sub)
    registered = {action.dest: action.help for action in sub._choices_actions}
    assert registered == AREAS[module]


def test_the_full_parser_knows_every_command():
    parser = build_parser()
    sub = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
    assert set(sub.choices) == {name for commands in AREAS.values() for name in commands}


def _modules_after(*argv: str) -> set[str]:
    code = ("import sys; from zuml_studio.cli.main import main\n"
            "try:\n    main(sys.argv[1:])\nexcept SystemExit:\n    pass\n"
            "print(' '.join(sorted(sys.modules)))")
    out = subprocess.run([sys.executable, "-c", code, *argv], capture_output=True, text=True, check=True).stdout
    return set(out.split("\n")[-2].split())


def test_help_and_check_import_neither_numpy_nor_the_simulator_nor_the_device_code():
    for argv in (["--help"], ["check", str(MACROS / "NiMh.zuml")]):
        loaded = _modules_after(*argv)
        assert not {"numpy", "serial", "zuml_studio.sim.interpreter", "zuml_studio.device.zuml.client",
                    "zuml_studio.cli.sim_commands", "zuml_studio.cli.device_commands"} & loaded, argv
