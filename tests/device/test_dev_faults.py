"""Line faults: bit errors both ways, a disconnect in the middle of a flash.

Whatever happens on the line, the device's EEPROM only ever holds a whole image that a host
committed with the right CRC: every record in it has a good check byte."""
import time

import pytest

from zuml_studio.device.client import ChargerClient
from zuml_studio.device.errors import DeviceLinkError, Disconnected, NotACharger
from zuml_studio.device.transport import serve_pty
from zuml_studio.device.virtual_charger import Faults, VirtualCharger
from zuml_studio.lang.eeprom import pack, slots

from helpers import compiled, needs_pty

pytestmark = needs_pty


def connect(port, tries=10, **kw):
    for _ in range(tries - 1):
        try:
            return ChargerClient(port, **kw)
        except NotACharger:
            continue
    return ChargerClient(port, **kw)


def all_records_valid(image: bytes) -> bool:
    return all(s.ok for s in slots(image))


def test_100_flashes_through_bit_errors_end_verified_or_with_an_error(make_charger):
    images = [pack([compiled("NiMh-dV"), compiled("LiPo")], 256), pack([compiled("NiCd"), compiled("LiFe")], 256),
              pack([compiled("Pb")], 256)]
    device, port = make_charger(eeprom_size=256, faults=Faults(ber=1e-3), seed=7, speed=100)
    client = connect(port, timeout=0.05)
    client.set_telemetry_rate(1) if client.connected else None
    verified = failed = 0
    slowest = 0.0
    for n in range(100):
        wanted = images[n % len(images)]
        started = time.monotonic()
        try:
            client.write_image(wanted)
            verified += 1
            assert device.eeprom_image == wanted
        except DeviceLinkError:
            failed += 1
        slowest = max(slowest, time.monotonic() - started)
        image = device.eeprom_image
        assert all_records_valid(image) and image in images + [b"\xff" * 256]
    assert verified + failed == 100
    assert verified >= 50, (verified, failed, client.stats)
    assert slowest < 10
    assert client.stats["retries"] + client.stats["early_resends"] > 0       # the noise was real


def test_disconnect_mid_flash_leaves_the_previous_image(make_client):
    old = pack([compiled("NiMh-dV")])
    device = VirtualCharger(speed=100, faults=Faults(disconnect_after=150))
    device.eeprom[:] = old
    port, stop = serve_pty(device, baud=None)
    try:
        client = make_client(port)
        new = pack([compiled("LiPo"), compiled("LiIon"), compiled("LiFe"), compiled("NiCd"), compiled("Pb")])
        with pytest.raises(Disconnected):
            client.write_image(new, current=old)         # BEGIN + staging cross the 150 bytes
        assert device.eeprom_image == old
        assert device.commits == 0
    finally:
        stop()
        device.close()


def test_lost_bytes_never_corrupt_the_eeprom(make_charger):
    device, port = make_charger(eeprom_size=256, faults=Faults(drop=2e-3), seed=3, speed=100)
    client = connect(port, timeout=0.05)
    wanted = pack([compiled("NiMh-dV"), compiled("LiPo")], 256)
    for _ in range(10):
        try:
            client.write_image(wanted)
        except DeviceLinkError:
            pass
        assert all_records_valid(device.eeprom_image)
    assert device.eeprom_image in (wanted, b"\xff" * 256)
