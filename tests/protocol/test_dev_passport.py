"""Battery passport, spec §4: the byte layout, the XOR checks, the chip, the lockout."""
import pytest

from zuml_studio.protocol import passport as pp
from zuml_studio.lang.compiler import compile_source
from zuml_studio.safety import conflicts
from zuml_studio.sim.interpreter import StartParams
from zuml_studio.virtual.passport_chip import PassportChip

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
    for req in (pp.read_all_request(), pp.read_page_request(3), pp.write_page_request(6, b"\x01\x02\x03\x04")):
        assert len(req) == 8 and req[0] == 0xA7
        x = 0
        for b in req[:7]:
            x ^= b
        assert req[7] == x
    assert pp.read_page_request(3)[1:3] == b"\x13\x03"
    assert pp.write_page_request(6, b"abcd")[1:7] == b"\x26\x06abcd"
    assert pp.parse_request(pp.write_page_request(2, b"abcd")) == ("write", 2, b"abcd")
    for bad in (b"\xa7" * 8, pp.read_page_request(1)[:7] + b"\x00", bytes(8)):
        with pytest.raises(pp.PassportError):
            pp.parse_request(bad)
    with pytest.raises(pp.PassportError, match="0..6"):
        pp.read_page_request(7)                                 # pages 0-6 (seed 003)


def _request(*body) -> bytes:
    x = 0
    for b in body:
        x ^= b
    return bytes(body) + bytes((x,))


@pytest.mark.parametrize("request_, code", [
    (b"", pp.AnswerError.BAD_LENGTH), (b"\xa7\x00\x00", pp.AnswerError.BAD_LENGTH),
    (bytes(9), pp.AnswerError.BAD_LENGTH), (b"\x00" * 8, pp.AnswerError.BAD_MAGIC),
    (b"\xa7\x00\x00\x00\x00\x00\x00\x00", pp.AnswerError.BAD_XOR),
    (_request(0xA7, 0x30, 0, 0, 0, 0, 0), pp.AnswerError.BAD_COMMAND),
    (_request(0xA7, 0x17, 7, 0, 0, 0, 0), pp.AnswerError.BAD_PAGE),
    (_request(0xA7, 0x12, 3, 0, 0, 0, 0), pp.AnswerError.BAD_PAGE),
    (_request(0xA7, 0x25, 5, 0, 0, 9, 0), pp.AnswerError.READ_ONLY)])      # TYPE (0x16) on page 5
def test_every_request_even_a_malformed_one_gets_32_bytes_with_an_error_code(request_, code):
    chip = PassportChip(pp.Passport("SER", "ZUML", 3, 0, 0, 8, 4))
    before = chip.image
    answer = chip.answer(request_)
    assert len(answer) == 32 and answer[0] == 0xA7 and answer[1] == pp.ERROR_MARK and answer[2] == code
    assert pp.check_word(answer) == int.from_bytes(answer[0x1E:], "little")
    assert pp.answer_error(answer).endswith(f"(passport error {int(code)})")
    assert chip.image == before and chip.writes == 0
    assert pp.answer_error(before) is None


def test_chip_keeps_temp_and_check_and_lets_a_production_charger_write_only_err_and_crit():
    temp = [31.6]
    chip = PassportChip(pp.Passport("SER", "ZUML", 3, 0, 0, 8, 4), lambda: temp[0])
    answer = chip.answer(pp.read_all_request())
    assert answer[0x1D] == 32 and pp.check_ok(answer)
    temp[0] = -5.2
    assert pp.Passport.from_bytes(chip.answer(pp.read_page_request(6))).temp == -5
    # page 6 = ERR high byte, CRIT, V_LIMIT: CRIT may change, V_LIMIT may not
    page = bytearray(pp.page_of(answer, 6))
    page[1] = 2
    after = chip.answer(pp.write_page_request(6, bytes(page)))
    p = pp.Passport.from_bytes(after)
    assert p.crit == 2 and p.v_limit == 8 and p.temp == -5 and pp.check_ok(after)
    page[3] = 20
    assert pp.answer_error(chip.answer(pp.write_page_request(6, bytes(page)))).startswith("the write touches "
                                                                                          "read-only fields")
    assert chip.passport.v_limit == 8 and chip.passport.crit == 2


def test_a_factory_chip_takes_type_serial_vendor_and_v_limit():
    old = pp.Passport("SER", "ZUML", 3, 0, 0, 8, 4)
    chip = PassportChip(old, factory=True)
    new = pp.Passport("NEW-1", "ROGA", 4, 0, 0, 13, 4)
    for req in pp.page_writes(old.to_bytes(), new.to_bytes()):
        assert pp.answer_error(chip.answer(req)) is None
    assert chip.passport == new


def test_fitness_warning_and_crit_lockout():
    assert pp.fitness_warnings(pp.Passport(err=2)) == ["the battery reports 2 error(s) (ERR=2)"]
    assert pp.fitness_warnings(pp.Passport()) == []


def test_field_writes_touch_only_their_pages():
    old = pp.Passport("ZUML-VIRT-0001", "ZUML", 3, 0, 0, 8, 4)
    new = old.with_field("type", "LiPo")
    assert new.type == 4
    writes = pp.page_writes(old.to_bytes(), new.to_bytes())
    assert [w[2] for w in writes] == [0x16 // 4]
    assert old.with_field("serial", "ABC").serial == "ABC"
    with pytest.raises(pp.PassportError, match="page 7"):
        pp.page_writes(old.to_bytes(), old.with_field("a_limit", 9).to_bytes())
    for field, value in (("serial", "x" * 17), ("vendor", "ÄBC"), ("a_limit", "300"), ("temp", "3"),
                         ("type", "Bogus"), ("err", "-1")):
        with pytest.raises(pp.PassportError):
            old.with_field(field, value)


NIMH = pp.Passport("S", "V", 3, 0, 0, 8, 4)
START = StartParams("charge", 1, 2000, 2.0, None, 4, False)


def test_matching_battery_has_no_conflicts():
    assert conflicts(NIMH, compiled("NiMh-dV"), START) == []


def test_chemistry_mismatch_and_undef():
    lipo = pp.Passport("S", "V", 4, 0, 0, 20, 10)
    assert conflicts(lipo, compiled("NiMh-dV"), START) == ["the macro is for NiMh; the battery is LiPo"]
    undef = compile_source("MACRO U\nCHARGE_SECTION\nFAZE\nCONSTANT_I=1A\nIF(V>8V) STOP_FAZE\nEND_FAZE\n"
                           "END_SECTION\nEND_MACRO\n").record
    assert "no battery type" in conflicts(NIMH, undef, START)[0]
    assert conflicts(pp.Passport("S", "V", 0, 0, 0, 8, 4), undef, START) == []


def test_current_and_voltage_limits_name_value_and_limit():
    found = conflicts(NIMH, compiled("NiMh-dV"), StartParams("charge", 1, 2000, 5.0, None, 6, False))
    assert "the macro charges at 5.00 A" in found[0] and found[0].endswith("the battery allows 4 A")
    assert "10.80 V" in found[1] and found[1].endswith("the battery allows 8 V")


def test_cv_alone_counts_its_current_limit_and_limits_of_zero_are_unset():
    lipo_rec = compiled("LiPo")
    lipo = pp.Passport("S", "V", 4, 0, 0, 13, 2)
    start = StartParams("charge", 1, 2000, None, None, 3, True)
    found = conflicts(lipo, lipo_rec, start, charger_max_a=5.0)
    assert any("up to 5.00 A" in f and "charger's limit" in f for f in found)
    assert conflicts(pp.Passport("S", "V", 4, 0, 0, 0, 0), lipo_rec, start, charger_max_a=5.0) == []
