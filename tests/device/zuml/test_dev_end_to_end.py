"""End to end over a real pty (and one socket://): an in-process virtual charger, the client."""
import os
import threading
import time

import pytest
import serial

from zuml_studio.protocol import messages as m
from zuml_studio.device.zuml.client import ChargerClient
from zuml_studio.device.errors import (DeviceError, Disconnected, ImageTooLarge, InvalidImage, NotACharger,
                                       PermissionDenied, PortBusy, PortNotFound)
from zuml_studio.protocol.passport import Passport, PassportError
from zuml_studio.virtual.transport import serve_pty
from zuml_studio.virtual.virtual_charger import VirtualCharger
from zuml_studio.lang.eeprom import pack
from zuml_studio.sim.interpreter import StartParams
from zuml_studio.sim.simulate import BatterySetup, simulate

from helpers import compiled, needs_pty, until

pytestmark = needs_pty


def thread_names():
    return sorted(t.name for t in threading.enumerate())


def test_flash_verify_slots_backup_restore(any_client):
    charger, client = any_client
    size = client.info.eeprom_size
    assert size == (1024 if charger.virtual else 431) and client.info.max_charge_a == 5.0
    seen = []
    image = pack([compiled("NiMh-dV"), compiled("NiMh"), compiled("LiPo")], size)
    result = client.write_image(image, progress=lambda stage, done, total: seen.append(stage))
    assert result.changed == sum(b != 0xFF for b in image)
    assert {"read", "write", "verify"} <= set(seen)
    assert [(s.index, s.name, s.ok) for s in client.slots()] == [(0, "NiMh-dV", True), (1, "NiMh", True),
                                                                  (2, "LiPo", True)]
    backup = client.read_image()
    assert backup == image
    # rewrite only what changes: replacing slot 1 by a same-size record touches a few bytes
    other = pack([compiled("NiMh-dV"), compiled("NiCd"), compiled("LiPo")], size)
    assert client.write_image(other).changed < 40
    assert client.write_image(backup).changed > 0 and client.read_image() == backup
    assert client.write_image(backup).changed == 0
    # a stale idea of the present image: the COMMIT's CRC refuses it, the client reads and retries
    client.write_image(other)
    assert client.write_image(pack([compiled("Pb")], size), current=backup).changed > 0
    assert client.read_image() == pack([compiled("Pb")], size)
    client.write_image(backup)
    with pytest.raises(ImageTooLarge):
        client.write_image(b"\xff" * (size + 1))
    with pytest.raises(InvalidImage):
        client.write_image(b"\x05\x01\x02")
    assert client.read_image() == backup
    if charger.virtual:
        assert charger.device.eeprom_image == backup


def test_charge_run_matches_the_simulator(charger):
    device, port, client = charger
    rec = compiled("NiMh-dV")
    client.write_image(pack([rec]))
    events, telemetry = [], []
    client.on_event(events.append)
    client.on_telemetry(telemetry.append)
    client.set_telemetry_rate(50)
    assert client.start(0, "charge", 1, 2000, 2.0, None, 4, sensor=False) == "NiMh-dV"
    assert until(lambda: any(e.kind == "finish" for e in events))
    sim = simulate(rec, StartParams("charge", 1, 2000, 2.0, None, 4, False), BatterySetup("NiMh", 0.0))
    expected = [(e.kind, e.section, e.index, e.repetition, e.offset, e.detail) for e in sim.interpreter.events]
    got = [(e.kind, e.section, e.index, e.repetition, e.offset, e.detail) for e in events]
    assert got == expected
    assert [e.time_s for e in events] == [round(e.time_s, 3) for e in sim.interpreter.events]
    ends = [e.detail for e in events if e.kind == "phase_end"]
    assert ends == [p.reason for p in sim.phases] == ["IF(DELTA_PEAK>0.01S) STOP_FAZE"]
    running = [t for t in telemetry if t.running]
    assert running and all(t.section == "charge" and t.phase == 1 and t.run == 1 for t in running)
    assert all(t.current_a > 0 for t in running if t.time_s > 0)
    st = client.status()
    assert (st.state, st.slot, st.name, st.end_reason) == ("finished", 0, "NiMh-dV", "end of macro")
    assert st.events == len(events) and client.missed_events == []
    assert abs(st.run_s - sim.interpreter.time_s) < 1e-6


def test_stop_takes_effect_at_once_and_discharge_current_is_negative(make_charger, make_client):
    device, port = make_charger(battery="NiMh:2000:4", speed=50, soc=1.0)
    client = make_client(port)
    client.write_image(pack([compiled("NiMh")]))
    telemetry = []
    client.on_telemetry(telemetry.append)
    client.set_telemetry_rate(50)
    client.start(0, "discharge", capacity_mah=2000, series=4, sensor=False)
    assert until(lambda: any(t.running and t.time_s > 2 for t in telemetry))
    assert client.status().state == "running"
    assert client.stop() == "finished"
    st = client.status()
    assert st.state == "finished" and st.end_reason == "stopped"
    discharging = [t for t in telemetry if t.running and t.time_s > 0]
    assert discharging and all(t.current_a < 0 and t.section == "discharge" for t in discharging)
    phase_end = client.get_event(st.events - 2)
    assert phase_end.kind == "phase_end" and phase_end.detail == "stopped"
    assert client.stop() == "finished"               # idempotent


def test_passport_read_write_and_lockout(make_charger, make_client):
    device, port = make_charger(battery="NiMh:2000:4", speed=20000, passport="LiPo", passport_factory=True)
    client = make_client(port)
    p = client.passport_read()
    assert p.type_name == "LiPo" and p.serial == "ZUML-VIRT-0001" and p.temp == 25
    client.write_image(pack([compiled("NiMh-dV")]))
    with pytest.raises(DeviceError) as exc:
        client.start(0, "charge", 1, 2000, 2.0, None, 4, False)
    assert exc.value.code == m.ErrorCode.PASSPORT_CONFLICT
    assert exc.value.lines == ["the macro is for NiMh; the battery is LiPo"]
    assert device.state == "idle"
    after = client.passport_write("type", "NiMh")                                  # a factory battery
    assert after.type == 3 and Passport.from_bytes(device.chip.image) == after      # check maintained
    # TEMP is live. The idle pack keeps stepping (x20000): it must not cool to 25 °C meanwhile.
    device.pack.ambient_c = device.pack.temp_c = 37.4
    assert client.passport_read().temp == 37
    with pytest.raises(PassportError, match="A_LIMIT lies on page 7"):
        client.passport_write("a_limit", 1)
    assert client.start(0, "charge", 1, 2000, 2.0, None, 4, False) == "NiMh-dV"


def test_a_production_battery_keeps_its_type_and_limits_and_the_lockout_holds(make_charger, make_client):
    """Issue 11.4: the PC cannot rewrite TYPE or V_LIMIT to get a LiPo macro started on a NiMH pack."""
    device, port = make_charger(battery="NiMh:2000:4", speed=20000)
    client = make_client(port)
    client.write_image(pack([compiled("LiPo")]))
    before = device.chip.image
    for field, value in (("type", "LiPo"), ("v_limit", 20), ("serial", "FAKE"), ("vendor", "X")):
        with pytest.raises(DeviceError, match="read-only fields"):
            client.passport_write(field, value)
    assert device.chip.image == before
    with pytest.raises(DeviceError, match="the macro is for LiPo; the battery is NiMh"):
        client.start(0, "charge", 1, 2000, 2.0, None, 3, False)
    assert client.passport_write("err", 2).err == 2                 # the error section stays writable


def test_a_battery_with_critical_errors_does_not_start_and_the_message_names_them(make_charger, make_client):
    device, port = make_charger(battery="NiMh:2000:4", speed=20000,
                                passport=Passport("PACK-7", "ROGA", 3, 1, 2, 8, 4, 25))
    client = make_client(port)
    client.write_image(pack([compiled("NiMh-dV")]))
    with pytest.raises(DeviceError) as exc:
        client.start(0, "charge", 1, 2000, 2.0, None, 4, False)
    assert exc.value.lines == ["the battery reports 2 critical error(s) (CRIT=2): it is not fit for use"]
    assert device.state == "idle"
    client.passport_write("crit", 0)
    assert client.start(0, "charge", 1, 2000, 2.0, None, 4, False) == "NiMh-dV"


def test_garbage_between_frames_is_skipped_both_ways(any_client):
    charger, client = any_client
    image = pack([compiled("NiMh-dV")], client.info.eeprom_size)
    client.write_image(image)
    for junk in (b"\xa5\xf0\x00", os.urandom(300), b"\xa5" * 10, b"\x00\xa5\x03\x01\x02"):
        client._serial.write(junk)                  # host -> device noise
        if charger.virtual:
            charger.device._queue_reply(junk)       # device -> host noise
        assert client.read_image() == image
        assert client.status().state == "idle"
    if charger.virtual:
        assert client._parser.skipped > 0 and charger.device._parser.skipped > 0


def test_socket_url_works_too(make_charger, make_client):
    device, url = make_charger(tcp=True, battery="NiMh:2000:4", speed=20000)
    assert url.startswith("socket://127.0.0.1:")
    client = make_client(url)
    client.write_image(pack([compiled("NiMh-dV")]))
    assert [s.name for s in client.slots()] == ["NiMh-dV"]
    client.close()
    again = make_client(url)                          # the next host after the first left
    assert again.identify().eeprom_size == 1024


def test_open_errors(make_charger, make_client, tmp_path, monkeypatch):
    device, port = make_charger()
    make_client(port)
    with pytest.raises(PortBusy, match="busy"):
        ChargerClient(port)
    with pytest.raises(PortNotFound):
        ChargerClient(str(tmp_path / "ttyUSB9"))
    master, slave = os.openpty()                      # a port where nothing answers
    try:
        with pytest.raises(NotACharger, match="no ZUML charger answered"):
            ChargerClient(os.ttyname(slave), timeout=0.05)
    finally:
        os.close(master)
        os.close(slave)

    def denied(*a, **kw):
        raise serial.SerialException(13, "could not open port /dev/ttyUSB0: [Errno 13] Permission denied")
    monkeypatch.setattr(serial, "serial_for_url", denied)
    with pytest.raises(PermissionDenied, match="/dev/ttyUSB0: permission denied; "):
        ChargerClient("/dev/ttyUSB0")


def test_link_loss_is_reported(make_client):
    device = VirtualCharger(speed=1000)
    port, stop = serve_pty(device, baud=None)
    client = make_client(port)
    lost = []
    client.on_disconnect(lost.append)
    stop()
    assert until(lambda: lost, 5)
    with pytest.raises(Disconnected):
        client.status()
    assert not client.connected
    device.close()


def test_many_chargers_leak_no_threads_or_fds(make_client):
    before_threads = thread_names()
    fd_dir = "/proc/self/fd"
    before_fds = len(os.listdir(fd_dir)) if os.path.isdir(fd_dir) else None
    for _ in range(15):
        device = VirtualCharger(speed=100)
        port, stop = serve_pty(device, baud=None)
        client = ChargerClient(port)
        client.status()
        client.close()
        stop()
    assert until(lambda: thread_names() == before_threads, 5), thread_names()
    if before_fds is not None:
        assert len(os.listdir(fd_dir)) == before_fds


def test_a_host_that_does_not_read_never_blocks_the_device():
    """The host stops reading: the pty fills, the device keeps running, queues every event,
    coalesces telemetry, and the host gets all events in order once it reads again."""
    from zuml_studio.protocol.frames import FrameParser, encode_frame
    from zuml_studio.lang.compiler import compile_source
    text = ("MACRO Many\nAKK_TYPE=NiMh\nCHARGE_SECTION\nCYCLE(200)\nFAZE\nCONSTANT_I=1A\nIF(tf>20s) STOP_FAZE\n"
            "END_FAZE\nLIGHT(FAST)\nEND_CYCLE\nEND_SECTION\nEND_MACRO\n")
    device = VirtualCharger("NiMh:2000:4", speed=100000)
    device.eeprom[:] = pack([compile_source(text).record])
    port, stop = serve_pty(device, baud=None)
    fd = os.open(port, os.O_RDWR | os.O_NOCTTY)
    try:
        os.write(fd, encode_frame(m.SET_TELEMETRY_RATE, 1, m.encode_request("SET_TELEMETRY_RATE", hz=50)))
        os.write(fd, encode_frame(m.START, 2, m.encode_request(
            "START", slot=0, task=0, repetitions=1, capacity_mah=2000, current_ma=0, voltage_mv=0, series=4,
            sensor=0)))
        assert until(lambda: device.state == "finished", 20)      # nobody reads meanwhile
        time.sleep(0.3)
        parser, frames = FrameParser(), []
        os.set_blocking(fd, False)
        deadline = time.monotonic() + 10
        while time.monotonic() < deadline:
            try:
                chunk = os.read(fd, 65536)
            except BlockingIOError:
                chunk = b""
            new = parser.feed(chunk)
            frames += new
            if any(f.type == m.EVENT and m.DeviceEvent.decode(f.payload).kind == "finish" for f in new):
                break
            if not chunk:
                time.sleep(0.02)
        events = [m.DeviceEvent.decode(f.payload) for f in frames if f.type == m.EVENT]
        assert [e.number for e in events] == list(range(len(device.run_events)))
        assert sum(e.kind == "phase_end" for e in events) == 200
    finally:
        os.close(fd)
        stop()
        device.close()


def test_builtin_serve_and_speed_change(make_client):
    from zuml_studio.virtual.transport import serve
    device = VirtualCharger(speed=10)
    url, stop = serve(device)
    try:
        client = make_client(url)
        client.write_image(pack([compiled("NiMh-dV")]))
        client.start(0, "charge", 1, 2000, 2.0, None, 4, False)
        device.set_speed(100000)
        assert until(lambda: client.status().state == "finished", 10)
        assert client.status().end_reason == "end of macro"
    finally:
        stop()
        device.close()


def test_one_port_per_charger_and_a_taken_tcp_port(make_charger):
    from zuml_studio.virtual.transport import serve_tcp
    from zuml_studio.virtual.virtual_charger import DeviceSetupError
    device, url = make_charger(tcp=True)
    with pytest.raises(DeviceSetupError):
        serve_pty(device)
    other = VirtualCharger()
    with pytest.raises(OSError):
        serve_tcp(other, "127.0.0.1", int(url.rsplit(":", 1)[1]))
    assert other._links == 0


def test_a_run_reports_telemetry_and_events_and_stops(any_charger, make_client):
    # the wall's time, as the firmware's; its battery is a 3-cell lithium one
    charger = any_charger(battery="LiPo:2000:3", passport=None, speed=1)
    client = make_client(charger.port, timeout=2)
    client.write_image(pack([compiled("LiPo")], client.info.eeprom_size))
    events = []
    client.on_event(events.append)
    assert client.start(0, "charge", capacity_mah=2000, current_a=1.0, series=3, sensor=False) == "LiPo"
    # The first frames of the phase may come before the stage has reached its current: wait for it.
    assert until(lambda: client.last_telemetry is not None and client.last_telemetry.phase == 1
                    and abs(client.last_telemetry.current_a - 1.0) <= 0.05)
    status = client.status()
    assert status.state == "running" and status.name == "LiPo" and status.slot == 0
    assert client.last_telemetry.section == "charge"
    assert client.stop() == "finished"
    assert until(lambda: [e.kind for e in events][-1:] == ["finish"])
    assert [e.kind for e in events] == ["section", "phase_start", "phase_end", "finish"]
    assert events[2].detail == "stopped" and events[1].offset == events[2].offset > 0
    assert client.status().end_reason == "stopped" and client.get_event(1).kind == "phase_start"
