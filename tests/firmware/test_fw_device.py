"""The firmware's device side (protocol, store, runs) on the host build behind a pty, through the
project's own client: the same requests ZUML Studio sends a charger."""
import os
import time
import tty

import pytest

from helpers import compiled, needs_pty, unsafe_record, until
from zuml_studio.protocol import messages as m
from zuml_studio.protocol import passport as pp
from zuml_studio.device.zuml.client import ChargerClient
from zuml_studio.device.errors import DeviceError
from zuml_studio.protocol.frames import FrameParser, encode_frame
from zuml_studio.lang import eeprom
from zuml_studio.domain.start_templates import StartTemplate, factory_templates

pytestmark = needs_pty


@pytest.fixture
def client(host_device):
    clients = []

    def connect(*args):
        c = ChargerClient(host_device(*args), timeout=2)
        clients.append(c)
        return c

    yield connect
    for c in clients:
        c.close()


def test_identify_reports_the_store_and_the_limits(client):
    info = client().info
    assert info.protocol == 1 and info.max_data == 240
    # (1 KB - 16 start templates of 9 B + a check byte - 2 flag bytes) / 2: the other half stages writes
    assert info.eeprom_size == 431
    assert info.max_charge_a == 5.0 and info.firmware.startswith("zuml-fw")


def test_flash_slots_and_read_back(client, tmp_path):
    path = tmp_path / "ee.bin"
    c = client("--eeprom", path)
    image = eeprom.pack([compiled("LiPo"), compiled("NiMh-dV")], c.info.eeprom_size)
    result = c.write_image(image)
    assert result.changed > 0
    assert [(s.name, s.ok) for s in c.slots()] == [("LiPo", True), ("NiMh-dV", True)]
    assert c.read_image() == image
    c.close()
    # the device writes its EEPROM file beside, then renames
    assert until(lambda: path.exists() and path.read_bytes()[:len(image)] == image)


def test_a_run_reports_events_with_the_interpreters_texts_and_stops(client):
    c = client()
    c.write_image(eeprom.pack([compiled("LiPo")], c.info.eeprom_size))
    events = []
    c.on_event(events.append)
    assert c.start(0, "charge", capacity_mah=2000, current_a=2.0, series=3) == "LiPo"
    # the device runs in real time: wait until it has run a second and sent telemetry of it, however late
    # a loaded machine schedules it
    assert until(lambda: c.status().run_s >= 1.0 and c.last_telemetry is not None and c.last_telemetry.running,
                 60.0)
    status = c.status()
    assert status.state == "running" and status.name == "LiPo" and status.run_s >= 1.0
    telemetry = c.last_telemetry
    assert telemetry.section == "charge" and telemetry.phase == 1 and telemetry.current_a == pytest.approx(2.0)
    assert c.stop() == "finished"
    assert until(lambda: any(e.kind == "finish" for e in events))      # the events come on the reader thread
    kinds = [e.kind for e in events]
    assert kinds == ["section", "phase_start", "phase_end", "finish"]
    assert events[2].detail == "stopped" and events[1].offset == events[2].offset > 0
    assert c.status().end_reason == "stopped"
    assert c.get_event(1).kind == "phase_start"


def test_start_refusals(client):
    c = client()
    c.write_image(eeprom.pack([compiled("LiPo")], c.info.eeprom_size))
    with pytest.raises(DeviceError) as slot:
        c.start(3)
    assert slot.value.code == m.ErrorCode.BAD_SLOT
    with pytest.raises(DeviceError) as start:
        c.start(0, "charge", capacity_mah=2000, series=3)      # CONSTANT_I=INPUT with no current
    assert start.value.code == m.ErrorCode.START_ERROR and "give the current" in str(start.value)


ANSWER_BOUND_S = 30.0     # a bound on an answer's wait, far above a loaded machine's: a hang fails, it does not wait


class RawLink:
    """Frames by hand, for what the client never sends twice on purpose."""

    def __init__(self, port):
        self.fd = os.open(port, os.O_RDWR | os.O_NOCTTY)
        tty.setraw(self.fd)
        os.set_blocking(self.fd, False)
        self.parser = FrameParser(m.DEVICE_TYPES)

    def ask(self, type_, seq, payload=b"", raw=None):
        os.write(self.fd, raw if raw is not None else encode_frame(type_, seq, payload))
        deadline = time.monotonic() + ANSWER_BOUND_S
        while time.monotonic() < deadline:
            try:
                chunk = os.read(self.fd, 4096)
            except BlockingIOError:
                time.sleep(0.01)
                continue
            for frame in self.parser.feed(chunk):
                if frame.type != m.TELEMETRY:
                    return frame
        raise AssertionError("no answer")

    def close(self):
        os.close(self.fd)


def test_retried_requests_are_answered_the_same_and_not_done_twice(host_device):
    link = RawLink(host_device())
    try:
        first = link.ask(m.BEGIN_WRITE, 9)
        again = link.ask(m.BEGIN_WRITE, 9)
        assert first.payload == again.payload                  # the same token: not a new transaction
        other = link.ask(m.BEGIN_WRITE, 10)
        assert other.payload != first.payload
        bad = link.ask(m.COMMIT, 11, m.encode_request("COMMIT", token=int.from_bytes(other.payload[:4], "little"),
                                                      crc=0x1234))
        assert bad.type == m.ERROR and bad.payload[1] == m.ErrorCode.CRC_MISMATCH
        broken = bytearray(encode_frame(m.IDENTIFY, 12))
        broken[-1] ^= 0xFF
        nak = link.ask(0, 0, raw=bytes(broken) + encode_frame(m.IDENTIFY, 13))
        assert nak.type == m.ERROR and nak.payload[1] == m.ErrorCode.BAD_FRAME
    finally:
        link.close()


def test_a_commit_cut_off_by_a_power_loss_is_finished_at_the_next_start(client, tmp_path):
    image = eeprom.pack([compiled("LiPo")], 431)
    old = eeprom.pack([], 431)
    # image, staging copy, 16 blank start templates, their flag, the journal at 1023: committing
    ee = old + image + b"\xff" * 160 + b"\xff\xa5"
    path = tmp_path / "ee.bin"
    path.write_bytes(ee)
    c = client("--eeprom", path)
    assert c.read_image() == image


def test_the_passport_locks_out_a_macro_for_another_battery(client):
    c = client("--passport", "3:8:2")                 # NiMh, 8 V, 2 A
    c.write_image(eeprom.pack([compiled("LiPo"), compiled("NiMh-dV")], c.info.eeprom_size))
    assert c.passport_read().type == 3
    with pytest.raises(DeviceError) as refused:
        c.start(0, "charge", capacity_mah=2000, current_a=3.0, series=3)
    assert refused.value.code == m.ErrorCode.PASSPORT_CONFLICT
    assert refused.value.lines == ["the macro is for LiPo; the battery is NiMh",
                                   "the macro charges at 3.00 A (charge phase 1); the battery allows 2 A",
                                   "the macro lets the voltage rise to 12.30 V (charge phase 1); the battery allows 8 V"]
    # (the fourth, CONSTANT_V=4.2S in phase 2, does not fit the one ERROR frame: only whole lines are sent)
    assert c.start(1, "charge", capacity_mah=2000, current_a=2.0, series=4) == "NiMh-dV"


def test_a_battery_with_critical_errors_does_not_start(client):
    c = client("--passport", "3:0:0:2")
    c.write_image(eeprom.pack([compiled("NiMh-dV")], c.info.eeprom_size))
    with pytest.raises(DeviceError) as refused:
        c.start(0, "charge", capacity_mah=2000, current_a=2.0, series=4)
    assert refused.value.lines == ["the battery has 2 critical error(s) (CRIT): it is not fit for use"]


def test_the_start_templates_are_the_factory_table_and_survive_a_restart(client, tmp_path):
    path = tmp_path / "ee.bin"
    c = client("--eeprom", path)
    assert c.list_templates() == sorted(factory_templates())
    assert {n: c.get_template(n) for n in c.list_templates()} == dict(factory_templates())
    stored = c.set_template(9, StartTemplate("train", 2, 1500, 0.75, None, 4))
    assert stored == StartTemplate("train", 2, 1500, 0.75, None, 4)
    with pytest.raises(DeviceError) as missing:
        c.get_template(10)
    assert missing.value.code == m.ErrorCode.NO_TEMPLATE
    c.close()
    until(lambda: path.exists() and len(path.read_bytes()) == 1024 and path.read_bytes()[862 + 8 * 10] == 2)
    assert client("--eeprom", path).get_template(9).task == "train"


def test_a_template_a_set_cannot_hold_is_refused(client):
    c = client()
    for fields in ([17, 0, 1, 0, 0, 0, 0, 0, 0, 0], [1, 3, 1, 0, 0, 0, 0, 0, 0, 0], [1, 0, 0, 0, 0, 0, 0, 0, 0, 0]):
        with pytest.raises(DeviceError) as refused:      # number 17, task 3, 0 repetitions
            c.request("SET_TEMPLATE", bytes(fields), response_len=12)
        assert refused.value.code == m.ErrorCode.BAD_RANGE
    assert c.list_templates() == sorted(factory_templates())


def test_start_shablon_takes_its_values_from_the_charger_and_a_missing_one_refuses(client):
    c = client()
    uses = compiled("MACRO T\nSTART_SHABLON=2 AKK_TYPE=LiPo\nDISCHARGE_SECTION\nEND_SECTION\nCHARGE_SECTION\n"
                    "FAZE CONSTANT_I=INPUT IF(V>4.2S) STOP_FAZE END_FAZE\nEND_SECTION\nEND_MACRO\n")
    lacks = compiled("MACRO U\nSTART_SHABLON=9 AKK_TYPE=LiPo\nDISCHARGE_SECTION\nEND_SECTION\nCHARGE_SECTION\n"
                     "FAZE CONSTANT_I=1A IF(V>4.2S) STOP_FAZE END_FAZE\nEND_SECTION\nEND_MACRO\n")
    c.write_image(eeprom.pack([uses, lacks], c.info.eeprom_size))
    assert c.start(0, "discharge") == "T"          # template 2: charge 3S 2200 mAh at 2.2 A
    assert c.status().task == "charge"
    with pytest.raises(DeviceError) as busy:
        c.start(1, "charge", current_a=1.0)
    assert busy.value.code == m.ErrorCode.BUSY                  # a START during a run: stop it first
    c.stop()
    with pytest.raises(DeviceError) as refused:
        c.start(1, "charge", current_a=1.0)
    assert refused.value.code == m.ErrorCode.START_ERROR and "START_SHABLON" in str(refused.value)


def test_the_batterys_passport_takes_err_and_crit_only_and_answers_every_request(client):
    c = client("--passport", "3:8:2")                 # NiMh, 8 V, 2 A
    assert c.passport_write("err", 3).err == 3
    with pytest.raises(DeviceError) as refused:
        c.passport_write("type", "LiPo")
    assert refused.value.code == m.ErrorCode.PASSPORT_ERROR and "read-only" in str(refused.value)
    assert c.passport_read().type == 3
    bad_page = bytearray(pp.read_all_request())
    bad_page[1:3] = bytes([0x17, 7])
    bad_page[7] = 0
    for b in bad_page[:7]:
        bad_page[7] ^= b
    answer = c.passport_raw(bytes(bad_page))
    assert len(answer) == 32 and pp.answer_error(answer) is not None and answer[2] == pp.AnswerError.BAD_PAGE


@pytest.mark.parametrize("request_", [b"", b"\xa7\x00\x00", bytes(9), b"\xa7" + bytes(6) + b"\xa7" + b"\x00",
                                      b"\x00" * 8])
def test_a_malformed_passport_request_gets_the_same_32_bytes_from_the_firmware_and_the_virtual_charger(
        client, make_charger, request_):
    firmware = client("--passport", "3:8:2")
    _, port = make_charger(battery="NiMh:2000:4", passport=pp.Passport("ZUML-HOST-0001", "ZUML", 3, 0, 0, 8, 2))
    virtual = ChargerClient(port, timeout=2)
    try:
        mine, theirs = firmware.passport_raw(request_), virtual.passport_raw(request_)
    finally:
        virtual.close()
    assert len(mine) == 32 and pp.answer_error(mine) is not None
    assert mine == theirs


LITHIUM_TRICKLE = ("MACRO LiT\nAKK_TYPE=LiPo\nCHARGE_SECTION\nFAZE CONSTANT_I=1A IF(V>4.1S) STOP_FAZE END_FAZE\n"
                   "FAZE TRICKLE(0.05C, 4.0S, 4.1S) IF(tf>1h) STOP_FAZE END_FAZE\nEND_SECTION\nEND_MACRO\n")


def test_a_lithium_trickle_charge_is_refused_as_the_virtual_charger_refuses_it(client, make_charger):
    record = unsafe_record(LITHIUM_TRICKLE)
    firmware = client("--passport", "4:20:5")                       # LiPo, 20 V, 5 A
    _, port = make_charger(battery="LiPo:2000:3", passport=pp.Passport("ZUML-HOST-0001", "ZUML", 4, 0, 0, 20, 5))
    virtual = ChargerClient(port, timeout=2)
    refusals = []
    try:
        for c in (firmware, virtual):
            c.write_image(eeprom.pack([record], c.info.eeprom_size))
            with pytest.raises(DeviceError) as refused:
                c.start(0, "charge", capacity_mah=2000, current_a=1.0, series=3)
            refusals.append(refused.value)
    finally:
        virtual.close()
    mine, theirs = refusals
    assert mine.code == theirs.code == m.ErrorCode.PASSPORT_CONFLICT
    assert mine.lines == theirs.lines == [f"E311 (byte {record.index(63)}): Lithium cells must never be "
                                          "trickle-charged"]


def test_a_start_template_a_power_cut_tore_is_no_template(client, tmp_path):
    # templates 1..3 of the factory table, then template 2 with its last byte changed and its check byte not
    c = client("--eeprom", tmp_path / "ee.bin")
    assert c.list_templates() == [1, 2, 3]
    c.close()
    path = tmp_path / "ee.bin"
    # template 3's task byte, written last (charge: 0), is in the file
    until(lambda: path.exists() and len(path.read_bytes()) == 1024 and path.read_bytes()[862 + 2 * 10] == 0)
    ee = bytearray(path.read_bytes())
    ee[862 + 10 + 8] ^= 0x01                          # template 2's cell count, half written
    path.write_bytes(bytes(ee))
    c = client("--eeprom", path)
    assert c.list_templates() == [1, 3]
    with pytest.raises(DeviceError) as missing:
        c.get_template(2)
    assert missing.value.code == m.ErrorCode.NO_TEMPLATE


def test_the_eeprom_is_not_written_while_a_macro_runs(client):
    c = client()
    image = eeprom.pack([compiled("LiPo")], c.info.eeprom_size)
    c.write_image(image)
    c.start(0, "charge", capacity_mah=2000, current_a=1.0, series=3)
    for ask in (lambda: c.write_image(eeprom.pack([], c.info.eeprom_size)),
                lambda: c.set_template(5, StartTemplate("charge", 1, 1000, 1.0, None, 3))):
        with pytest.raises(DeviceError) as busy:
            ask()
        assert busy.value.code == 15 and "stop it first" in str(busy.value)
    assert c.read_image() == image and 5 not in c.list_templates()
    c.stop()
    c.set_template(5, StartTemplate("charge", 1, 1000, 1.0, None, 3))
    assert 5 in c.list_templates()
