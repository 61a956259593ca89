"""The ZUML firmware heard on its TX alone (streams/zuml_stream.py): the frames it sends unasked become samples,
events and the display's lines; broken frames are counted, answers to another host's requests skipped; the
auto-detection recognises the stream."""
from hypothesis import given, settings, strategies as st

from zuml_studio.protocol import messages as m
from zuml_studio.streams.autodetect import Detector
from zuml_studio.streams.drivers import LISTEN, driver
from zuml_studio.protocol.frames import encode_frame

SAMPLE = m.Telemetry(time_s=12.0, task="charge", section="charge", repetition=1, cycle=0, phase=2, run=2,
                     running=True, paused=False, sensor=True, voltage_v=12.6, current_a=1.5, temp_c=25.5,
                     heatsink_c=30.0, mah_in=123.4, mah_out=0.0)
FINISH = m.DeviceEvent(number=5, time_s=12.0, kind="finish", detail="end of macro")


def lcd(row: int, text: str) -> bytes:
    return encode_frame(m.LCD, 3, bytes([row]) + text.ljust(16).encode())


STREAM = (lcd(0, "1 Bench") + lcd(1, "ready Vin 11.89V") + encode_frame(m.TELEMETRY, 1, SAMPLE.encode())
          + encode_frame(m.EVENT, 2, FINISH.encode()) + lcd(0, "end Bench"))


def test_samples_events_and_the_display_come_out_as_the_firmware_sent_them():
    dec = driver(LISTEN).decoder()
    assert dec.feed(STREAM) == [SAMPLE]
    assert dec.take_extras() == [("lcd", ("1 Bench", "")), ("lcd", ("1 Bench", "ready Vin 11.89V")),
                                 ("event", FINISH), ("lcd", ("end Bench", "ready Vin 11.89V"))]
    assert dec.take_extras() == []
    assert (dec.good, dec.bad, dec.skipped) == (5, 0, 0)


@settings(max_examples=50, deadline=None)
@given(st.lists(st.integers(0, len(STREAM)), max_size=8))
def test_the_pieces_a_port_cuts_the_bytes_into_change_nothing(cuts):
    dec = driver(LISTEN).decoder()
    bounds = [0, *sorted(cuts), len(STREAM)]
    samples = [s for a, b in zip(bounds, bounds[1:]) for s in dec.feed(STREAM[a:b])]
    assert samples == [SAMPLE] and len(dec.take_extras()) == 4


def test_a_broken_frame_is_counted_and_the_next_one_still_read():
    broken = bytearray(encode_frame(m.TELEMETRY, 1, SAMPLE.encode()))
    broken[10] ^= 0xFF
    dec = driver(LISTEN).decoder()
    assert dec.feed(bytes(broken) + encode_frame(m.TELEMETRY, 2, SAMPLE.encode())) == [SAMPLE]
    assert dec.bad >= 1 and dec.good == 1


def test_a_frame_whose_payload_does_not_fit_is_bad_and_an_answer_is_skipped():
    dec = driver(LISTEN).decoder()
    dec.feed(lcd(2, "no such row") + encode_frame(m.TELEMETRY, 1, b"\x00" * 5)
             + encode_frame(m.IDENTIFY | m.RESPONSE_FLAG, 1, b"\x01"))
    assert (dec.good, dec.bad, dec.skipped) == (0, 2, 1)
    assert dec.take_extras() == []


def test_the_auto_detection_recognises_the_stream():
    det = Detector()
    assert det.feed(STREAM) == [SAMPLE]
    assert det.winner == LISTEN
