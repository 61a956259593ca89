"""CRC-16/MODBUS and the frame codec/parser, fuzzed: never raises, never loses a frame after garbage."""
import os

from hypothesis import given, strategies as st

from zuml_studio.protocol.crc import crc16, crc16_update
from zuml_studio.protocol.frames import MAX_PAYLOAD, Frame, FrameParser, encode_frame


def test_crc_check_value_is_modbus():
    assert crc16(b"123456789") == 0x4B37
    assert crc16(b"") == 0xFFFF
    # cheali-charger's crc16_update byte by byte agrees with the two-bytes-per-step table
    for n in range(40):
        data = os.urandom(n)
        assert crc16(data) == crc16_update(0xFFFF, data) == crc16(bytearray(data)) == crc16(memoryview(data))


def test_frame_layout():
    raw = encode_frame(0x12, 7, b"\x01\x02")
    assert raw[:5] == bytes([0xA5, 2, 0x12, 7, 1])
    crc = crc16(raw[1:-2])
    assert raw[-2:] == bytes([crc & 0xFF, crc >> 8])      # little-endian, over LEN..PAYLOAD
    assert FrameParser().feed(raw) == [Frame(0x12, 7, b"\x01\x02")]


def test_empty_and_largest_payloads_and_limits():
    p = FrameParser()
    frames = [encode_frame(1, 0, b""), encode_frame(2, 255, bytes(range(250)))]
    assert p.feed(b"".join(frames)) == [Frame(1, 0, b""), Frame(2, 255, bytes(range(250)))]
    try:
        encode_frame(1, 0, bytes(MAX_PAYLOAD + 1))
    except ValueError:
        pass
    else:
        raise AssertionError("a 251-byte payload must be refused")


def test_impossible_len_and_bad_crc_drop_only_the_sync_byte():
    good = encode_frame(0x40, 1, b"hello")
    bad_crc = bytearray(encode_frame(0x40, 2, b"world"))
    bad_crc[-1] ^= 0xFF
    p = FrameParser()
    out = p.feed(b"\xa5\xff" + bytes(bad_crc) + good)
    assert out == [Frame(0x40, 1, b"hello")]
    assert p.bad_frames >= 2 and p.skipped == 2 + len(bad_crc)


def test_false_sync_waiting_for_bytes_does_not_hold_back_a_good_frame():
    good = encode_frame(0x40, 1, b"x" * 10)
    p = FrameParser()
    assert p.feed(b"\xa5\xf0\x40\x00" + good) == [Frame(0x40, 1, b"x" * 10)]   # LEN 240 from garbage


def test_unknown_types_are_refused_at_once():
    p = FrameParser(frozenset({0x40}))
    good = encode_frame(0x40, 1, b"ok")
    assert p.feed(encode_frame(0x41, 1, b"no") + good) == [Frame(0x40, 1, b"ok")]


frames_st = st.lists(st.tuples(st.integers(0, 255), st.integers(0, 255), st.binary(max_size=60)),
                     min_size=1, max_size=6)


def _feed_chunks(parser, data, cuts):
    out = []
    at = 0
    for cut in sorted(c % (len(data) + 1) for c in cuts):
        out += parser.feed(data[at:cut]) if cut > at else []
        at = max(at, cut)
    return out + parser.feed(data[at:])


def _subsequence(needles, hay):
    it = iter(hay)
    return all(any(x == y for y in it) for x in needles)


@given(st.binary(max_size=600), st.lists(st.integers(0, 700), max_size=8))
def test_random_bytes_never_raise(data, cuts):
    p = FrameParser()
    out = _feed_chunks(p, data, cuts)
    assert p.skipped + sum(len(f.payload) + 6 for f in out) + p.pending == len(data)


@given(st.lists(st.tuples(st.binary(max_size=40), st.integers(0, 255), st.integers(0, 255),
                          st.binary(max_size=80)), min_size=1, max_size=6),
       st.lists(st.integers(0, 2000), max_size=10))
def test_every_frame_after_garbage_is_found(parts, cuts):
    wanted = [Frame(t, s, p) for _, t, s, p in parts]
    data = b"".join(garbage + encode_frame(t, s, p) for garbage, t, s, p in parts)
    out = _feed_chunks(FrameParser(), data, cuts)
    assert _subsequence(wanted, out)


@given(frames_st, st.lists(st.integers(0, 10 ** 6), max_size=6), st.lists(st.integers(0, 2000), max_size=6))
def test_bit_flips_lose_only_the_frames_they_hit(frames, flips, cuts):
    encoded = [encode_frame(t, s, p) for t, s, p in frames]
    data = bytearray(b"".join(encoded))
    hit = set()
    for f in flips:
        bit = f % (8 * len(data))
        data[bit >> 3] ^= 1 << (bit & 7)
        at, k = bit >> 3, 0
        while at >= len(encoded[k]):
            at -= len(encoded[k])
            k += 1
        hit.add(k)
    untouched = [Frame(t, s, p) for k, (t, s, p) in enumerate(frames) if k not in hit]
    out = _feed_chunks(FrameParser(), bytes(data), cuts)
    assert _subsequence(untouched, out)
