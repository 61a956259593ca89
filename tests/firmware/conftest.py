"""The firmware's host build, made once per session; firmware tests skip (saying why) without a C compiler."""
import subprocess

import pytest

from b6_harness import B6, build
from host_core import FIRMWARE, LIBRARY, load
from tools import HOST, skip_unless
from helpers import compiled
from zuml_studio.lang import eeprom

HOST_DEVICE = FIRMWARE / "build" / "host" / "zuml_host"


@pytest.fixture(scope="session")
def host_build():
    """`make host` once: the core as a shared library and the device on a pty."""
    skip_unless(HOST)
    done = subprocess.run(["make", "-s", "-C", str(FIRMWARE), "host"], capture_output=True, text=True)
    assert done.returncode == 0, done.stdout + done.stderr


@pytest.fixture(scope="session")
def core_lib(host_build):
    return load(LIBRARY)


@pytest.fixture
def host_device(host_build):
    """start(*args) -> the pty of a fresh host firmware device (stopped after the test)."""
    started = []

    def start(*args):
        proc = subprocess.Popen([str(HOST_DEVICE), *map(str, args)], stdout=subprocess.PIPE,
                                stderr=subprocess.DEVNULL, text=True)
        started.append(proc)
        return proc.stdout.readline().strip()

    yield start
    for proc in started:
        proc.terminate()
        proc.wait(timeout=10)


@pytest.fixture(scope="session")
def image():
    """The iMAX B6 image and its simulator, built once (skipped, naming the tools, where they are missing)."""
    build("imaxb6", "simavr-imaxb6")
    return FIRMWARE / "build" / "imaxb6" / "zuml.elf"


@pytest.fixture
def b6_on(image, tmp_path):
    """run(eeprom, *args): the module's image on the simulated B6 at full speed, with its LCD and a trace of the
    model's true values (`sim.trace`), `eeprom` (padded with 0xFF) in a file of its own; all stopped after."""
    started = []

    def run(eeprom: bytes, *args):
        n = len(started)
        path = tmp_path / f"ee{n}.bin"
        path.write_bytes(eeprom.ljust(1024, b"\xff"))
        sim = B6(image, "--speed", "0", "--lcd", "--eeprom", path, "--trace", tmp_path / f"t{n}.csv", *args)
        sim.trace = tmp_path / f"t{n}.csv"
        started.append(sim)
        return sim

    yield run
    for sim in started:
        sim.stop()


STORE_SIZE = 404                    # IDENTIFY's eeprom_size on the B6 (docs/firmware.md, Calibration)


@pytest.fixture
def b6(b6_on):
    """start(macro, *args): the image on the simulated B6 with `macro` in slot 1 (an EEPROM file per start)."""
    return lambda macro, *args: b6_on(eeprom.pack([compiled(macro)], STORE_SIZE), *args)
