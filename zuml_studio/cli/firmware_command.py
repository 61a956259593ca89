"""zuml firmware-sim: the charger firmware (C, `firmware/`) behind a pty: the ATmega32 image on simavr
(default), or the host build."""
from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
from pathlib import Path

from .common import CliError
from ..i18n import _

FIRMWARE = Path(__file__).resolve().parents[2] / "firmware"
BUILD = FIRMWARE / "build"
INSTALL = "apt-get install -y make gcc gcc-avr avr-libc binutils-avr simavr libsimavr-dev libelf-dev"
# per board: make targets, the tools they need, the command that runs the device
BOARDS = {
    "atmega32": (("atmega32", "simavr"), ("make", "gcc", "avr-gcc", "avr-size"),
                 [str(BUILD / "simavr" / "zuml_avr_sim"), str(BUILD / "atmega32" / "zuml.elf")]),
    "host": (("host",), ("make", "gcc"), [str(BUILD / "host" / "zuml_host")]),
}


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("firmware-sim", help=_("run the charger firmware (ATmega32 on simavr, or the host build) "
                                              "behind a pty; prints the port"))
    p.add_argument("--board", choices=sorted(BOARDS), default="atmega32",
                   help=_("atmega32: the AVR image on simavr (default); host: the same C built for this PC"))
    p.add_argument("--eeprom", type=Path, metavar="FILE", help=_("the EEPROM, kept in this file (default: in memory)"))
    p.add_argument("--cells", type=int, default=3, help=_("cells of the simulated battery (default 3)"))
    p.add_argument("--capacity", type=float, default=2000, metavar="MAH", help=_("its capacity (default 2000)"))
    p.add_argument("--soc", type=float, default=0.2, help=_("its state of charge at start, 0..1 (default 0.2)"))
    p.set_defaults(run=cmd_firmware_sim)


def build_device(board: str) -> list[str]:
    """`make` the board's targets in firmware/ (a no-op when up to date); the device's command."""
    targets, tools, command = BOARDS[board]
    if not (FIRMWARE / "Makefile").is_file():
        raise CliError(_("the firmware sources are not here ({firmware}): run from a ZUML Studio checkout").format(
                firmware=FIRMWARE))
    missing = [tool for tool in tools if shutil.which(tool) is None]
    if missing:
        raise CliError(_("{missing} not found: the firmware cannot be built ({install})").format(
                missing=', '.join(missing), install=INSTALL))
    done = subprocess.run(["make", "-s", "-C", str(FIRMWARE), *targets], capture_output=True, text=True)
    if done.returncode != 0:
        raise CliError(f"the firmware did not build ({INSTALL}?):\n{done.stdout}{done.stderr}".rstrip())
    return list(command)


def cmd_firmware_sim(args: argparse.Namespace) -> int:
    if os.name != "posix":
        raise CliError(_("firmware-sim needs a POSIX pty (Linux, macOS)"))
    if not 1 <= args.cells <= 8 or args.capacity <= 0 or not 0.0 <= args.soc <= 1.0:
        raise CliError(_("--cells is 1..8, --capacity above 0, --soc 0..1"))
    argv = build_device(args.board) + ["--cells", str(args.cells), "--capacity", str(args.capacity),
                                       "--soc", str(args.soc)]
    if args.eeprom:
        argv += ["--eeprom", str(args.eeprom)]
    sys.stdout.flush()
    # The device prints its pty alone on the first line and runs until SIGTERM/Ctrl+C.
    os.execv(argv[0], argv)
    return 0
