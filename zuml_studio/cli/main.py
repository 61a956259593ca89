"""``zuml``: entry point. Each area registers its own subcommands.

Only the module of the command being run is imported: ``zuml check`` does not load numpy,
the simulator or the serial port code, and ``zuml --help`` loads none of them (the command
list and its one-line help come from ``AREAS``). A module of commands is one entry there:
its module name and, for each command it registers, the help line that ``zuml --help``
shows (tests/cli/test_main.py checks that the two agree)."""
from __future__ import annotations

import argparse
import importlib
import sys

from ..data import DataFileError
from .common import CliError
from ..i18n import _

AREAS: dict[str, dict[str, str]] = {
    "lang_commands": {
        "check": "check macros and print their errors and warnings",
        "compile": "compile a macro to its byte record",
        "decompile": "print the canonical text of a byte record",
        "image": "pack records into an EEPROM image, or list one",
    },
    "sim_commands": {
        "simulate": "run a macro's byte code against a battery model",
    },
    "fit_commands": {
        "fit": "fit a chemistry's battery model to a real charge log",
        "compare": "simulate a macro from a real log's start and compare the two",
    },
    "device_commands": {
        "ports": "list serial ports (and how to get a virtual charger)",
        "slots": "list the macros in a charger's EEPROM",
        "flash": "write a macro to the charger (replace by name, or append)",
        "backup": "save the charger's whole EEPROM image",
        "restore": "write a saved EEPROM image back to the charger",
        "run": "start the macro in a slot",
        "stop": "stop the running macro",
        "monitor": "print telemetry and events as they come (Ctrl+C ends)",
        "passport": "read (or write fields of) the battery's passport",
        "virtual-charger": "run a simulated charger behind a serial port (pty) or TCP",
        "replay": "play a charger recording onto a serial port (pty) at its recorded pace",
    },
    "template_commands": {
        "templates": "list, read or store the charger's start templates (START_SHABLON)",
    },
    "log_commands": {
        "log": "read a charger's log file: summary, CSV export",
    },
    "new_command": {
        "new": "write a new macro for a chemistry, pack and charge rate",
    },
    "firmware_command": {
        "firmware-sim": "run the charger firmware (ATmega32 on simavr, or the host build) behind a pty; "
                        "prints the port",
    },
}


def area_of(command: str) -> str | None:
    return next((module for module, commands in AREAS.items() if command in commands), None)


def build_parser(command: str | None = None) -> argparse.ArgumentParser:
    """The parser with ``command``'s module registered in full (None: every module); every
    other command is a name with its help line, enough to list it and to pick it."""
    parser = argparse.ArgumentParser(prog="zuml", description=_("ZUML 2.0 charger macros: check, compile, simulate, flash."))
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    wanted = area_of(command) if command is not None else None
    for module, commands in AREAS.items():
        if command is None or module == wanted:
            importlib.import_module(f"{__package__}.{module}").register(sub)
        else:
            for name, help_line in commands.items():
                sub.add_parser(name, help=help_line, add_help=False)
    return parser


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else list(argv)
    command = next((a for a in argv if not a.startswith("-")), "")
    args = build_parser(command).parse_args(argv)
    try:
        return args.run(args)
    except CliError as exc:
        sys.stderr.write(_("zuml: error: {exc}\n").format(exc=exc))
        return exc.code
    except DataFileError as exc:
        sys.stderr.write(_("zuml: error: {exc}\n").format(exc=exc))
        return 2
    except KeyboardInterrupt:
        sys.stderr.write(_("zuml: interrupted\n"))
        return 130
    except BrokenPipeError:
        return 0


if __name__ == "__main__":
    sys.exit(main())
