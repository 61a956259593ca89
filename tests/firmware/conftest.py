"""The firmware's host build, made once per session; firmware tests skip (saying why) without a C compiler."""
import shutil
import subprocess

import pytest

from host_core import FIRMWARE, LIBRARY, load

INSTALL_HINT = "install the tools with: apt-get install -y gcc make gcc-avr avr-libc binutils-avr simavr libsimavr-dev"


@pytest.fixture(scope="session")
def core_lib():
    missing = [tool for tool in ("gcc", "make") if shutil.which(tool) is None]
    if missing:
        pytest.skip(f"{' and '.join(missing)} not found: the firmware's host build cannot be made ({INSTALL_HINT})")
    done = subprocess.run(["make", "-s", "-C", str(FIRMWARE), "host"], capture_output=True, text=True)
    assert done.returncode == 0, done.stdout + done.stderr
    return load(LIBRARY)
