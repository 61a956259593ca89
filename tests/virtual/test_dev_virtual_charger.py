"""The virtual charger's device logic in-process, without a port: EEPROM transactions,
replayed requests, refusals, telemetry coalescing, events never dropped, signed current."""
import time

import pytest

from zuml_studio.protocol import messages as m
from zuml_studio.protocol.crc import crc16
from zuml_studio.protocol.frames import FrameParser, encode_frame
from zuml_studio.virtual.virtual_charger import BatterySpec, DeviceSetupError, VirtualCharger
from zuml_studio.lang.eeprom import pack, slots

from helpers import compiled, until


class Wire:
    """Talks to a device by calling receive/read_output directly."""

    def __init__(self, device):
        self.device = device
        self.parser = FrameParser()
        self.seq = 0
        self.unsolicited = []

    def raw(self, name, seq=None, **fields):
        code = m.BY_NAME[name].code
        if seq is None:
            self.seq = (self.seq + 1) & 0xFF
            seq = self.seq
        self.device.receive(encode_frame(code, seq, m.encode_request(name, **fields)))
        answer = None
        for frame in self.parser.feed(self.device.read_output(1 << 20)):
            if frame.type in (m.TELEMETRY, m.EVENT):
                self.unsolicited.append(frame)
            elif frame.seq == seq:
                answer = frame
        assert answer is not None, f"no answer to {name}"
        return answer

    def call(self, name, **fields):
        frame = self.raw(name, **fields)
        if frame.type == m.ERROR:
            req, code, text = m.decode_error(frame.payload)
            raise RefusedError(m.ErrorCode(code), text)
        assert frame.type == m.BY_NAME[name].code | 0x80
        return m.decode_response(m.BY_NAME[name].code, frame.payload)


class RefusedError(Exception):
    def __init__(self, code, text):
        super().__init__(f"{code.name}: {text}")
        self.code = code
        self.text = text


@pytest.fixture
def dev():
    d = VirtualCharger("NiMh:2000:4", speed=20000)
    yield d
    d.close()


def test_identify_reports_charger_model_limits(dev):
    v = Wire(dev).call("IDENTIFY")
    assert v["eeprom_size"] == 1024 and v["max_data"] == 240
    assert (v["max_charge_ma"], v["max_charge_dw"], v["max_discharge_ma"], v["max_discharge_dw"]) == (5000, 500, 1000, 50)
    assert "iMAX B6" in v["model"]


def test_reads_are_bounded(dev):
    w = Wire(dev)
    assert w.call("READ_EEPROM", offset=1000, length=24)["data"] == b"\xff" * 24
    for offset, length in ((1000, 25), (0, 241), (0, 0)):
        with pytest.raises(RefusedError) as exc:
            w.call("READ_EEPROM", offset=offset, length=length)
        assert exc.value.code is m.ErrorCode.BAD_RANGE


def _stage(w, image, nonce=0x600D5EED):
    token = w.call("BEGIN_WRITE", nonce=nonce)["token"]
    assert token == nonce                                    # the host's nonce is the token
    for at in range(0, len(image), 240):
        w.call("WRITE_STAGE", token=token, offset=at, data=image[at:at + 240])
    return token


def test_commit_checks_crc_and_abandoned_transfers_change_nothing(dev):
    w = Wire(dev)
    image = pack([compiled("NiMh-dV")])
    token = _stage(w, image)
    assert dev.eeprom_image == b"\xff" * 1024                # staged only
    with pytest.raises(RefusedError) as exc:
        w.call("COMMIT", token=token, crc=crc16(image) ^ 1)
    assert exc.value.code is m.ErrorCode.CRC_MISMATCH and dev.eeprom_image == b"\xff" * 1024
    done = w.call("COMMIT", token=token, crc=crc16(image))
    assert done["changed"] == sum(b != 0xFF for b in image) and dev.eeprom_image == image
    # the same COMMIT again (its answer was lost): success again, nothing more written
    assert w.call("COMMIT", token=token, crc=crc16(image)) == done
    # a new transfer that is abandoned (BEGIN again, or ABORT) never reaches the EEPROM
    token = _stage(w, pack([compiled("LiPo")]), nonce=2)
    w.call("BEGIN_WRITE", nonce=3)
    with pytest.raises(RefusedError) as exc:
        w.call("COMMIT", token=token, crc=crc16(pack([compiled("LiPo")])))
    assert exc.value.code is m.ErrorCode.BAD_TOKEN and dev.eeprom_image == image
    token = _stage(w, pack([compiled("LiPo")]), nonce=4)
    w.call("ABORT", token=token)
    assert not dev.staging_open and dev.eeprom_image == image


def test_a_repeated_request_is_answered_not_redone(dev):
    w = Wire(dev)
    image = pack([compiled("NiMh-dV")])
    w.call("COMMIT", token=_stage(w, image), crc=crc16(image))
    fields = dict(slot=0, task=0, repetitions=1, capacity_mah=2000, current_ma=2000, voltage_mv=0, series=4, sensor=0)
    first = w.raw("START", seq=200, **fields)
    dev.step(time.monotonic() + 0.05)
    events = len(dev.run_events)
    again = w.raw("START", seq=200, **fields)            # a retry with the same SEQ
    assert again.payload == first.payload and len(dev.run_events) == events
    assert dev.run_events[0].kind == "section"


def test_start_refusals(dev):
    w = Wire(dev)
    start = dict(task=0, repetitions=1, capacity_mah=2000, current_ma=2000, voltage_mv=0, series=4, sensor=0)
    with pytest.raises(RefusedError) as exc:
        w.call("START", slot=0, **start)
    assert exc.value.code is m.ErrorCode.BAD_SLOT
    rec = bytearray(compiled("NiMh-dV"))
    rec[-1] ^= 0x55                                      # bad check byte, written behind the protocol's back
    dev.eeprom[:len(rec)] = rec
    with pytest.raises(RefusedError) as exc:
        w.call("START", slot=0, **start)
    assert exc.value.code is m.ErrorCode.INVALID_RECORD and "check byte" in exc.value.text
    dev.eeprom[:len(rec)] = compiled("NiMh-dV")
    with pytest.raises(RefusedError) as exc:
        w.call("START", slot=0, **{**start, "current_ma": 0})
    assert exc.value.code is m.ErrorCode.START_ERROR and "INPUT" in exc.value.text
    with pytest.raises(RefusedError) as exc:
        w.call("START", slot=0, **{**start, "current_ma": 4500})
    assert exc.value.code is m.ErrorCode.PASSPORT_CONFLICT and "4.50 A" in exc.value.text


def test_telemetry_is_coalesced_and_events_are_never_dropped():
    text = ("MACRO Many\nAKK_TYPE=NiMh\nCHARGE_SECTION\nCYCLE(60)\nFAZE\nCONSTANT_I=1A\nIF(tf>30s) STOP_FAZE\n"
            "END_FAZE\nMUSIC(START)\nEND_CYCLE\nEND_SECTION\nEND_MACRO\n")
    from zuml_studio.lang.compiler import compile_source
    dev = VirtualCharger("NiMh:2000:4", speed=100000)
    try:
        dev.eeprom[:] = pack([compile_source(text).record])
        w = Wire(dev)
        w.call("SET_TELEMETRY_RATE", hz=50)
        w.call("START", slot=0, task=0, repetitions=1, capacity_mah=2000, current_ma=0, voltage_mv=0, series=4,
               sensor=0)
        dev.start()
        assert until(lambda: dev.state != "running") and dev.state == "finished"     # nobody reads meanwhile
        frames = FrameParser().feed(dev.read_output(1 << 22))
        events = [m.DeviceEvent.decode(f.payload) for f in frames if f.type == m.EVENT]
        assert [e.number for e in events] == list(range(len(dev.run_events)))
        assert sum(e.kind == "phase_end" for e in events) == 60 and events[-1].kind == "finish"
        assert sum(f.type == m.TELEMETRY for f in frames) <= 1
    finally:
        dev.close()


def test_discharge_current_is_negative_in_telemetry():
    dev = VirtualCharger("NiMh:2000:4", speed=100000, soc=1.0)
    try:
        dev.eeprom[:] = pack([compiled("NiMh")])
        w = Wire(dev)
        w.call("START", slot=0, task=1, repetitions=1, capacity_mah=2000, current_ma=0, voltage_mv=0, series=4,
               sensor=0)
        t0 = time.monotonic()
        dev.step(t0 + 0.01)
        frames = FrameParser().feed(dev.read_output(1 << 20))
        tel = [m.Telemetry.decode(f.payload) for f in frames if f.type == m.TELEMETRY][-1]
        assert tel.running and tel.section == "discharge" and tel.current_a < -0.5
        assert tel.mah_out > 0 and tel.mah_in == 0
    finally:
        dev.close()


def test_eeprom_file_is_loaded_and_every_commit_persisted(tmp_path):
    path = tmp_path / "eeprom.bin"
    image = pack([compiled("NiMh-dV")])
    dev = VirtualCharger(eeprom_path=path)
    w = Wire(dev)
    w.call("COMMIT", token=_stage(w, image), crc=crc16(image))
    assert path.read_bytes() == image
    assert [s.name for s in slots(VirtualCharger(eeprom_path=path).eeprom_image)] == ["NiMh-dV"]


def test_setup_errors():
    for bad in ("NiMh", "Foo:2000:4", "NiMh:x:4", "NiMh:2000:0"):
        with pytest.raises(DeviceSetupError):
            BatterySpec.parse(bad)
    with pytest.raises(DeviceSetupError):
        VirtualCharger(speed=0.5)
    with pytest.raises(DeviceSetupError):
        VirtualCharger(passport="Bogus")
    assert VirtualCharger(passport="none").chip is None
    assert VirtualCharger(passport="LiPo").chip.passport.type == 4


def test_telemetry_carries_the_unequal_cells_and_the_balancers_mask():
    from zuml_studio.sim.cell_pack import CellSpec
    cells = [CellSpec(2000.0)] * 3 + [CellSpec(1700.0)]           # the last cell 15 % weaker
    dev = VirtualCharger("LiPo:2000:4", speed=100, cells=cells)
    try:
        dev.eeprom[:] = pack([compiled("LiPo")])
        w = Wire(dev)
        w.call("START", slot=0, task=0, repetitions=1, capacity_mah=2000, current_ma=2000, voltage_mv=0, series=4,
               sensor=1)
        t0 = time.monotonic()
        seen = []
        # the B6 balances once a cell is at 3.75 V, in windows of 15 s (4 s off): a TELEMETRY every 100 s of the
        # charge (1 Hz at 100x), up to 5.5 h, 5 s a step
        for k in range(1, 4000):
            dev.step(t0 + k * 0.05)
            frames = FrameParser().feed(dev.read_output(1 << 20))
            seen += [m.Telemetry.decode(f.payload) for f in frames if f.type == m.TELEMETRY]
            if seen and seen[-1].running and seen[-1].balance_mask:
                break
        tel = seen[-1]
        assert tel.running and len(tel.cells_v) == 4
        assert tel.cells_v[3] - max(tel.cells_v[:3]) > 0.008           # the weak cell runs ahead
        assert tel.balance_mask & 0b1000                                # and the B6's balancer bleeds it
        assert sum(tel.cells_v) == pytest.approx(tel.voltage_v, abs=0.003)
    finally:
        dev.close()
