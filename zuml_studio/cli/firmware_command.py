"""zuml firmware-sim: the charger firmware (C, `firmware/`) behind a pty: the ATmega32 image on simavr
(default), the imaxb6 image on a simulated iMAX B6, or the host build."""
from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

from .common import CliError
from ..virtual.firmware_sim import BOARDS, FirmwareBuildError, build_device
from ..i18n import _

FAULTS = ("disconnect", "reverse", "cell-high", "sensor-open", "sink-hot", "input-low", "hang", "slow-loop",
          "input-sag")
BUTTONS = ("start", "stop", "inc", "dec")


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("firmware-sim", help=_("run the charger firmware (ATmega32 on simavr, or the host build) "
                                              "behind a pty; prints the port"))
    p.add_argument("--board", choices=sorted(BOARDS), default="atmega32",
                   help=_("atmega32: the AVR image on simavr (default); imaxb6: the iMAX B6 image on a simulated B6 "
                          "with the real board's wiring; host: the same C built for this PC"))
    p.add_argument("--eeprom", type=Path, metavar="FILE", help=_("the EEPROM, kept in this file (default: in memory)"))
    p.add_argument("--cells", type=int, default=3, help=_("cells of the simulated battery (default 3)"))
    p.add_argument("--capacity", type=float, default=2000, metavar="MAH", help=_("its capacity (default 2000)"))
    p.add_argument("--soc", type=float, default=0.2, help=_("its state of charge at start, 0..1 (default 0.2)"))
    b6 = p.add_argument_group(_("the simulated iMAX B6 (--board imaxb6 only)"))
    b6.add_argument("--cell-spread", type=float, metavar="MV",
                    help=_("the cells start this far apart, lowest to highest (mV, default 0)"))
    b6.add_argument("--weak-cell", type=float, metavar="PCT",
                    help=_("the last cell holds PCT %% less capacity (0..90, default 0)"))
    b6.add_argument("--seed", type=int, help=_("draws the components' tolerances (default 0)"))
    b6.add_argument("--uncalibrated", action="store_true",
                    help=_("start with no calibration in the EEPROM (default: the one the calibration procedure "
                           "finds for this board)"))
    b6.add_argument("--fault", action="append", metavar="KIND@SECONDS",
                    help=_("inject a fault at that simulated time (repeatable); KIND: {kinds}").format(
                        kinds=", ".join(FAULTS)))
    b6.add_argument("--press", action="append", metavar="BUTTON@SECONDS[:HOLD]",
                    help=_("press a front-panel button at that simulated time, for 0.2 s or HOLD seconds "
                           "(repeatable); BUTTON: {buttons}").format(buttons=", ".join(BUTTONS)))
    b6.add_argument("--trace", type=Path, metavar="FILE",
                    help=_("write the model's true values every simulated ms as CSV: "
                           "t_ms,buck_duty,boost_duty,output_enabled,current_a,voltage_v,cell_max_v"))
    b6.add_argument("--lcd", action="store_true", help=_("print every change of the LCD on stderr as LCD|line1|line2"))
    b6.add_argument("--no-rx", action="store_true",
                    help=_("no receive wire: the PC's bytes reach nothing and the firmware only sends over TX (the "
                           "B6's 3-pin port); PD0 is then cell 4's balancer"))
    b6.add_argument("--no-balance-lead", action="store_true",
                    help=_("the pack's balance lead unplugged: every tap reads 0 V (a pack on its main leads only)"))
    b6.add_argument("--speed", type=float, metavar="X",
                    help=_("simulated seconds per wall-clock second (default 1; 0: as fast as this PC can)"))
    p.set_defaults(run=cmd_firmware_sim)


def timed_events(values: list[str] | None, names: tuple[str, ...], option: str, hold: bool) -> list[str]:
    """NAME@SECONDS[:HOLD] values checked (a one-line error naming the bad one), as the device takes them."""
    for value in values or []:
        name, at, when = value.partition("@")
        seconds, colon, held = when.partition(":")
        try:
            ok = name in names and at and 0 <= float(seconds) <= 1e7 and (not colon or hold and 0 < float(held) <= 1e6)
        except ValueError:
            ok = False
        if not ok:
            raise CliError(_("{option} {value}: expected {form}, NAME one of {names}").format(
                option=option, value=value, form="NAME@SECONDS[:HOLD]" if hold else "NAME@SECONDS",
                names=", ".join(names)))
    return list(values or [])


def b6_arguments(args: argparse.Namespace) -> list[str]:
    """The simulated B6's own options, as zuml_b6_sim takes them; refused for the other boards."""
    given = [name for name in ("cell_spread", "weak_cell", "seed", "fault", "press", "trace", "speed")
             if getattr(args, name) is not None] + [name for name in ("uncalibrated", "lcd", "no_rx", "no_balance_lead")
                                                 if getattr(args, name)]
    if args.board != "imaxb6":
        if given:
            raise CliError(_("--{option} is for --board imaxb6 (the simulated iMAX B6)").format(
                option=given[0].replace("_", "-")))
        return []
    if not 1 <= args.cells <= 6:
        raise CliError(_("--cells is 1..6 on the iMAX B6 (its balance port)"))
    if args.cell_spread is not None and not 0 <= args.cell_spread <= 1000:
        raise CliError(_("--cell-spread is 0..1000 mV"))
    if args.weak_cell is not None and not 0 <= args.weak_cell <= 90:
        raise CliError(_("--weak-cell is 0..90 %"))
    if args.seed is not None and not 0 <= args.seed <= 0xFFFFFFFF:
        raise CliError(_("--seed is 0..4294967295"))
    if args.speed is not None and not 0 <= args.speed <= 1e6:
        raise CliError(_("--speed is 0 (as fast as this PC can) or the simulated seconds per second"))
    argv = [item for name in ("cell_spread", "weak_cell", "seed", "speed") if getattr(args, name) is not None
            for item in ("--" + name.replace("_", "-"), str(getattr(args, name)))]
    argv += [item for value in timed_events(args.fault, FAULTS, "--fault", False) for item in ("--fault", value)]
    argv += [item for value in timed_events(args.press, BUTTONS, "--press", True) for item in ("--press", value)]
    if args.trace:
        argv += ["--trace", str(args.trace)]
    return argv + ["--uncalibrated"] * args.uncalibrated + ["--lcd"] * args.lcd + ["--no-rx"] * args.no_rx \
        + ["--no-balance-lead"] * args.no_balance_lead


def cmd_firmware_sim(args: argparse.Namespace) -> int:
    if os.name != "posix":
        raise CliError(_("firmware-sim needs a POSIX pty (Linux, macOS)"))
    if not 1 <= args.cells <= 8 or args.capacity <= 0 or not 0.0 <= args.soc <= 1.0:
        raise CliError(_("--cells is 1..8, --capacity above 0, --soc 0..1"))
    b6 = b6_arguments(args)
    try:
        argv = build_device(args.board)
    except FirmwareBuildError as exc:
        raise CliError(str(exc)) from None
    argv += ["--cells", str(args.cells), "--capacity", str(args.capacity), "--soc", str(args.soc)] + b6
    if args.eeprom:
        argv += ["--eeprom", str(args.eeprom)]
    sys.stdout.flush()
    # The device prints its pty alone on the first line and runs until SIGTERM/Ctrl+C.
    os.execv(argv[0], argv)
    return 0
