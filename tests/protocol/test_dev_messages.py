"""The message table: every layout round-trips; telemetry carries a signed current."""
from dataclasses import replace

import pytest

from zuml_studio.protocol import messages as m

TEMPLATE = dict(number=2, task=2, repetitions=3, capacity_mah=2200, current_ma=2200, voltage_mv=0, series=3)
SAMPLES = {
    "IDENTIFY": ({}, dict(protocol=1, eeprom_size=1024, max_data=240, max_charge_ma=5000, max_charge_dw=500,
                          max_discharge_ma=1000, max_discharge_dw=50, max_mv=27000, write_us_per_byte=0,
                          model="iMAX B6 (virtual)", firmware="x 1.0")),
    "READ_EEPROM": (dict(offset=10, length=240), dict(offset=10, data=bytes(range(240)))),
    "BEGIN_WRITE": (dict(nonce=0x5EED1234), dict(token=0xDEADBEEF, size=1024)),
    "WRITE_STAGE": (dict(token=1, offset=1000, data=b"\x00\xff" * 12), dict(offset=1000, length=24)),
    "COMMIT": (dict(token=5, crc=0x4B37), dict(changed=17, crc=0x4B37)),
    "ABORT": (dict(token=0), {}),
    "START": (dict(slot=3, task=2, repetitions=4, capacity_mah=2000, current_ma=1500, voltage_mv=0, series=4,
                   sensor=1), dict(slot=3, name="NiMh-dV")),
    "STOP": ({}, dict(state=3)),
    "STATUS": ({}, dict(state=1, slot=0, task=0, uptime_ms=5, run_ms=3870000, events=5, speed=20000,
                        name="NiMh-dV", end_reason="")),
    "SET_TELEMETRY_RATE": (dict(hz=50), dict(hz=50)),
    "GET_EVENT": (dict(number=7), dict(number=7, time_ms=1, kind=2, section=1, index=1, repetition=1, offset=17,
                                       detail="IF(V>1.8S) STOP_FAZE")),
    "PASSPORT": (dict(request=bytes(8)), dict(answer=bytes(32))),
    "LIST_TEMPLATES": ({}, dict(numbers=bytes((1, 2, 3)))),
    "GET_TEMPLATE": (dict(number=2), TEMPLATE),
    "SET_TEMPLATE": (TEMPLATE, TEMPLATE),
    "CAL_READ": ({}, dict(source=1, block=bytes(54))),
    "CAL_WRITE": (dict(block=bytes(54)), dict(source=1, block=bytes(54))),
    "CAL_MEASURE": ({}, dict(inputs=bytes(78))),
    "CAL_OUTPUT": (dict(mode=1, current_ma=1000), dict(mode=1, current_ma=1000)),
}


def test_one_table_every_request_has_a_sample():
    requests = {t.name for t in m.MESSAGE_TYPES if t.request is not None}
    assert requests == set(SAMPLES)
    codes = [t.code for t in m.MESSAGE_TYPES]
    assert len(codes) == len(set(codes))
    assert all(t.response_code not in m.REQUEST_CODES for t in m.MESSAGE_TYPES)


@pytest.mark.parametrize("name", sorted(SAMPLES))
def test_layouts_round_trip(name):
    req, resp = SAMPLES[name]
    code = m.BY_NAME[name].code
    assert m.decode_request(code, m.encode_request(name, **req)) == req
    assert m.decode_response(code, m.encode_response(name, **resp)) == resp


def test_short_or_long_payloads_are_refused():
    with pytest.raises(m.PayloadError):
        m.decode_request(m.READ_EEPROM, b"\x00")
    with pytest.raises(m.PayloadError):
        m.decode_request(m.READ_EEPROM, b"\x00\x00\x10\x00")


def test_telemetry_current_is_signed_and_temperature_may_be_unknown():
    t = m.Telemetry(3600.5, "discharge", "discharge", 1, 2, 1, 3, True, False, False, 4.812, -0.997, None, 41.25,
                    0.0, 1234.5)
    back = m.Telemetry.decode(t.encode())
    assert back == t
    assert back.current_a < 0 and back.temp_c is None


def test_event_round_trip_and_error_payload():
    e = m.DeviceEvent(4, 3870.0, "phase_end", "charge", 1, 1, 17, "IF(DELTA_PEAK>0.01S) STOP_FAZE")
    assert m.DeviceEvent.decode(e.encode()) == e
    assert m.decode_error(m.encode_error(0x10, m.ErrorCode.PASSPORT_CONFLICT, "a\nb")) == (0x10, 9, "a\nb")


def test_telemetry_carries_up_to_six_cells_and_the_balance_mask():
    t = m.Telemetry(10.0, "charge", "charge", 1, 0, 1, 1, True, False, True, 16.5, 2.0, 25.0, 30.0, 5.0, 0.0,
                    cells_v=(4.1, 4.12, 4.13, 4.15), balance_mask=0b1010)
    assert m.Telemetry.decode(t.encode()) == t
    eight = replace(t, cells_v=tuple(4.0 + k / 100 for k in range(8)), balance_mask=0xFF)
    back = m.Telemetry.decode(eight.encode())
    assert back.cells_v == eight.cells_v[:6] and back.balance_mask == 0x3F
    one = replace(t, cells_v=(4.1,), balance_mask=0)
    assert len(one.encode()) == 30 and m.Telemetry.decode(one.encode()).cells_v == ()
    with pytest.raises(m.PayloadError, match="cell tail"):
        m.Telemetry.decode(t.encode()[:-1])
    frame = bytearray(t.encode())
    frame[m._TELEMETRY_STRUCT.size + 1] = 0b10000    # cell 5 of a 4-cell tail
    with pytest.raises(m.PayloadError, match="beyond its 4 cells"):
        m.Telemetry.decode(bytes(frame))
