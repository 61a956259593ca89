"""The firmware's host build, made once per session; firmware tests skip (saying why) without a C compiler."""
import subprocess

import pytest

from host_core import FIRMWARE, LIBRARY, load
from tools import HOST, skip_unless

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
