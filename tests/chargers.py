"""Every device test that needs only a port runs against both chargers: the Python virtual
charger and the C firmware (`zuml firmware-sim`: the ATmega32 image on simavr), so the two answer
alike. The firmware runs skip, naming the tool they lack, where simavr or avr-gcc are missing."""
import subprocess
import sys
from dataclasses import dataclass
from pathlib import Path

import pytest

from tools import SIMAVR, needs

NEEDS_FIRMWARE_SIM = needs(SIMAVR)
FIRMWARE_SIM = pytest.param("firmware-sim", marks=NEEDS_FIRMWARE_SIM)
KINDS = ["virtual", FIRMWARE_SIM]


@dataclass
class Charger:
    kind: str                          # "virtual" or "firmware-sim"
    port: str
    device: object = None              # the VirtualCharger (None for the firmware)

    @property
    def virtual(self) -> bool:
        return self.kind == "virtual"


class FirmwareSims:
    """`zuml firmware-sim` subprocesses, each with its EEPROM in a file of its own; stopped at the end."""

    def __init__(self, tmp_path: Path):
        self.tmp_path = tmp_path
        self.procs: list[subprocess.Popen] = []

    def start(self, *args: str) -> str:
        eeprom = self.tmp_path / f"fw-ee-{len(self.procs)}.bin"
        # its events go to a file: a pipe nobody reads would fill and stop the simulator mid-run
        events = self.tmp_path / f"fw-{len(self.procs)}.stderr"
        with open(events, "w") as err:
            proc = subprocess.Popen([sys.executable, "-m", "zuml_studio.cli.main", "firmware-sim", "--eeprom",
                                     str(eeprom), *args], stdout=subprocess.PIPE, stderr=err, text=True)
        self.procs.append(proc)
        port = proc.stdout.readline().strip()
        if not port.startswith("/dev/"):
            proc.wait(timeout=10)
            raise AssertionError(f"firmware-sim did not start: {port} {events.read_text()}")
        return port

    def stop(self) -> None:
        for proc in self.procs:
            proc.terminate()
            try:
                proc.wait(timeout=10)
            except subprocess.TimeoutExpired:
                proc.kill()
                proc.wait()
            proc.stdout.close()
