"""zuml firmware install / restore: the ZUML firmware onto an iMAX B6 with avrdude and an ISP programmer
(a USBasp by default), after saving the original; the original back from that backup."""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

from ..i18n import _
from .common import CliError

def add_programmer_options(p: argparse.ArgumentParser) -> None:
    p.add_argument("--programmer", default="usbasp", metavar="ID",
                   help=_("avrdude's programmer id (-c), default usbasp; e.g. stk500v1, avrisp, arduino"))
    p.add_argument("--port", metavar="PORT", help=_("the programmer's port (-P), for serial programmers"))
    p.add_argument("--baud", type=int, metavar="N", help=_("the programmer's baud rate (-b)"))


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("firmware", help=_("install the ZUML firmware on an iMAX B6 with avrdude, or restore "
                                          "the original"))
    actions = p.add_subparsers(dest="firmware_command", required=True, metavar="ACTION")
    install = actions.add_parser("install", help=_("save the original flash and EEPROM, check the fuses (BOD), "
                                                   "write and verify the ZUML image"))
    add_programmer_options(install)
    install.add_argument("--image", type=Path, metavar="FILE",
                         help=_("the image to write (.elf, .hex or .bin; default: the imaxb6 image, built)"))
    install.add_argument("--backup-dir", type=Path, metavar="DIR",
                         help=_("where the original is saved: a new or empty folder (default: a new folder in the "
                                "settings folder)"))
    install.add_argument("--fix-fuses", action="store_true",
                         help=_("set the fuses the B6 needs where they differ: brown-out at 4.0 V, the 16 MHz "
                                "crystal, JTAG off (docs/firmware.md)"))
    install.add_argument("--no-way-back", action="store_true",
                         help=_("install even when the charger's original cannot be read (a locked chip): it is "
                                "then lost for good"))
    install.add_argument("--yes", action="store_true", help=_("do not ask: the warnings are read"))
    install.set_defaults(run=cmd_install)
    restore = actions.add_parser("restore", help=_("write a backup made by install back (flash, EEPROM, fuses)"))
    restore.add_argument("backup", metavar="BACKUP", type=Path, help=_("the backup folder install printed"))
    add_programmer_options(restore)
    restore.set_defaults(run=cmd_restore)


def programmer(args: argparse.Namespace):
    from ..device.install.avrdude import Programmer
    if args.baud is not None and not 300 <= args.baud <= 2_000_000:
        raise CliError(_("--baud is 300..2000000"))
    return Programmer(args.programmer, args.port, args.baud)


def say(line: str) -> None:
    print(line, flush=True)


def confirmed(yes: bool) -> bool:
    from ..device.install.avr_install import warnings
    for line in warnings():
        sys.stderr.write(_("warning: {line}\n").format(line=line))
    if yes:
        return True
    if not sys.stdin.isatty():
        raise CliError(_("the warnings above need an answer: add --yes to install without a question"))
    return input(_("Install the ZUML firmware? Type yes: ")).strip().lower() in ("yes", _("yes"))


def cmd_install(args: argparse.Namespace) -> int:
    from ..device.install import avr_install
    from ..device.install.avrdude import ProgrammerError, avrdude_path
    chosen = programmer(args)
    try:
        avrdude_path()
    except ProgrammerError as exc:
        raise CliError(str(exc)) from None
    if not confirmed(args.yes):
        raise CliError(_("not installed"), 1)
    folder = args.backup_dir or avr_install.default_backup_folder()
    try:
        image = args.image or avr_install.build_image()
        avr_install.install(chosen, image, folder, args.fix_fuses, say, args.no_way_back)
    except ProgrammerError as exc:
        raise CliError(str(exc), 1) from None
    say(_("To put the backup back: {command}").format(command=avr_install.restore_command(chosen, folder)))
    return 0


def cmd_restore(args: argparse.Namespace) -> int:
    from ..device.install import avr_install
    from ..device.install.avrdude import ProgrammerError
    chosen = programmer(args)
    try:
        avr_install.restore(chosen, args.backup, say)
    except ProgrammerError as exc:
        raise CliError(str(exc), 1) from None
    return 0
