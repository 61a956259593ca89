"""Hostile text: huge numbers, huge files, huge lines (issue 12, points 2 and 3). Times are
measured by benchmarks/bench_hostile_text.py, not here."""
import pytest

from zuml_studio.lang import parser
from zuml_studio.lang.compiler import compile_source

TEMPLATE = """MACRO Big
  AKK_TYPE=NiMh
  {intro}
  CHARGE_SECTION
    CYCLE({cycles})
    FAZE
      CONSTANT_I={current}
      IF(tf>{time}) STOP_FAZE
      IF(V>{volts}) STOP_FAZE
      IF(T>{temp}) STOP_FAZE
    END_FAZE
    END_CYCLE
  END_SECTION
END_MACRO
"""
SAFE = dict(intro="CAPACITY=2000", cycles="2", current="1A", time="10min", volts="1.5S", temp="45")
HUGE = ["9" * 27, "9" * 29, "9" * 60 + ".5", "0." + "0" * 40 + "1", "9" * 5000]


@pytest.mark.parametrize("field", sorted(SAFE))
@pytest.mark.parametrize("number", HUGE, ids=lambda n: f"{len(n)}chars")
def test_every_numeric_literal_gets_a_range_diagnostic(field, number):
    units = {"current": "A", "time": "s", "volts": "S", "intro": ""}
    value = number + units.get(field, "")
    values = dict(SAFE, **{field: ("CAPACITY=" + number) if field == "intro" else value})
    result = compile_source(TEMPLATE.format(**values))
    assert not result.ok or any(d.code == "W205" for d in result.diagnostics), result.diagnostics
    assert all(d.code.startswith(("E", "W")) and d.message for d in result.diagnostics)


def test_a_29_digit_capacity_is_out_of_range():
    result = compile_source(TEMPLATE.format(**dict(SAFE, intro="CAPACITY=" + "9" * 29)))
    assert [d.code for d in result.errors] == ["E204"]
    assert "out of range" in result.errors[0].message


def test_text_past_one_megabyte_is_refused_at_once_with_one_line():
    text = "MACRO Big\n" + "// x\n" * (parser.MAX_TEXT_CHARS // 5)
    result = compile_source(text)
    assert [d.code for d in result.diagnostics] == ["E161"]
    assert "\n" not in result.diagnostics[0].message


def test_thousands_of_statements_stop_at_the_first_that_cannot_fit():
    body = "\n".join(["    FAZE", "      CONSTANT_I=1A", "      IF(tf>1min) STOP_FAZE", "    END_FAZE"] * 2500)
    result = compile_source(f"MACRO Big\n  CHARGE_SECTION\n{body}\n  END_SECTION\nEND_MACRO\n")
    assert [d.code for d in result.diagnostics] == ["E160"]
    assert result.diagnostics[0].line == 256            # the 255th statement (line 1 is the header)


def test_comment_and_blank_lines_are_not_parsed(monkeypatch):
    seen = []
    real = parser._parse_line
    monkeypatch.setattr(parser, "_parse_line", lambda text, first: seen.append(text) or real(text, first))
    compile_source("// a\n\nMACRO A\n   // b\n  CHARGE_SECTION\n\n  END_SECTION\nEND_MACRO\n")
    assert seen == ["MACRO A", "  CHARGE_SECTION", "  END_SECTION", "END_MACRO"]


def test_the_parse_cache_is_bounded_by_the_text_it_holds(monkeypatch):
    monkeypatch.setattr(parser, "_CACHE", {})
    monkeypatch.setattr(parser, "_cache_chars", 0)
    monkeypatch.setattr(parser, "_CACHE_MAX_CHARS", 5_000)
    for i in range(300):                                 # 300 keystrokes on a long comment line
        parser._parse_line(f"  CONSTANT_I=1A // {'x' * 100} {i}", False)
    held = sum(len(text) for text, _ in parser._CACHE)
    assert held == parser._cache_chars <= 5_000
    parser._parse_line("// " + "y" * (parser._CACHE_LINE_MAX + 1), False)
    assert all(len(text) <= parser._CACHE_LINE_MAX for text, _ in parser._CACHE)


@pytest.mark.parametrize("field", ["intro", "current", "volts"])
def test_a_number_longer_than_any_operand_is_refused_before_it_is_converted(field, monkeypatch):
    # issue 27: CAPACITY= with 990 000 digits took minutes in round_half_away (int of a huge Decimal)
    from zuml_studio.lang import operands

    def short_only(text):
        assert len(text) < 100, "a number this long was converted"
        return split_number(text)
    split_number = operands.split_number
    monkeypatch.setattr(operands, "split_number", short_only)
    monkeypatch.setattr(operands, "_PARSED", {})
    number = "9" * 990_000
    value = {"intro": "CAPACITY=" + number, "current": number + "A", "volts": number + "S"}[field]
    result = compile_source(TEMPLATE.format(**dict(SAFE, **{field: value})))
    assert [d.code for d in result.errors] == ["E204"]
    assert result.errors[0].message == ("a number of 990000 characters (999999999999…) is longer than any value "
                                        "a macro stores")
