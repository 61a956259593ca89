"""Fixtures for the device-link tests: virtual chargers on ptys (or TCP), clients, records."""
import os
import threading

import pytest

from zuml_studio.device.client import ChargerClient
from zuml_studio.device.transport import serve_pty, serve_tcp
from zuml_studio.device.virtual_charger import VirtualCharger
from zuml_studio.lang.compiler import compile_source

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
MACROS = os.path.join(ROOT, "macros")

needs_pty = pytest.mark.skipif(os.name != "posix", reason="ptys need POSIX")


def record(name: str) -> bytes:
    with open(os.path.join(MACROS, f"{name}.zuml"), encoding="utf-8") as fh:
        result = compile_source(fh.read())
    assert result.ok, result.diagnostics
    return result.record


@pytest.fixture
def make_charger():
    """make_charger(baud=None, tcp=False, **VirtualCharger kwargs) -> (device, port_or_url)."""
    made = []

    def make(baud=None, tcp=False, **kw):
        device = VirtualCharger(**kw)
        where, stop = serve_tcp(device, "127.0.0.1", 0, baud) if tcp else serve_pty(device, baud)
        made.append((device, stop))
        return device, where

    yield make
    for device, stop in made:
        stop()
        device.close()


@pytest.fixture
def make_client():
    made = []

    def make(port, **kw):
        client = ChargerClient(port, **kw)
        made.append(client)
        return client

    yield make
    for client in made:
        client.close()


@pytest.fixture
def charger(make_charger, make_client):
    """A NiMh 2000 mAh x4 virtual charger at speed 20000 on a pty, unpaced, and a client."""
    device, port = make_charger(battery="NiMh:2000:4", speed=20000)
    return device, port, make_client(port)


def thread_names():
    return sorted(t.name for t in threading.enumerate())
