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

from .. import i18n
from ..data import DataFileError
from ..errors import ZumlError
from ..error_words import describe_error
from ..i18n import N_, _
from .common import CliError, GuardedOutput, OutputError, silence

AREAS: dict[str, dict[str, str]] = {
    "lang_commands": {
        "check": N_("check macros and print their errors and warnings"),
        "compile": N_("compile a macro to its byte record"),
        "decompile": N_("print the canonical text of a byte record"),
        "image": N_("pack records into an EEPROM image, or list one"),
    },
    "sim_commands": {
        "simulate": N_("run a macro's byte code against a battery model"),
    },
    "fit_commands": {
        "fit": N_("fit a chemistry's battery model to a real charge or discharge log"),
        "compare": N_("simulate a macro from a real log's start and compare the two"),
    },
    "device_commands": {
        "ports": N_("list serial ports (and how to get a virtual charger)"),
        "slots": N_("list the macros in a charger's EEPROM"),
        "flash": N_("write macros to the charger (each replaces the one of its name, or is appended)"),
        "backup": N_("save the charger's whole EEPROM image"),
        "restore": N_("write a saved EEPROM image back to the charger"),
        "run": N_("start the macro in a slot"),
        "stop": N_("stop the running macro"),
        "monitor": N_("print telemetry and events as they come (Ctrl+C ends)"),
        "passport": N_("read (or write fields of) the battery's passport"),
        "virtual-charger": N_("run a simulated charger behind a serial port (pty) or TCP"),
        "replay": N_("play a charger recording onto a serial port (pty) at its recorded pace"),
    },
    "template_commands": {
        "templates": N_("list, read or store the charger's start templates (START_SHABLON)"),
    },
    "log_commands": {
        "log": N_("read a charger's log file: summary, CSV export"),
    },
    "pack_commands": {
        "pack": N_("the battery logbook: packs, their sessions, trends and health"),
    },
    "new_command": {
        "new": N_("write a new macro for a chemistry, pack and charge rate"),
    },
    "firmware_command": {
        "firmware-sim": N_("run the charger firmware (ATmega32 on simavr, or the host build) behind a pty; "
                        "prints the port"),
    },
    "calibrate_command": {
        "calibrate": N_("calibrate an iMAX B6 running the ZUML firmware against your multimeter"),
    },
    "firmware_install_command": {
        "firmware": N_("install the ZUML firmware on an iMAX B6 with avrdude, or restore the original"),
    },
}


def area_of(command: str) -> str | None:
    return next((module for module, commands in AREAS.items() if command in commands), None)


def build_parser(command: str | None = None) -> argparse.ArgumentParser:
    """The parser with ``command``'s module registered in full (None: every module); every
    other command is a name with its help line, enough to list it and to pick it."""
    parser = argparse.ArgumentParser(prog="zuml",
                                     description=_("ZUML 2.0 charger macros: check, compile, simulate, flash."))
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    wanted = area_of(command) if command is not None else None
    for module, commands in AREAS.items():
        if command is None or module == wanted:
            importlib.import_module(f"{__package__}.{module}").register(sub)
        else:
            for name, help_line in commands.items():
                sub.add_parser(name, help=_(help_line), add_help=False)
    return parser


def main(argv: list[str] | None = None) -> int:
    # Before anything is printed, argparse's own words included (usage:, error:).
    try:
        i18n.install(i18n.choose_language())
    except DataFileError as exc:
        sys.stderr.write(f"zuml: error: {exc}\n")   # no catalogue to say it in: English
        return 2
    i18n.translate_argparse()
    argv = sys.argv[1:] if argv is None else list(argv)
    command = next((a for a in argv if not a.startswith("-")), "")
    args = build_parser(command).parse_args(argv)
    real = sys.stdout
    sys.stdout = GuardedOutput(real)
    try:
        code = args.run(args)
        sys.stdout.flush()          # a full disk at the last flush is said too, not left to the exit
        return code
    except OutputError as exc:
        silence(real)
        sys.stderr.write(_("zuml: error: {exc}\n").format(exc=exc))
        return exc.code
    except CliError as exc:
        sys.stderr.write(_("zuml: error: {exc}\n").format(exc=exc))
        return exc.code
    except ZumlError as exc:        # a broken installation, or any failure a command left unworded: one line
        sys.stderr.write(_("zuml: error: {exc}\n").format(exc=describe_error(exc, sentence=False)))
        return 2
    except KeyboardInterrupt:
        sys.stderr.write(_("zuml: interrupted\n"))
        return 130
    except BrokenPipeError:
        return 0
    finally:
        sys.stdout = real


if __name__ == "__main__":
    sys.exit(main())
