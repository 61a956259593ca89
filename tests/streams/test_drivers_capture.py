"""The driver registry, decoding a whole capture, auto-detection, and decoders that never
raise, never grow without bound and give the same samples however the bytes are cut."""
import random

import pytest
from hypothesis import given, settings, strategies as st

from realdata_samples import (ICHARGER_HID_REPORT, IMAXB6_README_FRAME, dollar_lines, imaxb6_frames, isdt_frames, raw,
                      skyrc_reply, ultramat_sections)
from zuml_studio.streams.autodetect import BaudSweep, Detector, usual_bauds
from zuml_studio.streams.drivers import DRIVERS, CaptureError, decode_capture, hex_dump_reports

CHEALI = b"".join(line + b"\r\n" for line in dollar_lines("cheali_captured_lines_from_issues.txt"))
ICHARGER = raw("icharger306B_RB_1000_lines_head300.txt")
STREAMS = {
    "cheali": CHEALI,
    "icharger": ICHARGER,
    "imaxb6": b"".join(imaxb6_frames()[:50]),
    "ultramat": b"".join(ultramat_sections()["Ultramat16"]),
    "icharger-hid": ICHARGER_HID_REPORT * 3,
    "isdt": b"".join(isdt_frames()),
    "skyrc": b"".join(skyrc_reply(1, k, 2 * k, 3800 + k, 300, 0, 30, [3800 + k, 3790]) for k in range(6)),
}


def test_registry():
    assert set(DRIVERS) == {"cheali", "icharger", "imaxb6", "ultramat", "zuml-tx", "skyrc", "icharger-hid", "isdt"}
    assert all(d.monitor_only for d in DRIVERS.values())
    assert DRIVERS["cheali"].baud == 57600 and DRIVERS["icharger"].baud == 128000 and 9600 in DRIVERS["icharger"].bauds
    assert DRIVERS["imaxb6"].baud == DRIVERS["ultramat"].baud == 9600
    assert DRIVERS["icharger-hid"].vid_pids == ((0x0483, 0x5751),) and DRIVERS["isdt"].vid_pids == ((0x28E9, 0x028A),)
    assert DRIVERS["skyrc"].transport == "hid" and DRIVERS["skyrc"].baud is None


@pytest.mark.parametrize("name", list(STREAMS))
def test_decode_capture_recognises_each_format(name):
    driver, samples, bad = decode_capture(STREAMS[name])
    assert driver == name and samples and bad == 0
    assert decode_capture(STREAMS[name], name)[1] == samples


def test_decode_capture_hex_dump_and_refusal():
    dump = "# a dump\nRX " + ICHARGER_HID_REPORT[:32].hex(" ") + "\nTX 0f 03 55 00 55 ff ff\n"
    assert hex_dump_reports(dump.encode()) == ICHARGER_HID_REPORT
    assert decode_capture(dump.encode())[0] == "icharger-hid"
    with pytest.raises(CaptureError, match="tried cheali, icharger, imaxb6, ultramat, zuml-tx, skyrc, icharger-hid, isdt"):
        decode_capture(b"hello, this is not a charger\n" * 10)
    name, samples, bad = decode_capture(b"garbage", "cheali")          # a forced driver reports, never guesses
    assert (name, samples) == ("cheali", [])


@pytest.mark.parametrize("name", ["cheali", "icharger", "imaxb6", "ultramat"])
def test_detector_recognises_a_serial_stream_without_losing_a_sample(name):
    whole = decode_capture(STREAMS[name], name)[1]
    det = Detector()
    got = []
    data = b"\xff\x13junk at the start" + STREAMS[name]
    for i in range(0, len(data), 7):
        got += det.feed(data[i:i + 7])
    assert det.winner == name and got == whole


def test_detector_ignores_garbage():
    det = Detector()
    rng = random.Random(1)
    det.feed(bytes(rng.randrange(256) for _ in range(20000)))
    assert det.winner is None


def test_baud_sweep_moves_on_junk_or_time_and_names_what_it_tried():
    sweep = BaudSweep(first=9600)
    assert sweep.baud == 9600 and sweep.bauds == (9600,) + tuple(b for b in usual_bauds() if b != 9600)
    assert not sweep.advance(0.0, b"") and not sweep.advance(100.0, b"")    # silence: keep listening
    line = b";0;0;354;0;1;26\r\n$1;1;;15564;12645;19;4203"                 # torn, but a record starts
    assert not sweep.advance(100.0, line) and not sweep.advance(101.0, b"") and not sweep.advance(102.4, b"")
    assert sweep.advance(102.6, b"") and sweep.baud == sweep.bauds[1]       # 2.5 s of data, no record
    assert not sweep.advance(103.0, bytes(range(128, 160)))                 # a burst of junk ...
    assert not sweep.advance(103.2, b"")
    assert sweep.advance(103.3, b"") and sweep.baud == sweep.bauds[2]       # ... ends: the next baud
    assert not sweep.advance(104.0, b"\x80\x01") and not sweep.advance(104.5, b"")   # too short to judge
    assert sweep.advance(104.6, b"\x81" * 250)                               # many bytes, no record
    while not sweep.done:
        sweep.advance(200.0, b"\x00" * 500)
    assert "tried cheali, icharger, imaxb6, ultramat, zuml-tx at 9600, 57600, 128000" in sweep.message("/dev/x", Detector())
    assert usual_bauds()[:3] == (57600, 128000, 9600)


@pytest.mark.parametrize("name", list(STREAMS))
def test_the_cut_does_not_matter(name):
    data = hex_dump_reports(STREAMS[name]) or STREAMS[name]
    whole = DRIVERS[name].decoder().feed(data)
    dec = DRIVERS[name].decoder()
    rng = random.Random(7)
    got, i = [], 0
    while i < len(data):
        n = rng.randrange(1, 90)
        got += dec.feed(data[i:i + n])
        i += n
    assert got == whole


def _feed(name: str, data: bytes, cuts) -> tuple[list, tuple[int, int, int]]:
    dec = DRIVERS[name].decoder()
    got, at = [], 0
    for cut in list(cuts) + [len(data)]:
        got += dec.feed(data[at:cut])
        at = cut
    return got, (dec.good, dec.bad, dec.skipped)


def _torn_long_line() -> bytes:
    """A cheali line with another charger's frames inside it, past the line cap (issue 27: in one piece
    the decoder read it as a record, in pieces it dropped it), then a good line."""
    line = dollar_lines("cheali_captured_lines_from_issues.txt")[4]
    inner = b"\r".join(ultramat_sections()["Ultramat16"][:6])
    return line[:40] + inner + line[40:] + b"\r\n" + line + b"\r\n"


def _hostile_inputs() -> list[bytes]:
    inputs = [_torn_long_line()]
    for source in sorted(STREAMS):
        base = (hex_dump_reports(STREAMS[source]) or STREAMS[source])[:1500]
        inputs.append(base)
        inputs += [_mutate(base, random.Random(seed)) for seed in range(8)]
    return inputs


@pytest.mark.parametrize("name", list(DRIVERS))
def test_every_input_gives_the_same_samples_in_one_piece_byte_by_byte_and_at_random_cuts(name):
    """A serial port (or HID read) delivers bytes in whatever pieces it likes (issue 27)."""
    rng = random.Random(27)
    for data in _hostile_inputs():
        whole = _feed(name, data, [])
        assert _feed(name, data, range(1, len(data))) == whole
        for _ in range(3):
            cuts = sorted(rng.sample(range(1, len(data)), min(len(data) - 1, rng.randrange(1, 40))))
            assert _feed(name, data, cuts) == whole


@pytest.mark.parametrize("name", list(DRIVERS))
def test_memory_is_bounded_without_terminators(name):
    dec = DRIVERS[name].decoder()
    for _ in range(200):
        dec.feed(b"$1;1;" + b"7" * 997)
        dec.feed(b"\x0c" + b"A" * 999)
        dec.feed(b"{" + b"\x81" * 999)
    assert dec.pending <= dec.max_record


def _mutate(data: bytes, rng: random.Random) -> bytes:
    b = bytearray(data)
    for _ in range(rng.randrange(1, 8)):
        op = rng.randrange(4)
        if not b:
            break
        at = rng.randrange(len(b))
        if op == 0:
            b[at] ^= 1 << rng.randrange(8)
        elif op == 1:
            del b[at:at + rng.randrange(1, 20)]
        elif op == 2:
            b[at:at] = bytes(rng.randrange(256) for _ in range(rng.randrange(1, 20)))
        else:
            b[at] = rng.choice(b"$;\r\n{}\x0c\x0d\xaa\x0f\x02")
    return bytes(b)


@settings(max_examples=150, deadline=None)
@given(seed=st.integers(0, 2**32 - 1), cut=st.integers(1, 80), driver=st.sampled_from(sorted(DRIVERS)),
       source=st.sampled_from(sorted(STREAMS)))
def test_fuzzed_streams_never_raise_and_never_invent_values(seed, cut, driver, source):
    """Mutated real streams: no exception, and every sample is plausible (a corrupted record that
    slips through an 8-bit checksum still has to pass the shape and range checks)."""
    rng = random.Random(seed)
    base = hex_dump_reports(STREAMS[source]) or STREAMS[source]
    data = _mutate(base[:2000], rng)
    dec = DRIVERS[driver].decoder()
    for i in range(0, len(data), cut):
        for t in dec.feed(data[i:i + cut]):
            assert 0 <= t.voltage_v < 70 and abs(t.current_a) < 400 and t.time_s >= 0
    assert dec.pending <= dec.max_record


@pytest.mark.parametrize("name", list(STREAMS))
def test_imaxb6_frame_between_others_is_not_lost(name):
    """Another format's bytes before a good frame do not swallow it."""
    dec = DRIVERS["imaxb6"].decoder()
    assert len(dec.feed(STREAMS[name][:300] + IMAXB6_README_FRAME)) >= 1


def test_drivers_import_neither_qt_nor_hidapi():
    """Everything but ui/ is Qt-free, and hidapi loads only when a HID port is listed or opened."""
    import subprocess
    import sys
    mods = ", ".join(f"zuml_studio.{m}" for m in (
        "streams.drivers", "streams.autodetect", "device.links.monitor_link", "virtual.replay", "device.links.hid_link",
        "logs.session_log", "streams.cheali", "streams.icharger_logview", "streams.imaxb6_serial", "streams.ultramat",
        "streams.skyrc_hid", "streams.icharger_hid", "streams.isdt_hid"))
    code = (f"import sys; import {mods}; "
            "print(any(m.split('.')[0] in ('PySide6', 'pyqtgraph', 'hid') for m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "False"


def test_a_long_recording_is_read_by_the_driver_its_start_shows(monkeypatch):
    """Issue 27: every driver decoded every reading of a capture (5 s per MB); past CHOOSE_ON bytes
    the start picks one, which alone decodes the rest, to the same samples, saying how far it is."""
    from zuml_studio.streams import drivers
    big = ICHARGER * (drivers.CHOOSE_ON // len(ICHARGER) + 2)
    whole = drivers.decode_capture(big, "icharger")
    decoded = []
    real = drivers.decode_capture
    monkeypatch.setattr(drivers, "decode_capture", lambda data, driver=None: (
        decoded.append((len(data), driver)), real(data, driver))[1])
    pieces = []
    got = drivers.decode_recording(big, progress=lambda done, total: pieces.append((done, total)))
    assert (got.driver, got.samples, got.bad) == ("icharger", whole[1], whole[2])
    assert not [n for n, _driver in decoded if n > drivers.CHOOSE_ON]      # no driver tried on the whole
    assert pieces[-1] == (len(big), len(big)) and len(pieces) == -(-len(big) // drivers.CHOOSE_ON)
