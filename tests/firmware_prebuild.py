"""The firmware built once before pytest-xdist starts its workers: tests (and the `zuml` commands they start)
`make` the images they need, and two workers making the same missing target at once would write the same files
together. Built here first, every later `make` finds its target up to date and writes nothing."""
import shutil
import subprocess

from chargers import simavr_missing
from b6_sim import FIRMWARE

AVR_TOOLS = ("avr-gcc", "avr-size", "avr-objcopy")


def targets() -> list[str]:
    """The make targets this machine has the tools for (the tests needing the others skip, saying why)."""
    if not (shutil.which("make") and shutil.which("gcc")):
        return []
    if not simavr_missing():
        return ["host", "atmega32", "imaxb6", "simavr", "simavr-imaxb6"]
    return ["host", "atmega32", "imaxb6"] if all(shutil.which(t) for t in AVR_TOOLS) else ["host"]


def build() -> None:
    """`make` them; a failure is left to the tests, whose own `make` then reports it with the compiler's output."""
    wanted = targets()
    if wanted:
        subprocess.run(["make", "-s", "-C", str(FIRMWARE), *wanted], capture_output=True)
