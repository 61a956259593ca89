"""Battery passport, spec §4: the byte layout, the XOR checks, the chip, the lockout."""
import pytest

from zuml_studio.device import passport as pp
from zuml_studio.lang.compiler import compile_source
from zuml_studio.sim.interpreter import StartParams

from helpers import compiled


def test_answer_layout_follows_spec_offsets():
    p = pp.Passport("A1BC2D34EFG56789", "ROGA", 5, 0x0102, 0x0304, 12, 6, 35)
    raw = p.to_bytes()
    assert len(raw) == 32
    assert raw[0x00:0x02] == b"\xa7\x01"
    assert raw[0x02:0x12] == b"A1BC2D34EFG56789"
    assert raw[0x12:0x16] == b"ROGA"
    assert raw[0x16] == 5
    assert raw[0x17:0x19] == b"\x02\x01" and raw[0x19:0x1B] == b"\x04\x03"
    assert (raw[0x1B], raw[0x1C], raw[0x1D]) == (12, 6, 35)
    check = 0
    for k in range(0, 0x1E, 2):
        check ^= raw[k] | raw[k + 1] << 8
    assert raw[0x1E:0x20] == bytes([check & 0xFF, check >> 8])
    assert pp.Passport.from_bytes(raw) == p


def test_bad_check_or_magic_is_refused():
    raw = bytearray(pp.Passport("S", "V", 3).to_bytes())
    raw[5] ^= 1
    with pytest.raises(pp.PassportError, match="check"):
        pp.Passport.from_bytes(raw)
    raw = bytearray(pp.Passport("S", "V", 3).to_bytes())
    raw[0] = 0
    with pytest.raises(pp.PassportError, match="magic"):
        pp.Passport.from_bytes(raw)


def test_requests_are_8_bytes_with_xor():
    for req in (pp.read_all_request(), pp.read_page_request(3), pp.write_page_request(7, b"\x01\x02\x03\x04")):
        assert len(req) == 8 and req[0] == 0xA7
        x = 0
        for b in req[:7]:
            x ^= b
        assert req[7] == x
    assert pp.read_page_request(3)[1:3] == b"\x13\x03"
    assert pp.write_page_request(7, b"abcd")[1:7] == b"\x27\x07abcd"
    assert pp.parse_request(pp.write_page_request(2, b"abcd")) == ("write", 2, b"abcd")
    for bad in (b"\xa7" * 8, pp.read_page_request(1)[:7] + b"\x00", bytes(8)):
        with pytest.raises(pp.PassportError):
            pp.parse_request(bad)


def test_chip_keeps_temp_and_check_and_ignores_bad_requests():
    temp = [31.6]
    chip = pp.PassportChip(pp.Passport("SER", "ZUML", 3, 0, 0, 8, 4), lambda: temp[0])
    answer = chip.answer(pp.read_all_request())
    assert answer[0x1D] == 32 and pp.check_ok(answer)
    temp[0] = -5.2
    assert pp.Passport.from_bytes(chip.answer(pp.read_page_request(7))).temp == -5
    # write page 7: A_LIMIT changes; TEMP and the check stay the battery's own
    page = bytearray(pp.page_of(answer, 7))
    page[0] = 2
    page[1] = 99
    page[2:4] = b"\x00\x00"
    after = chip.answer(pp.write_page_request(7, bytes(page)))
    p = pp.Passport.from_bytes(after)
    assert p.a_limit == 2 and p.temp == -5 and pp.check_ok(after)
    assert chip.answer(b"\xa7\x00\x00\x00\x00\x00\x00\x00") is None       # bad XOR: no answer


def test_field_writes_touch_only_their_pages():
    old = pp.Passport("ZUML-VIRT-0001", "ZUML", 3, 0, 0, 8, 4)
    new = old.with_field("type", "LiPo")
    assert new.type == 4
    writes = pp.page_writes(old.to_bytes(), new.to_bytes())
    assert [w[2] for w in writes] == [0x16 // 4]
    assert old.with_field("serial", "ABC").serial == "ABC"
    for field, value in (("serial", "x" * 17), ("vendor", "ÄBC"), ("a_limit", "300"), ("temp", "3"),
                         ("type", "Bogus"), ("err", "-1")):
        with pytest.raises(pp.PassportError):
            old.with_field(field, value)


NIMH = pp.Passport("S", "V", 3, 0, 0, 8, 4)
START = StartParams("charge", 1, 2000, 2.0, None, 4, False)


def test_matching_battery_has_no_conflicts():
    assert pp.conflicts(NIMH, compiled("NiMh-dV"), START) == []


def test_chemistry_mismatch_and_undef():
    lipo = pp.Passport("S", "V", 4, 0, 0, 20, 10)
    assert pp.conflicts(lipo, compiled("NiMh-dV"), START) == ["the macro is for NiMh; the battery is LiPo"]
    undef = compile_source("MACRO U\nCHARGE_SECTION\nFAZE\nCONSTANT_I=1A\nIF(V>8V) STOP_FAZE\nEND_FAZE\n"
                           "END_SECTION\nEND_MACRO\n").record
    assert "no battery type" in pp.conflicts(NIMH, undef, START)[0]
    assert pp.conflicts(pp.Passport("S", "V", 0, 0, 0, 8, 4), undef, START) == []


def test_current_and_voltage_limits_name_value_and_limit():
    found = pp.conflicts(NIMH, compiled("NiMh-dV"), StartParams("charge", 1, 2000, 5.0, None, 6, False))
    assert "the macro charges at 5.00 A" in found[0] and found[0].endswith("the battery allows 4 A")
    assert "10.80 V" in found[1] and found[1].endswith("the battery allows 8 V")


def test_cv_alone_counts_its_current_limit_and_limits_of_zero_are_unset():
    lipo_rec = compiled("LiPo")
    lipo = pp.Passport("S", "V", 4, 0, 0, 13, 2)
    start = StartParams("charge", 1, 2000, None, None, 3, True)
    found = pp.conflicts(lipo, lipo_rec, start, charger_max_a=5.0)
    assert any("up to 5.00 A" in f and "charger's limit" in f for f in found)
    assert pp.conflicts(pp.Passport("S", "V", 4, 0, 0, 0, 0), lipo_rec, start, charger_max_a=5.0) == []
