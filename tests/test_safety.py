"""The one safety check on bytes bound for a charger (zuml_studio/safety.py)."""
from helpers import HOT_LIION, compiled, unsafe_record
from zuml_studio.virtual.passport_chip import default_passport
from zuml_studio.lang.compiler import compile_source
from zuml_studio.lang.eeprom import pack
from zuml_studio.safety import judge, judge_image
from zuml_studio.sim.interpreter import StartParams


def test_the_compiler_withholds_unsafe_bytes_unless_overridden():
    assert not compile_source(HOT_LIION).ok
    forced = compile_source(HOT_LIION, unsafe_ok=True)
    assert forced.ok and [d.code for d in forced.errors] == ["E303", "E303"]


def test_a_record_above_the_chemistry_maximum_is_refused_from_its_bytes():
    problems = list(judge(unsafe_record()).errors)
    assert len(problems) == 2
    assert problems[0].startswith("E303 (byte ") and "4.96 V per cell" in problems[0] and "4.25 V" in problems[0]


def test_a_safe_record_has_no_problems():
    assert list(judge(compiled("LiIon-CCCV")).errors) == []
    assert judge(compiled("NiMh"), default_passport("NiMh", 2000, 4)).safe


def test_the_cell_count_entered_at_start_resolves_absolute_volts():
    text = HOT_LIION.replace("  SERIES=1\n", "").replace("4.96S", "4.96V")
    record = unsafe_record(text)
    assert list(judge(record).errors) == []                     # per cell unknown before start
    start = StartParams(series=1, capacity_mah=2000)
    assert any(p.startswith("E303") for p in list(judge(record, None, start).errors))


def test_the_passport_limits_apply_when_writing_a_macro_for_that_battery():
    passport = default_passport("LiIon", 1000, 1)            # A_LIMIT 2 A
    record = compiled(HOT_LIION.replace("4.96S", "4.2S").replace("CONSTANT_I=1A", "CONSTANT_I=3A"))
    assert list(judge(record).errors) == []
    assert any("charges at 3.00 A" in p for p in list(judge(record, passport).errors))


def test_writing_a_macro_for_another_chemistry_is_no_passport_problem_but_starting_it_is():
    passport = default_passport("LiIon", 2000, 1)
    record = compiled("NiMh")
    assert list(judge(record, passport).errors) == []
    assert any("the battery is LiIon" in p for p in list(judge(record, passport, StartParams()).errors))


def test_a_fast_nickel_charge_is_asked_about_and_above_2c_without_the_sensor_refused():
    """W320 for a 0.5C-or-faster nickel charge with no IF(T>x); E320 at a start above 2C with the sensor
    off (a temperature end cannot work), whether the rate is typed in the macro or entered at start."""
    fast = compiled(NIMH_FAST)
    assert judge(fast).safe and any(w.startswith("W320") for w in judge(fast).warnings)
    assert judge(fast, start=StartParams(capacity_mah=1000, series=4)).safe
    refused = judge(fast, start=StartParams(capacity_mah=1000, series=4, sensor=False))
    assert refused.codes() == ["E320"] and "sensor off" in refused.errors[0]
    with_t = compiled(NIMH_FAST.replace("STOP_FAZE\n", "STOP_FAZE\n    IF(T>40) STOP_FAZE\n", 1))
    assert not any(w.startswith("W320") for w in judge(with_t).warnings)
    assert judge(with_t, start=StartParams(capacity_mah=1000, series=4, sensor=False)).codes() == ["E320"]
    entered = compiled(NIMH_FAST.replace("CONSTANT_I=5C", "CONSTANT_I=INPUT"))
    assert judge(entered, start=StartParams(capacity_mah=1000, current_a=2, series=4, sensor=False)).safe
    assert judge(entered, start=StartParams(capacity_mah=1000, current_a=2.5, series=4, sensor=False)).codes() == [
        "E320"]


NIMH_FAST = """MACRO Fast
  AKK_TYPE=NiMh
  CHARGE_SECTION
    FAZE
    CONSTANT_I=5C
    IF(DELTA_PEAK>0.01S) STOP_FAZE
    END_FAZE
  END_SECTION
END_MACRO
"""


def test_image_problems_name_the_slot():
    image = pack([compiled("NiMh"), unsafe_record()], 1024)
    problems = judge_image(image).errors
    assert problems and all(p.startswith("slot 1 (Hot): E303") for p in problems)


TEMPLATE_LIPO = """MACRO Tpl-LiPo
  AKK_TYPE=LiPo
  START_SHABLON=5
  CHARGE_SECTION
    FAZE
    CONSTANT_I=1A
    IF(V>12.6V) STOP_FAZE()
    END_FAZE
  END_SECTION
END_MACRO
"""


def test_a_macro_naming_a_start_template_is_judged_with_the_templates_values():
    from zuml_studio.domain.start_templates import StartTemplate
    record = compiled(TEMPLATE_LIPO)
    typed = StartParams(series=3, capacity_mah=2000, current_a=1.0)
    assert judge(record, start=typed, templates={5: StartTemplate(series=3)}).safe
    two_cells = {5: StartTemplate(series=2, capacity_mah=2000, current_a=1.0)}
    for verdict in (judge(record, start=typed, templates=two_cells), judge(record, templates=two_cells)):
        assert verdict.codes() == ["E303"]
        assert "6.30 V per cell" in verdict.errors[0] and "[start template 5: " in verdict.errors[0]
    missing = judge(record, start=typed, templates={})
    assert not missing.safe and "start template 5" in missing.errors[0]
    assert judge(record, templates={}).safe          # only writing: storing the template is judged then


def test_a_macro_the_check_cannot_judge_is_refused_and_warnings_are_kept_apart():
    no_type = compiled("MACRO NoType\n  SERIES=3\n  CHARGE_SECTION\n    FAZE\n    CONSTANT_I=1A\n"
                       "    IF(V>4.5S) STOP_FAZE()\n    END_FAZE\n  END_SECTION\nEND_MACRO\n")
    assert judge(no_type).codes() == ["W301"]
    lipo = judge(compiled("LiPo"))
    assert lipo.safe and lipo.warnings and all(w.startswith("W3") for w in lipo.warnings)


def test_notes_are_never_asked_before_a_flash():
    """A generic standard macro (values entered at start: W310/W306 notes) is neither refused nor asked."""
    from zuml_studio import data
    from zuml_studio.lang.compiler import compile_source
    from zuml_studio.safety import judge
    record = compile_source((data.standard_macros_dir() / "NiMh-dV.zuml").read_text(encoding="utf-8")).record
    verdict = judge(record)
    assert not verdict.errors and not verdict.warnings


# -- raw bytes typed by hand (the serial monitor) ---------------------------------------------------
from zuml_studio.protocol.frames import encode_frame  # noqa: E402 - this section's own imports
from zuml_studio.protocol.messages import encode_request  # noqa: E402 - this section's own imports
from zuml_studio.safety import RAW_ALLOWED, RawSendGuard  # noqa: E402 - this section's own imports

CHANGING_REQUESTS = {
    "BEGIN_WRITE": {"nonce": 0x1234ABCD},
    "WRITE_STAGE": {"token": 7, "offset": 0, "data": b"\x01\x02\x03"},
    "COMMIT": {"token": 7, "crc": 0x1234},
    "START": {"slot": 0, "task": 0, "repetitions": 1, "capacity_mah": 2200, "current_ma": 2000,
              "voltage_mv": 0, "series": 3, "sensor": 0},
    "SET_TEMPLATE": {"number": 1, "task": 0, "repetitions": 1, "capacity_mah": 2200, "current_ma": 9000,
                     "voltage_mv": 4500, "series": 3},
    "CAL_WRITE": {"block": bytes(8)},
    "CAL_OUTPUT": {"mode": 1, "current_ma": 5000},
    "PASSPORT": {"request": bytes(8)},
}
GARBAGE = b"AT\r\n\xa5\x05\x10\x01\xa5\xa5\x00\xff"     # false starts: sync bytes, a LEN, a START type


def _frame(name: str, seq: int = 3) -> bytes:
    from zuml_studio.protocol.messages import BY_NAME
    return encode_frame(BY_NAME[name].code, seq, encode_request(name, **CHANGING_REQUESTS[name]))


def test_every_request_that_changes_the_charger_is_refused_wherever_it_is_split():
    for name in CHANGING_REQUESTS:
        frame = _frame(name)
        for before in (b"", GARBAGE):
            whole = before + frame
            assert not RawSendGuard().judge(whole).safe, name
            for cut in range(1, len(whole)):
                guard = RawSendGuard()
                assert guard.judge(whole[:cut]).safe, (name, cut)
                guard.sent(whole[:cut])
                verdict = guard.judge(whole[cut:])
                assert not verdict.safe and name in verdict.errors[0] and verdict.codes() == ["RAW"], (name, cut)


def test_a_request_sent_a_byte_at_a_time_is_refused_at_its_last_byte():
    for name in CHANGING_REQUESTS:
        guard = RawSendGuard()
        whole = GARBAGE + _frame(name)
        for byte in whole[:-1]:
            assert guard.judge(bytes([byte])).safe
            guard.sent(bytes([byte]))
        assert not guard.judge(whole[-1:]).safe, name


def test_a_refused_send_is_not_remembered_and_reading_requests_pass():
    from zuml_studio.protocol.messages import BY_NAME
    guard = RawSendGuard()
    frame = _frame("COMMIT")
    guard.sent(frame[:4])
    assert not guard.judge(frame[4:]).safe
    assert guard.judge(b"hello\n").safe                    # the refused bytes never reached the charger
    for code in RAW_ALLOWED:
        payload = encode_request(BY_NAME["READ_EEPROM"].name, offset=0, length=16) if code == BY_NAME[
            "READ_EEPROM"].code else b""
        assert RawSendGuard().judge(encode_frame(code, 1, payload)).safe


def test_a_request_whose_start_left_the_guards_memory_long_ago_is_no_frame():
    guard = RawSendGuard()
    frame = _frame("START")
    guard.sent(frame[:5])
    guard.sent(b"x" * 300)                                 # longer than any frame: that start is history
    assert guard.judge(frame[5:]).safe
