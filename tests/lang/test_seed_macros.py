import pytest

from helpers import SEED_MACROS, seed_text
from zuml_studio.lang.compiler import compile_source
from zuml_studio.lang.decoder import decode_record
from zuml_studio.lang.formatter import format_macro

LIPO_BYTES = ("2b 09 16 27 4c 69 50 6f 00 15 04 03 08 3c 64 80 52 18 81 09 05 04 08 3c ff ff 53 9a 81 09 08 "
              "3d a4 81 54 0a 00 09 05 64 02 02 5b")


@pytest.mark.parametrize("name", SEED_MACROS)
def test_seed_macro_checks_without_errors_and_compiles(name):
    result = compile_source(seed_text(name))
    assert result.errors == []
    assert result.ok
    assert result.record[0] == len(result.record)
    assert result.macro.name == name


def test_lipo_compiles_to_the_hand_worked_bytes():
    assert compile_source(seed_text("LiPo")).record.hex(" ") == LIPO_BYTES


@pytest.mark.parametrize("name", SEED_MACROS)
def test_seed_macro_round_trips(name):
    record = compile_source(seed_text(name)).record
    text = format_macro(decode_record(record).macro)
    again = compile_source(text)
    assert again.errors == []
    assert again.record == record


def test_seed_spellings_are_read_as_the_spec_says():
    pb = compile_source(seed_text("Pb")).macro
    trickle_phase = pb.charge.items[1]
    condition = trickle_phase.statements[1]
    assert condition.op.code == 88 and condition.args[0].raw == 120     # IF(t>120): phase time, tenths
    nimh = compile_source(seed_text("NiMh")).macro
    dpeak = nimh.charge.items[0].statements[1]
    assert dpeak.op.code == 89 and dpeak.args[0].raw == 0x8000 | 20     # IF(DELTA_PEAK=0.2S)


def test_lower_case_keywords_and_paren_header_are_accepted():
    text = seed_text("LiPo").lower().replace("macro lipo", "MACRO(LiPo)").replace("if(v", "if(V")
    assert compile_source(text).record.hex(" ") == LIPO_BYTES


def test_charge_ex_with_four_and_five_arguments():
    base = "MACRO X\nCHARGE_SECTION\nFAZE\nCHARGE_EX(60, 0.5C, 3, 0.1C{})\nIF(tf>1h) STOP_FAZE\nEND_FAZE\nEND_SECTION\nEND_MACRO\n"
    four = compile_source(base.format(""))
    five = compile_source(base.format(", 2"))
    assert four.ok and five.ok
    ins4 = next(i for i in four.encoded.instructions if i.op.code == 62)
    ins5 = next(i for i in five.encoded.instructions if i.op.code == 62)
    assert ins4.raws == (60, 0x8000 | 50, 3, 0x8000 | 10, 0)
    assert ins5.raws[-1] == 2
    assert ins4.size == 8


def test_every_library_macro_checks_without_a_warning_or_says_on_its_line_why_the_warning_is_right():
    from helpers import MACROS
    from zuml_studio.lang.diagnostics import Severity
    for path in sorted(MACROS.glob("*.zuml")):
        lines = path.read_text().splitlines()
        for d in compile_source(path.read_text()).diagnostics:
            if d.severity is not Severity.NOTE:
                assert f"// {d.code} right" in lines[d.line - 1], (path.name, d.line, d.code, d.message)
