"""Line faults: bit errors both ways, a disconnect in the middle of a flash.

Whatever happens on the line, the device's EEPROM only ever holds a whole image that a host
committed with the right CRC: every record in it has a good check byte."""
import time

import pytest

from zuml_studio.device.zuml.client import ChargerClient
from zuml_studio.device.errors import (CommitUncertain, DeviceLinkError, DeviceTimeout, Disconnected, NoisyLine,
                                      NotACharger)
from zuml_studio.virtual.transport import serve_pty
from zuml_studio.virtual.virtual_charger import Faults, VirtualCharger
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
    client = connect(port)                 # the link's own timeouts: a fixed 0.05 s fails on a loaded machine
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
    assert slowest < 60                    # a bound on a hang, not a speed (benchmarks/ measure speed)
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


def lose_commit_answer(client, monkeypatch, failure, commit_arrives=True):
    """Every answer to COMMIT is lost (``failure`` raised in its place), and the COMMIT itself
    reaches the charger or not."""
    real = client.request

    def request(name, payload, **kw):
        if name != "COMMIT":
            return real(name, payload, **kw)
        if commit_arrives:
            real(name, payload, **kw)
        raise failure
    monkeypatch.setattr(client, "request", request)


def test_commit_taken_but_its_answers_lost_is_found_by_the_read_back(charger, monkeypatch):
    device, _, client = charger
    new = pack([compiled("LiPo")])
    lose_commit_answer(client, monkeypatch, DeviceTimeout("no answer to COMMIT"))
    result = client.write_image(new)
    assert result.changed > 0 and device.eeprom_image == new + b"\xff" * (1024 - len(new))


def test_commit_lost_with_its_answers_keeps_the_old_image_and_says_so(charger, monkeypatch):
    device, _, client = charger
    old = device.eeprom_image
    lose_commit_answer(client, monkeypatch, DeviceTimeout("no answer to COMMIT"), commit_arrives=False)
    with pytest.raises(DeviceTimeout, match="did not take COMMIT; it keeps its previous image"):
        client.write_image(pack([compiled("LiPo")]))
    assert device.eeprom_image == old and device.commits == 0


def test_link_lost_right_after_commit_says_the_image_is_old_or_new(charger, monkeypatch):
    device, _, client = charger
    lose_commit_answer(client, monkeypatch, Disconnected("the connection was lost"))
    with pytest.raises(CommitUncertain, match="either the new image or its previous one"):
        client.write_image(pack([compiled("LiPo")]))
    assert device.eeprom_image[:len(compiled("LiPo"))] == compiled("LiPo")


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


def test_a_flash_at_a_bit_error_rate_of_1e_2_says_the_line_is_noisy(make_charger):
    # issue 27: it said "no ZUML charger answered (wrong port or baud rate?)" although the charger answered
    _device, port = make_charger(faults=Faults(ber=1e-2), seed=1)
    with pytest.raises(NoisyLine, match=r"^\S+: the charger answers, but \d+ answers arrived damaged .* the line is "
                                        r"noisy"):
        ChargerClient(port).close()


def test_silence_is_still_no_charger_not_a_noisy_line():
    import os
    master, slave = os.openpty()
    try:
        with pytest.raises(NotACharger, match="no ZUML charger answered"):
            ChargerClient(os.ttyname(slave), timeout=0.05, retries=1)
    finally:
        os.close(master)
        os.close(slave)


def test_a_monitor_only_charger_whose_cable_is_pulled_says_the_zuml_links_sentence():
    # issue 27: pyserial's "device reports readiness to read but returned no data ..." was shown
    import os
    import threading
    from realdata_samples import dollar_lines
    from zuml_studio.device.links.monitor_link import MonitorLink
    master, slave = os.openpty()
    sampled, closed, why = threading.Event(), threading.Event(), []
    link = MonitorLink(os.ttyname(slave), "cheali", on_sample=lambda s: sampled.set(),
                       on_closed=lambda e: (why.append(e), closed.set()))
    link.start()
    try:
        os.write(master, dollar_lines("cheali_captured_lines_from_issues.txt")[0] + b"\r\n")
        assert sampled.wait(10)
    finally:
        os.close(master)                 # the cable pulled
    assert closed.wait(10)
    os.close(slave)
    assert why == [f"{link.port}: the connection was lost (the charger closed the "
                   "line: it stopped, or its cable was pulled)"]


def test_a_try_waits_for_the_links_measured_delay_and_an_explicit_timeout_is_kept(charger, make_client):
    """A link whose answers come late (a simulated charger on a loaded machine: PASSPORT timed out at a quiet
    machine's 0.11 s a try) gets tries as long as its measured delay, up to TIMEOUT_MAX_S."""
    from zuml_studio.device.zuml.client import TIMEOUT_MAX_S
    _device, port, client = charger
    quiet = client._attempt_timeout(8, 32)
    for _ in range(30):
        client._measured(0.8)
    slow = client._attempt_timeout(8, 32)
    assert quiet < 0.8 <= slow <= TIMEOUT_MAX_S
    for _ in range(30):
        client._measured(60.0)
    assert client._attempt_timeout(8, 32) == TIMEOUT_MAX_S
    client.close()
    fixed = make_client(port, timeout=0.3)
    fixed._measured(2.0)
    assert fixed._attempt_timeout(8, 32) == 0.3
