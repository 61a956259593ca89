"""Fixtures for the device-link tests: clients of virtual chargers (``make_charger`` is the
suite's, in ``tests/conftest.py``)."""
import pytest

from zuml_studio.device.zuml.client import ChargerClient


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


@pytest.fixture
def any_client(any_charger, make_client):
    """(charger, client) on each charger of ``any_charger`` (the virtual one: NiMh 2000 mAh x4 at
    speed 20000, as ``charger``; then the firmware on simavr)."""
    charger = any_charger(battery="NiMh:2000:4", speed=20000)
    return charger, make_client(charger.port, timeout=2)
