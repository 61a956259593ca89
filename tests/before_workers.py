"""What the pytest-xdist controller does once before its workers start, so that no two workers write the same
files at once:

- the firmware is built: tests (and the `zuml` commands they start) `make` the images they need, and two
  workers making one missing target would write its files together; built here, every later `make` finds its
  target up to date and writes nothing;
- the package is byte-compiled: a worker importing a module for the first time writes its .pyc (through a
  temporary file) while the frozen-bundle test copies the package with `cp -r`, which fails on a file that
  vanishes under it."""
import compileall
import subprocess

from b6_sim import FIRMWARE
from tools import AVR, HOST, SIMAVR, missing
PACKAGE = FIRMWARE.parent / "zuml_studio"


def firmware_targets() -> list[str]:
    """The make targets this machine has the tools for (the tests needing the others skip, saying why)."""
    if missing(HOST):
        return []
    if not missing(SIMAVR):
        return ["host", "atmega32", "imaxb6", "simavr", "simavr-imaxb6"]
    return ["host"] if missing(AVR) else ["host", "atmega32", "imaxb6"]


def prepare() -> None:
    # A failed make is left to the tests: their own `make` then fails with the compiler's output.
    targets = firmware_targets()
    if targets:
        subprocess.run(["make", "-s", "-C", str(FIRMWARE), *targets], capture_output=True)
    compileall.compile_dir(PACKAGE, quiet=2)
