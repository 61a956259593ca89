"""Every error kind, with its line, column and code."""
import pytest

from helpers import bare_seed
from zuml_studio.lang.compiler import compile_source

LIPO = bare_seed("LiPo")


def not_lint(diagnostics):
    """The language's own diagnostics; the safety lint (W3xx/E3xx) has its own tests."""
    return [d for d in diagnostics if not d.code[1:].startswith("3")]


def only(text):
    found = not_lint(compile_source(text).diagnostics)
    assert len(found) == 1, found
    return found[0]


CASES = [
    # name, edit, (line, column, code)
    ("missing unit", ("CONSTANT_I=1C", "CONSTANT_I=1"), (5, 16, "E201")),
    ("wrong unit", ("CONSTANT_I=1C", "CONSTANT_I=1V"), (5, 16, "E202")),
    ("not a value", ("CONSTANT_I=1C", "CONSTANT_I=LOTS"), (5, 16, "E203")),
    ("out of range", ("CONSTANT_I=1C", "CONSTANT_I=400A"), (5, 16, "E204")),
    ("unknown command", ("CONSTANT_I=1C", "CONSTANT_X=1C"), (5, 5, "E110")),
    ("assign written as call", ("CONSTANT_I=1C", "CONSTANT_I(1C)"), (5, 5, "E111")),
    ("argument count", ("MUSIC(STOP)", "MUSIC(STOP, 2)"), (19, 3, "E112")),
    ("unknown variable", ("IF(V<2.8S)", "IF(Q<2.8S)"), (6, 8, "E120")),
    ("comparison not allowed", ("IF(V<2.8S) STOP_FAZE()", "IF(T<40) STOP_FAZE()"), (6, 9, "E121")),
    ("missing outcome", ("IF(V<2.8S) STOP_FAZE()", "IF(V<2.8S)"), (6, 5, "E122")),
    ("wrong outcome", ("IF(V<2.8S) STOP_FAZE()", "IF(V<2.8S) STOP_MACRO"), (6, 16, "E123")),
    ("unclosed phase", ("    END_FAZE\n  END_SECTION\n  CHARGE", "  END_SECTION\n  CHARGE"), (4, 5, "E130")),
    ("duplicate section", ("  MUSIC(STOP)", "  CHARGE_SECTION\n  END_SECTION\n  MUSIC(STOP)"), (19, 3, "E131")),
    ("action between sections", ("  CHARGE_SECTION", "  CONSTANT_I=1C\n  CHARGE_SECTION"), (9, 3, "E150")),
    ("END_SECTION without section", ("  MUSIC(STOP)", "  END_SECTION"), (19, 3, "E134")),
    ("phase outside section", ("  AKK_TYPE=LiPo", "  AKK_TYPE=LiPo FAZE CONSTANT_I=1A END_FAZE"), (2, 17, "E135")),
    ("END_FAZE without FAZE", ("  MUSIC(STOP)", "  END_FAZE"), (19, 3, "E136")),
    ("END_CYCLE without CYCLE", ("  MUSIC(STOP)", "  END_CYCLE"), (19, 3, "E137")),
    ("text after END_MACRO", ("END_MACRO", "END_MACRO\nMUSIC(1)"), (21, 1, "E138")),
    ("missing END_MACRO", ("END_MACRO", ""), (21, 1, "E139")),
    ("name too long", ("MACRO LiPo", "MACRO LiPo-with-a-long-name"), (1, 7, "E141")),
    ("name characters", ("MACRO LiPo", "MACRO Li*Po"), (1, 7, "E142")),
    ("placement", ("  AKK_TYPE=LiPo", "  AKK_TYPE=LiPo\n  CONSTANT_I=1C"), (3, 3, "E150")),
    ("declared twice", ("  AKK_TYPE=LiPo", "  AKK_TYPE=LiPo\n  AKK_TYPE=LiFe"), (3, 3, "E151")),
    ("nested cycle", ("  CHARGE_SECTION\n", "  CHARGE_SECTION\n CYCLE(2)\n CYCLE(3)\n FAZE CONSTANT_I=1A IF(tf>1s) STOP_FAZE END_FAZE\n END_CYCLE\n END_CYCLE\n"), (11, 2, "E152")),
    ("two actions", ("    CONSTANT_I=1C\n", "    CONSTANT_I=1C\n    TRICKLE(0.1C,2S,3S)\n"), (6, 5, "E154")),
    ("no action", ("    CONSTANT_I=1C\n", ""), (4, 5, "E155")),
    ("trickle limits reversed", ("    CONSTANT_I=1C\n", "    TRICKLE(0.1C,3S,2S)\n"), (5, 5, "E157")),
    ("syntax", ("CONSTANT_I=1C", "CONSTANT_I=(1C"), (5, 16, "E100")),
    ("no header", ("MACRO LiPo", ""), (2, 3, "E101")),
    ("bad character", ("AKK_TYPE=LiPo", "AKK_TYPE=LiPo #"), (2, 17, "E102")),
    ("text ends early", ("  MUSIC(STOP)\nEND_MACRO\n", "  MUSIC(STOP"), (19, 13, "E103")),
    ("outcome alone", ("  MUSIC(STOP)", "  STOP_FAZE"), (19, 3, "E104")),
    ("MACRO twice", ("  MUSIC(STOP)", "  MACRO"), (19, 3, "E106")),
]


@pytest.mark.parametrize("name,edit,where", CASES, ids=[c[0] for c in CASES])
def test_error_is_reported_where_it_is(name, edit, where):
    old, new = edit
    assert old in LIPO
    d = only(LIPO.replace(old, new, 1))
    assert (d.line, d.column, d.code) == where
    assert d.is_error
    assert d.message


def test_missing_unit_message_speaks_to_a_charger_user():
    d = only(LIPO.replace("CONSTANT_I=1C", "CONSTANT_I=2"))
    assert d.message == "CONSTANT_I needs a unit: 2A or 0.5C"
    assert "2A or 2C" in d.hint


def test_rounding_that_changes_a_value_is_a_warning_and_still_compiles():
    result = compile_source(LIPO.replace("CONSTANT_I=1C", "CONSTANT_I=1.005C"))
    (d,) = not_lint(result.diagnostics)
    assert (d.line, d.column, d.code, d.is_error) == (5, 16, "W205", False)
    assert result.ok
    assert result.encoded.instructions[3].raws == (0x8000 | 101,)   # half away from zero


def test_record_too_large_points_where_it_stops_fitting():
    phase = "    FAZE CHARGE_EX(1,1A,1,1A) IF(tf>1) STOP_FAZE END_FAZE\n"
    text = LIPO.replace("    FAZE\n    CONSTANT_V", phase * 30 + "    FAZE\n    CONSTANT_V")
    d = only(text)
    assert d.code == "E160" and d.line == 28


def test_one_syntax_error_does_not_cascade():
    broken = LIPO.replace("CONSTANT_I=1C", "CONSTANT_I=(1C").replace("IF(V>4.1S)", "IF(V>>4.1S")
    assert len(compile_source(broken).diagnostics) == 1


def test_case_sensitive_condition_variables():
    d = only(LIPO.replace("  AKK_TYPE=LiPo", "  AKK_TYPE=LiPo\n  IF(TC>70) PAUSE_MACRO"))
    assert d.code == "E120" and "Tc" in d.hint
    ok = compile_source(LIPO.replace("  AKK_TYPE=LiPo", "  AKK_TYPE=LiPo\n  IF(Tc>70) PAUSE_MACRO"))
    assert ok.ok
    lower_v = compile_source(LIPO.replace("IF(V<2.8S)", "if(v<2.8s)"))
    assert lower_v.record == compile_source(LIPO).record


def test_time_suffixes():
    for text, tenths in (("120", 120), ("12s", 120), ("2m", 1200), ("30min", 18000), ("2h", 72000), ("1.5h", 54000)):
        result = compile_source(LIPO.replace("IF(I<0.1A) STOP_FAZE()", f"IF(tf>{text}) STOP_FAZE"))
        assert result.ok, result.diagnostics
        cond = result.macro.charge.items[1].statements[1]
        assert cond.args[0].raw == tenths


def test_capacity_input_auto_and_limits():
    for value, raw in (("INPUT", 0), ("AUTO", 0xFFFF), ("4200", 4200), ("2.2Ah", 2200)):
        result = compile_source(LIPO.replace("AKK_TYPE=LiPo", f"AKK_TYPE=LiPo CAPACITY={value}"))
        assert result.ok, result.diagnostics
        assert result.macro.intro[1].args[0].raw == raw
    for bad in ("1", "65535", "0"):
        d = only(LIPO.replace("AKK_TYPE=LiPo", f"AKK_TYPE=LiPo CAPACITY={bad}"))
        assert d.code == "E204"


def test_relative_current_cannot_collide_with_input():
    d = only(LIPO.replace("CONSTANT_I=1C", "CONSTANT_I=327.67C"))
    assert d.code == "E204"
    assert compile_source(LIPO.replace("CONSTANT_I=1C", "CONSTANT_I=327.67A")).ok
