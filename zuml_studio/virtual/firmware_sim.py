"""The charger firmware built and run on this PC (`firmware/`): each simulated board's make targets, the
tools they need and the command that runs it (the ATmega32 image or the iMAX B6's on simavr, the host
build). ``zuml firmware-sim`` and the window's simulated iMAX B6 (simulated_b6.py) both start it from here."""
from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

from ..errors import ZumlError
from ..i18n import _

FIRMWARE = Path(__file__).resolve().parents[2] / "firmware"
BUILD = FIRMWARE / "build"
INSTALL = "apt-get install -y make gcc gcc-avr avr-libc binutils-avr simavr libsimavr-dev libelf-dev"
# per board: make targets, the tools they need, the command that runs the device
BOARDS = {
    "atmega32": (("atmega32", "simavr"), ("make", "gcc", "avr-gcc", "avr-size"),
                 [str(BUILD / "simavr" / "zuml_avr_sim"), str(BUILD / "atmega32" / "zuml.elf")]),
    "imaxb6": (("imaxb6", "simavr-imaxb6"), ("make", "gcc", "avr-gcc", "avr-size"),
               [str(BUILD / "simavr" / "zuml_b6_sim"), str(BUILD / "imaxb6" / "zuml.elf")]),
    "host": (("host",), ("make", "gcc"), [str(BUILD / "host" / "zuml_host")]),
}


class FirmwareBuildError(ZumlError):
    """The firmware cannot be built here: its sources, a tool or the build itself is missing; one line."""


def build_device(board: str) -> list[str]:
    """`make` the board's targets in firmware/ (a no-op when up to date); the device's command."""
    targets, tools, command = BOARDS[board]
    if not (FIRMWARE / "Makefile").is_file():
        raise FirmwareBuildError(_("the firmware sources are not here ({firmware}): run from a ZUML Studio "
                                   "checkout").format(firmware=FIRMWARE))
    missing = [tool for tool in tools if shutil.which(tool) is None]
    if missing:
        raise FirmwareBuildError(_("{missing} not found: the firmware cannot be built ({install})").format(
                missing=', '.join(missing), install=INSTALL))
    done = subprocess.run(["make", "-s", "-C", str(FIRMWARE), *targets], capture_output=True, text=True)
    if done.returncode != 0:
        raise FirmwareBuildError(f"the firmware did not build ({INSTALL}?):\n{done.stdout}{done.stderr}".rstrip())
    return list(command)
