"""The iMAX B6 image fits its ATmega32: 32 KB of flash, and 2 KB of RAM with room left for the stack (its
measured high-water mark is in docs/firmware.md, *Budgets*)."""
import subprocess


from host_core import FIRMWARE
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


def test_the_b6_image_fits_32_kb_of_flash_and_leaves_the_stack_its_ram():
    done = subprocess.run(["make", "-s", "-C", str(FIRMWARE), "imaxb6", "atmega32"], capture_output=True, text=True)
    assert done.returncode == 0, done.stdout + done.stderr
    b6 = sections(FIRMWARE / "build" / "imaxb6" / "zuml.elf")
    flash, ram = b6[".text"] + b6[".data"], b6[".data"] + b6.get(".bss", 0)
    # the figures docs/firmware.md quotes (*Sizes*, *Budgets*): `./dev test tests/firmware/test_fw_avr_size.py -s`
    print(f"\nthe iMAX B6 image: {flash} B of 32 KB flash, {ram} B of 2 KB RAM ({2048 - ram} B for the stack)")
    assert flash <= 32 * 1024
    assert ram <= 2048 - STACK_RESERVE
    generic = sections(FIRMWARE / "build" / "atmega32" / "zuml.elf")
    assert generic[".text"] + generic[".data"] <= 32 * 1024
