"""The tools some tests need beyond what the README asks for (C compilers, the AVR toolchain, simavr,
avrdude): what this machine lacks of each set, and a skip that names it with the line installing it.
One table, so every test that needs a tool skips alike instead of erroring in its build."""
from __future__ import annotations

import functools
import os
import shutil
import subprocess

import pytest

INSTALL = "apt-get install -y make gcc gcc-avr avr-libc binutils-avr simavr libsimavr-dev libelf-dev"
INSTALL_AVRDUDE = "apt-get install -y avrdude"

HOST = ("make", "gcc")                                              # the firmware's host build
AVR = HOST + ("avr-gcc", "avr-size", "avr-objcopy", "<avr/io.h>")   # the ATmega32 images
SIMAVR = AVR + ("<simavr/sim_avr.h>", "<libelf.h>", "-lsimavr", "-lsimavrparts", "-lelf")   # the simulated boards
AVRDUDE = ("avrdude",)


@functools.cache
def _present(need: str) -> bool:
    if need.startswith("-l"):               # a library the linker must find (a -dev package's .so)
        name = f"lib{need[2:]}.so"
        if not shutil.which("gcc"):
            return False
        found = subprocess.run(["gcc", f"-print-file-name={name}"], capture_output=True, text=True).stdout.strip()
        return os.path.isabs(found)
    if need.startswith("<"):                # a header: avr-libc's through avr-gcc, the others through gcc
        compiler = ["avr-gcc", "-mmcu=atmega32"] if need.startswith("<avr/") else ["gcc", "-I/usr/include/simavr"]
        if not shutil.which(compiler[0]):
            return False
        return subprocess.run([*compiler, "-E", "-x", "c", "-o", os.devnull, "-"], input=f"#include {need}\n",
                              capture_output=True, text=True).returncode == 0
    return shutil.which(need) is not None


def missing(needs: tuple[str, ...]) -> str:
    """What of ``needs`` this machine lacks, comma-separated ('' when nothing); POSIX ptys count too."""
    lacking = [need for need in needs if not _present(need)]
    if needs is not HOST and needs is not AVR and os.name != "posix":
        lacking.append("a POSIX pty")
    return ", ".join(lacking)


def reason(needs: tuple[str, ...]) -> str:
    return f"{missing(needs)} missing here: install with `{INSTALL_AVRDUDE if needs is AVRDUDE else INSTALL}`"


def needs(tools: tuple[str, ...]) -> pytest.MarkDecorator:
    """A skipif mark for tests that need ``tools`` (HOST, AVR, SIMAVR, AVRDUDE)."""
    return pytest.mark.skipif(bool(missing(tools)), reason=reason(tools) if missing(tools) else "")


def skip_unless(tools: tuple[str, ...]) -> None:
    """Skip the calling test or fixture, naming what to install, when ``tools`` are not all here."""
    if missing(tools):
        pytest.skip(reason(tools))
