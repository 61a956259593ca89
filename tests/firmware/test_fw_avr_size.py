"""The core fits its share of an ATmega32: at most 16 KB of flash and 1 KB of RAM (the rest is the board's)."""
import shutil
import subprocess

import pytest

from host_core import FIRMWARE, INSTALL_HINT

pytestmark = pytest.mark.skipif(not (shutil.which("avr-gcc") and shutil.which("avr-size") and shutil.which("make")),
                                reason=f"avr-gcc/avr-size not found: no ATmega32 build ({INSTALL_HINT})")


def sections(elf):
    out = subprocess.run(["avr-size", "-A", str(elf)], capture_output=True, text=True, check=True).stdout
    sizes = {}
    for line in out.splitlines():
        parts = line.split()
        if len(parts) >= 2 and parts[0].startswith(".") and parts[1].isdigit():
            sizes[parts[0]] = int(parts[1])
    return sizes


def test_the_core_fits_16_kb_of_flash_and_1_kb_of_ram():
    done = subprocess.run(["make", "-s", "-C", str(FIRMWARE), "atmega32"], capture_output=True, text=True)
    assert done.returncode == 0, done.stdout + done.stderr
    core = sections(FIRMWARE / "build" / "atmega32" / "core.elf")
    assert core[".text"] + core[".data"] <= 16 * 1024
    assert core[".data"] + core.get(".bss", 0) <= 1024
    whole = sections(FIRMWARE / "build" / "atmega32" / "zuml.elf")
    assert whole[".text"] + whole[".data"] <= 32 * 1024 and whole[".data"] + whole.get(".bss", 0) <= 2048 - 512
