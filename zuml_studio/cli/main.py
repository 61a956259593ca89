"""``zuml``: entry point. Each area registers its own subcommands."""
from __future__ import annotations

import argparse
import sys

from ..data import DataFileError
from . import (device_commands, firmware_command, fit_commands, lang_commands, log_commands, new_command,
               sim_commands, template_commands)
from .common import CliError

AREAS = (lang_commands, sim_commands, fit_commands, device_commands, template_commands, log_commands, new_command,
         firmware_command)


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="zuml", description="ZUML 2.0 charger macros: check, compile, "
                                     "simulate, flash.")
    sub = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    for area in AREAS:
        area.register(sub)
    return parser


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    try:
        return args.run(args)
    except CliError as exc:
        sys.stderr.write(f"zuml: error: {exc}\n")
        return exc.code
    except DataFileError as exc:
        sys.stderr.write(f"zuml: error: {exc}\n")
        return 2
    except KeyboardInterrupt:
        sys.stderr.write("zuml: interrupted\n")
        return 130
    except BrokenPipeError:
        return 0


if __name__ == "__main__":
    sys.exit(main())
