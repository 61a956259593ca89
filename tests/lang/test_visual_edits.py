"""The visual editor's edits as pure text -> text functions (no Qt): each result compiles,
does what it says to the AST and the bytes, and keeps the comments it does not touch."""
import pytest

from helpers import MACROS, SEED_MACROS, bare_seed, seed_text
from zuml_studio.lang import visual_edits as ve
from zuml_studio.lang import opcodes as ops
from zuml_studio.lang.ast import Cycle, Phase
from zuml_studio.lang.compiler import compile_source

IF_TF = ops.BY_CODE[88]
IF_T = ops.BY_CODE[81]
IF_TM = ops.BY_CODE[87]

COMMENTED = """// LiPo with comments everywhere
MACRO LiPo
  AKK_TYPE=LiPo // the chemistry
  DISCHARGE_SECTION
    FAZE
      CONSTANT_I=1C // one C
      IF(V<3S) STOP_FAZE()
    END_FAZE
  END_SECTION
  CHARGE_SECTION
    // bulk
    FAZE
      CONSTANT_I=INPUT
      IF(V>4.1S) STOP_FAZE
    END_FAZE
    // absorption: hold the voltage
    FAZE // CV
      CONSTANT_V=4.2S
      IF(I<0.1A) STOP_FAZE
    END_FAZE // end of CV
  END_SECTION
  MUSIC(STOP) // done
END_MACRO
"""


def compiled(text):
    result = compile_source(text)
    assert result.ok, result.diagnostics
    return result


def macro(text):
    return compiled(text).macro


def comments_kept(old, new, except_=()):
    assert [c for c in ve.dropped_comments(old, new) if c not in except_] == []


# -- values -----------------------------------------------------------------------------------

def test_set_value_rewrites_only_the_statement_and_keeps_its_comment():
    m = macro(COMMENTED)
    st = m.discharge.items[0].statements[0]
    new = ve.set_value(COMMENTED, st, 0, "0.5C")
    assert "      CONSTANT_I=0.5C // one C\n" in new
    assert new.replace("CONSTANT_I=0.5C", "CONSTANT_I=1C") == COMMENTED
    comments_kept(COMMENTED, new)
    expected = compiled(COMMENTED.replace("CONSTANT_I=1C", "CONSTANT_I=0.5C")).record
    assert compiled(new).record == expected != compiled(COMMENTED).record


def test_set_value_writes_the_canonical_statement():
    text = bare_seed("Pb")
    m = macro(text)
    cond = m.charge.items[1].statements[1]           # IF(t>120) STOP_FAZE()
    new = ve.set_value(text, cond, 0, "30min")
    assert "IF(tf>30min) STOP_FAZE\n" in new
    (phase_cond,) = [s for s in macro(new).charge.items[1].statements if s.op is IF_TF]
    assert phase_cond.args[0].raw == 30 * 600


def test_set_value_refuses_what_cannot_be_stored_and_notes_rounding():
    m = macro(COMMENTED)
    st = m.discharge.items[0].statements[0]
    with pytest.raises(ve.EditError, match="unit"):
        ve.set_value(COMMENTED, st, 0, "2")
    with pytest.raises(ve.EditError):
        ve.set_value(COMMENTED, st, 0, "lots")
    raw, note = ve.parse_value(st.op.operands[0], "0.333C")
    assert note and "0.33" in note and raw == 33 | 0x8000
    assert "CONSTANT_I=0.33C" in ve.set_value(COMMENTED, st, 0, "0.333C")


def test_set_action_value_only_takes_actions():
    m = macro(COMMENTED)
    with pytest.raises(ve.EditError):
        ve.set_action_value(COMMENTED, m.discharge.items[0].statements[1], 0, "3S")
    new = ve.set_action_value(COMMENTED, m.charge.items[1].statements[0], 0, "4.15S")
    assert macro(new).charge.items[1].statements[0].args[0].raw == 415 | 0x8000


def test_set_statement_replaces_exactly_the_span():
    m = macro(COMMENTED)
    new = ve.set_statement(COMMENTED, m.conclusion[0], "MUSIC(ATTENTION)")
    assert "  MUSIC(ATTENTION) // done\n" in new
    assert macro(new).conclusion[0].args[0].raw == 4


# -- conditions -------------------------------------------------------------------------------

def test_add_condition_is_a_new_line_after_the_last_statement_with_the_phase_indentation():
    m = macro(COMMENTED)
    new = ve.add_condition(COMMENTED, m.charge.items[0], IF_TF, "2h")
    assert "      IF(V>4.1S) STOP_FAZE\n      IF(tf>2h) STOP_FAZE\n    END_FAZE\n" in new
    comments_kept(COMMENTED, new)
    phase = macro(new).charge.items[0]
    assert [s.op for s in phase.statements][-1] is IF_TF and phase.statements[-1].args[0].raw == 72000
    record = compiled(new).record
    assert len(record) == len(compiled(COMMENTED).record) + IF_TF.size
    assert bytes([IF_TF.code]) + (72000).to_bytes(4, "little") in record


def test_add_condition_follows_the_files_own_indentation():
    text = bare_seed("LiPo")                       # phase contents at the FAZE's indentation
    m = macro(text)
    new = ve.add_condition(text, m.discharge.items[0], IF_T, "45")
    assert "    IF(V<2.8S) STOP_FAZE()\n    IF(T>45) STOP_FAZE\n    END_FAZE\n" in new


def test_add_condition_when_the_last_statement_shares_the_end_faze_line():
    text = "MACRO X\n  CHARGE_SECTION\n    FAZE CONSTANT_I=1A IF(V>4S) STOP_FAZE END_FAZE\n  END_SECTION\nEND_MACRO\n"
    new = ve.add_condition(text, macro(text).charge.items[0], IF_TF, "1h")
    assert [s.op for s in macro(new).charge.items[0].statements][-1] is IF_TF


def test_add_condition_refuses_a_macro_wide_condition():
    with pytest.raises(ve.EditError):
        ve.add_condition(COMMENTED, macro(COMMENTED).charge.items[0], IF_TM, "1h")


def test_remove_statement_alone_on_its_line_deletes_the_line():
    m = macro(COMMENTED)
    new = ve.remove_statement(COMMENTED, m.charge.items[1].statements[1])
    assert "IF(I<0.1A)" not in new
    assert new.count("\n") == COMMENTED.count("\n") - 1
    comments_kept(COMMENTED, new)
    assert [s.op for s in macro(new).charge.items[1].statements] == [ops.CONSTANT_V]


def test_remove_statement_sharing_a_line_keeps_the_others():
    text = "MACRO X\n  CHARGE_SECTION\n    FAZE\n      CONSTANT_I=1A IF(V>4S) STOP_FAZE IF(tf>1h) STOP_FAZE\n" \
           "    END_FAZE\n  END_SECTION\nEND_MACRO\n"
    m = macro(text)
    new = ve.remove_statement(text, m.charge.items[0].statements[1])
    assert "      CONSTANT_I=1A IF(tf>1h) STOP_FAZE\n" in new
    new = ve.remove_statement(text, m.charge.items[0].statements[2])
    assert "      CONSTANT_I=1A IF(V>4S) STOP_FAZE\n" in new


def test_removing_a_statement_with_a_comment_reports_the_comment():
    m = macro(COMMENTED)
    new = ve.remove_statement(COMMENTED, m.conclusion[0])
    assert ve.dropped_comments(COMMENTED, new) == ["// done"]
    assert compiled(new).record != compiled(COMMENTED).record


def test_missing_conditions_lists_the_phase_conditions_not_present():
    phase = macro(COMMENTED).charge.items[0]
    missing = ve.missing_conditions(phase)
    assert ops.BY_CODE[83] not in missing and IF_TF in missing and IF_TM not in missing
    assert all(ops.Place.PHASE in op.places and op.role is ops.Role.CONDITION for op in missing)


# -- actions ----------------------------------------------------------------------------------

def test_set_action_to_cc_cv_and_back():
    m = macro(COMMENTED)
    new = ve.set_action(COMMENTED, m.charge.items[0], "CC-CV", m)
    assert "      CONSTANT_I=INPUT\n      CONSTANT_V=4.2S\n" in new
    phase = macro(new).charge.items[0]
    assert ve.action_key(phase) == "CC-CV"
    back = ve.set_action(new, phase, "CONSTANT_I", macro(new))
    assert back == COMMENTED


def test_action_kinds_come_from_the_opcode_table():
    keys = [k.key for k in ve.action_kinds()]
    assert set(keys) == {op.keyword for op in ops.ACTIONS} | {"CC-CV"}


# -- moving phases ----------------------------------------------------------------------------

def test_move_phase_moves_whole_lines_with_the_comments_above():
    m = macro(COMMENTED)
    new = ve.move_phase(COMMENTED, m.charge, 1, 0)
    comments_kept(COMMENTED, new)
    assert new.index("// absorption") < new.index("FAZE // CV") < new.index("// bulk") < new.index("CONSTANT_I=INPUT")
    moved = macro(new)
    assert [ve.action_key(p) for p in moved.charge.items] == ["CONSTANT_V", "CONSTANT_I"]
    assert compiled(new).record != compiled(COMMENTED).record
    assert ve.move_phase(new, moved.charge, 0, 1) == COMMENTED


def test_move_phase_gives_the_bytes_of_the_reordered_text():
    text = seed_text("LiPo")
    m = macro(text)
    new = ve.move_phase(text, m.charge, 0, 1)
    lines = text.split("\n")
    reordered = "\n".join(lines[:9] + lines[13:17] + lines[9:13] + lines[17:])
    assert new == reordered
    assert compiled(new).record == compiled(reordered).record


def test_move_refuses_a_phase_that_shares_its_line_with_another():
    one_line = "MACRO X\n  CHARGE_SECTION\n    FAZE CONSTANT_I=1A END_FAZE\n    FAZE\n      CONSTANT_V=4S\n" \
               "    END_FAZE\n  END_SECTION\nEND_MACRO\n"
    moved = ve.move_phase(one_line, macro(one_line).charge, 0, 1)       # a phase on one line of its own moves
    assert moved.index("CONSTANT_V=4S") < moved.index("FAZE CONSTANT_I=1A END_FAZE")
    shared = "MACRO X\n  CHARGE_SECTION\n    FAZE\n      CONSTANT_I=1A\n    END_FAZE FAZE\n      CONSTANT_V=4S\n" \
             "    END_FAZE\n  END_SECTION\nEND_MACRO\n"
    with pytest.raises(ve.EditError, match="own lines"):
        ve.move_phase(shared, macro(shared).charge, 0, 1)


# -- cycles -----------------------------------------------------------------------------------

def test_wrap_in_cycle_and_unwrap_give_the_text_back():
    m = macro(COMMENTED)
    wrapped = ve.wrap_in_cycle(COMMENTED, m.charge.items[1], 3)
    comments_kept(COMMENTED, wrapped)
    assert "    CYCLE(3)\n      // absorption: hold the voltage\n      FAZE // CV\n        CONSTANT_V=4.2S\n" in wrapped
    assert "      END_FAZE // end of CV\n    END_CYCLE\n  END_SECTION\n" in wrapped
    wm = macro(wrapped)
    cycle = wm.charge.items[1]
    assert isinstance(cycle, Cycle) and cycle.count.raw == 3 and isinstance(cycle.items[0], Phase)
    record = compiled(wrapped).record
    assert bytes([ops.CYCLE.code, 3]) in record and bytes([ops.END_CYCLE.code]) in record
    assert ve.unwrap_cycle(wrapped, cycle) == COMMENTED


def test_unwrap_keeps_a_comment_on_the_cycle_lines():
    text = COMMENTED.replace("    FAZE // CV", "    CYCLE(2) // twice\n      FAZE // CV").replace(
        "    END_FAZE // end of CV", "      END_FAZE // end of CV\n    END_CYCLE")
    m = macro(text)
    new = ve.unwrap_cycle(text, m.charge.items[1])
    comments_kept(text, new)
    assert "    // twice\n    FAZE // CV\n" in new
    assert not any(isinstance(i, Cycle) for i in macro(new).charge.items)


def test_set_cycle_count_and_remove_from_cycle():
    m = macro(COMMENTED)
    wrapped = ve.wrap_in_cycle(COMMENTED, [m.charge.items[0], m.charge.items[1]], 2)
    cycle = macro(wrapped).charge.items[0]
    assert len(cycle.items) == 2
    counted = ve.set_cycle_count(wrapped, cycle, 5)
    assert macro(counted).charge.items[0].count.raw == 5
    out = ve.remove_from_cycle(wrapped, cycle, 1)
    comments_kept(wrapped, out)
    items = macro(out).charge.items
    assert isinstance(items[0], Cycle) and len(items[0].items) == 1 and isinstance(items[1], Phase)
    assert "    // absorption: hold the voltage\n    FAZE // CV\n      CONSTANT_V=4.2S\n" in out
    first_out = ve.remove_from_cycle(wrapped, cycle, 0)
    items = macro(first_out).charge.items
    assert isinstance(items[0], Phase) and isinstance(items[1], Cycle)


def test_wrapping_inside_a_cycle_is_refused_by_the_check():
    m = macro(COMMENTED)
    wrapped = ve.wrap_in_cycle(COMMENTED, m.charge.items[1], 2)
    inner = macro(wrapped).charge.items[1].items[0]
    twice = compile_source(ve.wrap_in_cycle(wrapped, inner, 2))
    assert not twice.ok and any(d.code == "E152" for d in twice.errors)


# -- phases, sections, introduction -------------------------------------------------------------

def test_delete_phase_takes_its_comment_lines_and_says_so():
    m = macro(COMMENTED)
    new = ve.delete_phase(COMMENTED, m.charge.items[1])
    assert ve.dropped_comments(COMMENTED, new) == ["// absorption: hold the voltage", "// CV", "// end of CV"]
    assert len(macro(new).charge.items) == 1


def test_add_phase_to_a_present_and_to_an_absent_section():
    text = seed_text("LiFe-CCCV")                   # no discharge section
    m = macro(text)
    more = ve.add_phase(text, m, "charge")
    assert len(macro(more).charge.items) == 2
    with_discharge = ve.add_phase(text, m, "discharge")
    dm = macro(with_discharge)
    assert dm.discharge.present and len(dm.discharge.items) == 1
    assert ve.action_key(dm.discharge.items[0]) == "CONSTANT_I"
    assert with_discharge.index("DISCHARGE_SECTION") < with_discharge.index("CHARGE_SECTION")
    comments_kept(text, with_discharge)


def test_set_declaration_rewrites_or_inserts_in_table_order():
    text = seed_text("LiPo")
    m = macro(text)
    new = ve.set_declaration(text, m, ops.CAPACITY, "2200")
    assert "  AKK_TYPE=LiPo\n  CAPACITY=2200\n  DISCHARGE_SECTION" in new
    new = ve.set_declaration(new, macro(new), ops.SERIES, "3")
    assert "  AKK_TYPE=LiPo\n  SERIES=3\n  CAPACITY=2200\n" in new
    new = ve.set_declaration(new, macro(new), ops.SERIES, "4")
    assert "SERIES=4" in new and "SERIES=3" not in new
    new = ve.set_declaration(new, macro(new), IF_TM, "5h")
    mm = macro(new)
    assert [s.op for s in mm.intro] == [ops.AKK_TYPE, ops.SERIES, ops.CAPACITY, IF_TM]
    assert ve.remove_declaration(new, mm, ops.SERIES).count("SERIES") == 0
    with pytest.raises(ve.EditError):
        ve.set_declaration(text, m, ops.CONSTANT_I, "1A")


def test_set_declaration_in_a_macro_without_introduction():
    text = "MACRO X\n  CHARGE_SECTION\n    FAZE\n      CONSTANT_I=1A\n    END_FAZE\n  END_SECTION\nEND_MACRO\n"
    new = ve.set_declaration(text, macro(text), ops.AKK_TYPE, "NiMh")
    assert new.startswith("MACRO X\n  AKK_TYPE=NiMh\n  CHARGE_SECTION\n")


def test_set_name():
    new = ve.set_name(COMMENTED, macro(COMMENTED), "LiPo-3S")
    assert macro(new).name == "LiPo-3S"
    comments_kept(COMMENTED, new)


# -- words, paths, patches ------------------------------------------------------------------------

def test_sentences():
    m = macro(COMMENTED)
    assert ve.describe_phase(m.discharge.items[0], "discharge") == "Discharge at 1C until V < 3 V/cell"
    assert ve.describe_phase(m.charge.items[0]) == "Charge at the current entered at start until V > 4.1 V/cell"
    assert ve.describe_phase(m.charge.items[1]) == "Hold 4.2 V/cell until I < 0.1 A"
    text = "MACRO X\n  CHARGE_SECTION\n    FAZE\n      CONSTANT_I=1C\n      IF(V>4.1S) STOP_FAZE\n" \
           "      IF(tf>2h) STOP_FAZE\n    END_FAZE\n    FAZE\n      CONSTANT_I=1C CONSTANT_V=4.2S\n" \
           "      IF(I<0.05C) STOP_FAZE\n    END_FAZE\n    FAZE\n      TRICKLE(0.1C, 2.3S, 2.5S)\n" \
           "    END_FAZE\n  END_SECTION\nEND_MACRO\n"
    a, b, c = macro(text).charge.items
    assert ve.describe_phase(a) == "Charge at 1C until V > 4.1 V/cell or 2 h"
    assert ve.describe_phase(b) == "CC-CV 1C to 4.2 V/cell until I < 0.05C"
    assert ve.describe_phase(c) == "Top up at 0.1C between 2.3 and 2.5 V/cell, with no stop condition"
    assert "\u00a0" in ve.describe_phase(a, nbsp=True)


def test_paths_find_the_same_nodes_again():
    text = ve.wrap_in_cycle(COMMENTED, macro(COMMENTED).charge.items[1], 2)
    m = macro(text)
    nodes = [m.intro[0], m.conclusion[0], m.discharge.items[0], m.charge.items[1], m.charge.items[1].items[0],
             m.charge.items[1].items[0].statements[1]]
    again = macro(text)
    for node in nodes:
        path = ve.path_of(m, node)
        assert ve.node_at(m, path) is node
        assert type(ve.node_at(again, path)) is type(node)
    assert ve.path_of(m, m.charge.items[1].items[0].statements[1]) == ("charge", 1, 0, "st", 1)
    with pytest.raises(LookupError):
        ve.node_at(m, ("charge", 7))
    assert ve.shape(m) == ve.shape(again) != ve.shape(macro(COMMENTED))


def test_common_patch_is_the_smallest_middle():
    old, new = "abcXYZdef", "abcQdef"
    start, end, insert = ve.common_patch(old, new)
    assert (start, end, insert) == (3, 6, "Q")
    assert old[:start] + insert + old[end:] == new
    assert ve.common_patch("same", "same") == (4, 4, "")
    assert sorted(ve.dropped_comments("a // x\nb // y\n// x\n", "a // x\nb\n")) == ["// x", "// y"]


@pytest.mark.parametrize("name", sorted(p.stem for p in MACROS.glob("*.zuml")))
def test_every_value_of_every_seed_macro_can_be_set_to_itself(name):
    """Setting each operand to its own canonical text keeps the bytes (it only canonicalises)."""
    text = (MACROS / f"{name}.zuml").read_text()
    base = compiled(text)
    m = base.macro
    statements = list(m.intro) + list(m.conclusion)
    for section in m.sections():
        for phase in section.phases():
            statements += phase.statements
    for st in statements:
        path = ve.path_of(m, st)
        for i, operand in enumerate(st.op.operands):
            fresh = macro(text)
            new = ve.set_value(text, ve.node_at(fresh, path), i, operand.kind.format(st.args[i].raw))
            assert compiled(new).record == base.record
            assert not ve.dropped_comments(text, new)


def test_seed_macros_are_the_ones_tested():
    assert set(SEED_MACROS) <= {p.stem for p in MACROS.glob("*.zuml")}


@pytest.mark.parametrize("name", sorted(p.stem for p in MACROS.glob("*.zuml")))
def test_edits_undone_by_their_opposite_give_the_same_text(name):
    """wrap/unwrap, add/remove a condition and move down/up are exact inverses on every seed macro;
    each step compiles."""
    text = (MACROS / f"{name}.zuml").read_text()
    m = macro(text)
    for section in m.sections():
        for i, item in enumerate(section.items):
            path = (section.kind, i)
            if isinstance(item, Phase):
                wrapped = ve.wrap_in_cycle(text, item, 2)
                assert ve.unwrap_cycle(wrapped, ve.node_at(macro(wrapped), path)) == text
                for op in ve.missing_conditions(item):
                    added = ve.add_condition(text, item, op, ve.default_value(op, m, section.kind))
                    result = compile_source(added)
                    if not result.ok:                       # only the safety lint may refuse a default
                        assert all(d.code.startswith("E3") for d in result.errors)
                        continue
                    assert ve.remove_statement(added, ve.node_at(result.macro, path).statements[-1]) == text
            if i + 1 < len(section.items):
                moved = ve.move_item(text, section, i, i + 1)
                assert ve.move_item(moved, getattr(macro(moved), section.kind), i + 1, i) == text
        assert compile_source(ve.add_phase(text, m, section.kind)).ok
