"""The iMAX B6 image fits its ATmega32: 32 KB of flash, and 2 KB of RAM with room left for the stack (its
measured high-water mark is in docs/firmware.md, *Budgets*)."""
import re
import subprocess

from host_core import FIRMWARE, ROOT
from tools import AVR, needs

pytestmark = needs(AVR)

STACK_RESERVE = 640     # the measured high-water mark (513 B) and room for what a test run did not reach


def sections(elf):
    out = subprocess.run(["avr-size", "-A", str(elf)], capture_output=True, text=True, check=True).stdout
    sizes = {}
    for line in out.splitlines():
        parts = line.split()
        if len(parts) >= 2 and parts[0].startswith(".") and parts[1].isdigit():
            sizes[parts[0]] = int(parts[1])
    return sizes


def flash_and_ram(elf):
    sizes = sections(elf)
    return sizes[".text"] + sizes[".data"], sizes[".data"] + sizes.get(".bss", 0)


def quoted(row: str) -> tuple[int, int]:
    """The flash and RAM figures docs/firmware.md's *Budgets (measured)* table gives in the row that begins so."""
    text = (ROOT / "docs" / "firmware.md").read_text(encoding="utf-8")
    budgets = text[text.index("### Budgets (measured)"):]
    line = next(line for line in budgets.splitlines() if line.startswith(f"| {row}"))
    flash, ram = (int(m.replace(" ", "")) for m in re.findall(r"(\d[\d ]*) B", line)[:2])
    return flash, ram


def test_the_b6_image_fits_32_kb_of_flash_and_leaves_the_stack_its_ram():
    done = subprocess.run(["make", "-s", "-C", str(FIRMWARE), "imaxb6", "atmega32", "build/atmega32/core.elf"],
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stdout + done.stderr
    flash, ram = flash_and_ram(FIRMWARE / "build" / "imaxb6" / "zuml.elf")
    print(f"\nthe iMAX B6 image: {flash} B of 32 KB flash, {ram} B of 2 KB RAM ({2048 - ram} B for the stack)")
    assert flash <= 32 * 1024
    assert ram <= 2048 - STACK_RESERVE
    generic = flash_and_ram(FIRMWARE / "build" / "atmega32" / "zuml.elf")
    assert generic[0] <= 32 * 1024
    # the docs quote what is measured here, so a change of size is a change of the docs too
    assert quoted("the iMAX B6 image") == (flash, ram)
    assert quoted("the generic image") == generic
    assert quoted("the core alone") == flash_and_ram(FIRMWARE / "build" / "atmega32" / "core.elf")
