"""Indentation and comment rules (plain functions, no Qt)."""
import subprocess
import sys

from hypothesis import given, strategies as st

from zuml_studio.ui.editor.indent import (CLOSERS, OPENERS, backspace_column, closer_indent, comment_edits,
                                          indent_after, opener_indent, structure_words, toggle_comment)


def test_the_rules_do_not_load_qt():
    code = ("import sys, zuml_studio.ui.editor.indent as m; "
            "print(m.indent_after('FAZE') == '  ', any(n.startswith('PySide6') for n in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.split() == ["True", "False"]


def test_openers_and_closers_come_from_the_opcode_table():
    assert OPENERS == {"MACRO", "DISCHARGE_SECTION", "CHARGE_SECTION", "CYCLE", "FAZE"}
    assert CLOSERS["END_SECTION"] == {"DISCHARGE_SECTION", "CHARGE_SECTION"}
    assert CLOSERS["END_FAZE"] == {"FAZE"} and CLOSERS["END_CYCLE"] == {"CYCLE"}
    assert CLOSERS["END_MACRO"] == {"MACRO"}


def test_structure_words_only_in_statement_position():
    assert structure_words("    FAZE") == ["FAZE"]
    assert structure_words("  LIGHT(FAZE)") == []                 # a value, not a phase
    assert structure_words("MACRO FAZE") == ["MACRO"]              # the name is a name
    assert structure_words("MACRO(x) FAZE") == ["MACRO", "FAZE"]
    assert structure_words("FAZE CONSTANT_I=1C END_FAZE") == ["FAZE", "END_FAZE"]
    assert structure_words("  // FAZE") == []
    assert structure_words("  cycle(3) // repeat") == ["CYCLE"]


def test_indent_after_an_opener_is_one_level_more():
    assert indent_after("MACRO LiPo") == "  "
    assert indent_after("  DISCHARGE_SECTION") == "    "
    assert indent_after("  CHARGE_SECTION // charge") == "    "
    assert indent_after("    CYCLE(3)") == "      "
    assert indent_after("    FAZE") == "      "
    assert indent_after("      CONSTANT_I=1C") == "      "
    assert indent_after("    END_FAZE") == "    "
    assert indent_after("    FAZE CONSTANT_I=1C IF(V>1S) STOP_FAZE END_FAZE") == "    "
    assert indent_after("  MUSIC(STOP) LIGHT(FAZE)") == "  "
    assert indent_after("") == ""


SOURCE = """MACRO LiPo
  DISCHARGE_SECTION
    FAZE
      CONSTANT_I=1C
      FAZE CONSTANT_I=1C END_FAZE
      END_FAZE
  END_SECTION
  CHARGE_SECTION
    CYCLE(2)
      FAZE
        LIGHT(FAZE)
        END_FAZE
        END_CYCLE
        END_SECTION
        END_MACRO""".split("\n")


def test_a_closer_takes_the_indentation_of_its_opener():
    assert closer_indent(SOURCE, 5) == "    "          # END_FAZE -> FAZE (skipping the one-line phase)
    assert closer_indent(SOURCE, 6) == "  "            # END_SECTION -> DISCHARGE_SECTION
    assert closer_indent(SOURCE, 11) == "      "       # END_FAZE -> FAZE (LIGHT(FAZE) is a value)
    assert closer_indent(SOURCE, 12) == "    "         # END_CYCLE -> CYCLE
    assert closer_indent(SOURCE, 13) == "  "           # END_SECTION -> CHARGE_SECTION
    assert closer_indent(SOURCE, 14) == ""             # END_MACRO -> MACRO
    assert closer_indent(SOURCE, 3) is None            # not a closer
    assert opener_indent("END_FAZE", []) is None       # nothing to close


def test_an_unclosed_block_of_another_kind_is_skipped():
    above = ["      CONSTANT_I=1C", "    FAZE", "  CHARGE_SECTION", "MACRO x"]   # END_FAZE is missing
    assert opener_indent("      END_SECTION", above) == "  "


def test_closer_case_and_comments():
    assert opener_indent("      end_faze // done", ["    faze"]) == "    "
    assert opener_indent("  // END_FAZE", ["    FAZE"]) is None


def test_backspace_goes_to_the_previous_multiple_of_two():
    assert [backspace_column(c) for c in range(7)] == [0, 0, 0, 2, 2, 4, 4]


def test_toggle_comment_round_trip_keeps_the_shape():
    lines = ["    FAZE", "", "      CONSTANT_I=1C", "    END_FAZE"]
    commented = toggle_comment(lines)
    assert commented == ["    // FAZE", "", "    //   CONSTANT_I=1C", "    // END_FAZE"]
    assert toggle_comment(commented) == lines


def test_toggle_comment_mixed_lines_comment_all():
    lines = ["  // FAZE", "  CONSTANT_I=1C"]
    assert toggle_comment(lines) == ["  // // FAZE", "  // CONSTANT_I=1C"]
    assert toggle_comment(["//x", "  //y"]) == ["x", "  y"]
    assert comment_edits(["", "   "]) == []


@given(st.lists(st.text(alphabet=" ABF_=()/1", max_size=12), min_size=1, max_size=6))
def test_toggle_twice_is_identity_unless_all_were_comments(lines):
    once = toggle_comment(lines)
    filled = [line for line in lines if line.strip()]
    if filled and not all(line.lstrip().startswith("//") for line in filled):
        assert toggle_comment(once) == lines
