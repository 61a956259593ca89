"""The one safety check on bytes bound for a charger (zuml_studio/safety.py)."""
from helpers import HOT_LIION, compiled, unsafe_record
from zuml_studio.device.passport import default_passport
from zuml_studio.lang.compiler import compile_source
from zuml_studio.lang.eeprom import pack
from zuml_studio.safety import image_problems, record_problems
from zuml_studio.sim.interpreter import StartParams


def test_the_compiler_withholds_unsafe_bytes_unless_overridden():
    assert not compile_source(HOT_LIION).ok
    forced = compile_source(HOT_LIION, unsafe_ok=True)
    assert forced.ok and [d.code for d in forced.errors] == ["E303", "E303"]


def test_a_record_above_the_chemistry_maximum_is_refused_from_its_bytes():
    problems = record_problems(unsafe_record())
    assert len(problems) == 2
    assert problems[0].startswith("E303 (byte ") and "4.96 V per cell" in problems[0] and "4.25 V" in problems[0]


def test_a_safe_record_has_no_problems():
    assert record_problems(compiled("LiIon-CCCV")) == []
    assert record_problems(compiled("NiMh"), default_passport("NiMh", 2000, 4)) == []


def test_the_cell_count_entered_at_start_resolves_absolute_volts():
    text = HOT_LIION.replace("  SERIES=1\n", "").replace("4.96S", "4.96V")
    record = unsafe_record(text)
    assert record_problems(record) == []                     # per cell unknown before start
    start = StartParams(series=1, capacity_mah=2000)
    assert any(p.startswith("E303") for p in record_problems(record, None, start))


def test_the_passport_limits_apply_when_writing_a_macro_for_that_battery():
    passport = default_passport("LiIon", 1000, 1)            # A_LIMIT 2 A
    record = compiled(HOT_LIION.replace("4.96S", "4.2S").replace("CONSTANT_I=1A", "CONSTANT_I=3A"))
    assert record_problems(record) == []
    assert any("charges at 3.00 A" in p for p in record_problems(record, passport))


def test_writing_a_macro_for_another_chemistry_is_no_passport_problem_but_starting_it_is():
    passport = default_passport("LiIon", 2000, 1)
    record = compiled("NiMh")
    assert record_problems(record, passport) == []
    assert any("the battery is LiIon" in p for p in record_problems(record, passport, StartParams()))


def test_image_problems_name_the_slot():
    image = pack([compiled("NiMh"), unsafe_record()], 1024)
    problems = image_problems(image)
    assert problems and all(p.startswith("slot 1 (Hot): E303") for p in problems)
