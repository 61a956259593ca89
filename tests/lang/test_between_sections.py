"""Issue 11.2: commands between the sections (seed 000, byte layout item 8) are legal, stored where
they stand, decompiled back and run in order."""
import pytest

from zuml_studio.lang import opcodes as ops
from zuml_studio.lang.compiler import compile_source
from zuml_studio.lang.decoder import decode_record
from zuml_studio.lang.formatter import format_macro

TEXT = """MACRO Between
  AKK_TYPE=NiMh
  DISCHARGE_SECTION
    FAZE
      CONSTANT_I=0.5C
      IF(V<1S) STOP_FAZE
    END_FAZE
  END_SECTION
  MUSIC(ATTENTION)
  LIGHT(FAST)
  CHARGE_SECTION
    FAZE
      CONSTANT_I=0.5C
      IF(DELTA_PEAK>0.01S) STOP_FAZE
      IF(tf>3h) STOP_FAZE
    END_FAZE
  END_SECTION
  MUSIC(STOP)
END_MACRO
"""


def test_commands_between_sections_compile_where_they_stand():
    result = compile_source(TEXT)
    assert not result.errors, result.errors
    ins = result.encoded.instructions
    codes = [i.op.code for i in ins]
    end_discharge = codes.index(ops.END_SECTION.code)
    assert codes[end_discharge + 1:end_discharge + 4] == [100, 101, ops.CHARGE_SECTION.code]
    record = result.record
    assert record[2] == ins[end_discharge + 3].offset + 1          # the charge section still starts after them
    assert [s.op.keyword for s in result.macro.between] == ["MUSIC", "LIGHT"]


def test_they_decompile_back_to_the_same_text_and_bytes():
    record = compile_source(TEXT).record
    macro = decode_record(record).macro
    assert [s.raws() for s in macro.between] == [(4,), (101,)]
    assert format_macro(macro) == TEXT
    assert compile_source(format_macro(macro)).record == record


def test_with_an_absent_discharge_section_the_bytes_still_round_trip():
    text = "MACRO B\nMUSIC(1)\nCHARGE_SECTION\nFAZE CONSTANT_I=1A IF(tf>1h) STOP_FAZE END_FAZE\nEND_SECTION\nEND_MACRO\n"
    assert any(d.code == "E150" for d in compile_source(text).errors)     # in the introduction: not between
    empty_discharge = text.replace("MUSIC(1)\n", "DISCHARGE_SECTION\nEND_SECTION\nMUSIC(1)\n")
    record = compile_source(empty_discharge).record
    again = format_macro(decode_record(record).macro)
    assert compile_source(again).record == record


@pytest.mark.parametrize("task, expected", [
    ("train", ["section", "MUSIC(ATTENTION)", "LIGHT(FAST)", "section", "MUSIC(STOP)"]),
    ("discharge", ["section", "MUSIC(ATTENTION)", "LIGHT(FAST)", "MUSIC(STOP)"]),
    ("charge", ["section", "MUSIC(STOP)"])])
def test_they_run_after_the_discharge_section(task, expected):
    from zuml_studio.sim.interpreter import StartParams
    from zuml_studio.sim.simulate import BatterySetup, simulate
    record = compile_source(TEXT).record
    r = simulate(record, StartParams(task, 1, 2000, None, None, 4), BatterySetup(soc=None))
    seen = [e.detail or e.kind for e in r.interpreter.events if e.kind in ("section", "music", "light")]
    assert seen == expected
