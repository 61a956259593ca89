"""Completion: items from the opcode table, popup behaviour, insertion."""
from PySide6.QtCore import Qt

from zuml_studio.lang import opcodes
from zuml_studio.ui.editor.completion import completion_items, items_at, word_before


def test_items_cover_every_statement_form_and_symbolic_values():
    items = [item.text for item in completion_items()]
    for expected in ("CONSTANT_I=", "CONSTANT_V=", "CHARGE_EX(", "TRICKLE(", "IF(V>", "IF(V<", "IF(T>", "IF(Tc<",
                     "IF(tm>", "IF(tf>", "IF(DELTA_PEAK>", "FAZE", "END_FAZE", "CYCLE(", "MUSIC(", "LIGHT(",
                     "AKK_TYPE=", "STOP_FAZE", "PAUSE_MACRO", "INPUT", "AUTO", "LiPo", "NiMh", "STOP", "FAST"):
        assert expected in items, expected
    assert len(items) == len({i.upper() for i in items})          # FAZE once, though also a LIGHT value
    keywords = {op.keyword for op in opcodes.OPCODES if not op.condition}
    assert keywords <= {i.rstrip("=(") for i in items}
    assert all(item.detail for item in completion_items())


def test_word_before_ignores_units_and_comments():
    assert word_before("  CONS", 6) == "CONS"
    assert word_before("CONSTANT_I=1C", 13) == ""         # the unit of a number
    assert word_before("  // CONS", 9) == ""
    assert word_before("IF(V>4.1", 8) == ""


def test_typing_two_letters_opens_the_popup_and_return_accepts(editor, qtbot):
    qtbot.keyClicks(editor, "    C")
    assert not editor.completer.is_open()
    qtbot.keyClicks(editor, "on")
    assert editor.completer.is_open()
    assert editor.completer.completionPrefix() == "Con"
    shown = [editor.completer.completionModel().index(r, 0).data()
             for r in range(editor.completer.completionModel().rowCount())]
    assert shown == ["CONSTANT_I=", "CONSTANT_V="]              # no outcome at a line start
    qtbot.keyClick(editor, Qt.Key.Key_Down)
    qtbot.keyClick(editor, Qt.Key.Key_Return)
    assert editor.toPlainText() == "    CONSTANT_V="
    assert not editor.completer.is_open()
    editor.undo()                                          # the insertion is one undo step
    assert editor.toPlainText() == "    Con"


def test_tab_accepts_and_condition_items_insert_up_to_the_value(editor, qtbot):
    qtbot.keyClicks(editor, "if")
    assert editor.completer.is_open()
    while editor.completer.current_text() != "IF(V>":
        qtbot.keyClick(editor, Qt.Key.Key_Down)
    qtbot.keyClick(editor, Qt.Key.Key_Tab)
    assert editor.toPlainText() == "IF(V>"
    qtbot.keyClicks(editor, "4.1S) ")
    assert not editor.completer.is_open()


def test_the_popup_does_not_steal_plain_typing(editor, qtbot):
    qtbot.keyClicks(editor, "FAZE")
    assert not editor.completer.is_open()                 # an exact, single match: nothing to offer
    qtbot.keyClick(editor, Qt.Key.Key_Return)
    assert editor.toPlainText() == "FAZE\n  "
    qtbot.keyClicks(editor, "IF(V>4S) STOP")              # STOP_FAZE, STOP_MACRO
    assert editor.completer.is_open()
    editor.completer.popup().setCurrentIndex(editor.completer.completionModel().index(-1, 0))
    editor.completer.close()
    qtbot.keyClick(editor, Qt.Key.Key_Return)
    assert editor.toPlainText() == "FAZE\n  IF(V>4S) STOP\n  "
    qtbot.keyClicks(editor, "xyz ab")                     # no matches: no popup
    assert not editor.completer.is_open()
    qtbot.keyClicks(editor, " // comment words")
    assert not editor.completer.is_open()
    assert editor.toPlainText().endswith("xyz ab // comment words")


def test_escape_closes_and_ctrl_space_opens_with_everything(editor, qtbot):
    qtbot.keyClicks(editor, "CH")
    assert editor.completer.is_open()
    qtbot.keyClick(editor, Qt.Key.Key_Escape)
    assert not editor.completer.is_open()
    assert editor.toPlainText() == "CH"
    qtbot.keyClick(editor, Qt.Key.Key_Space, Qt.KeyboardModifier.ControlModifier)
    assert editor.completer.is_open()
    assert editor.completer.completionCount() == 2          # CHARGE_SECTION, CHARGE_EX(
    editor.setPlainText("")
    qtbot.keyClick(editor, Qt.Key.Key_Space, Qt.KeyboardModifier.ControlModifier)
    assert editor.completer.completionCount() == len(editor.completer.items())
    qtbot.keyClick(editor, Qt.Key.Key_Return)
    assert editor.toPlainText() == editor.completer.items()[0]


def test_units_of_numbers_do_not_open_the_popup(editor, qtbot):
    qtbot.keyClicks(editor, "CONSTANT_I=500mA")
    assert not editor.completer.is_open()
    editor.setPlainText("")
    qtbot.keyClicks(editor, "CONSTANT_I=IN")
    assert editor.completer.is_open()
    qtbot.keyClick(editor, Qt.Key.Key_Backspace)
    assert not editor.completer.is_open()


def _shown(editor):
    model = editor.completer.completionModel()
    return [model.index(r, 0).data() for r in range(model.rowCount())]


def test_after_an_equals_sign_only_that_operands_values_are_offered(editor, qtbot):
    qtbot.keyClicks(editor, "AKK_TYPE=Li")
    assert editor.completer.is_open()
    assert _shown(editor) == ["LiPo", "LiIon", "LiS", "LiFe"]
    qtbot.keyClick(editor, Qt.Key.Key_Return)
    assert editor.toPlainText() == "AKK_TYPE=LiPo"


def test_contexts_come_from_the_opcode_table():
    texts = lambda line, col=None: [i.text for i in items_at(line, len(line) if col is None else col)]
    assert "LIGHT(" in texts("  LI") and "LiPo" not in texts("  LI")      # a statement at the line start
    assert texts("CONSTANT_I=") == ["INPUT"]                                  # a current: INPUT, never LiPo
    assert texts("CAPACITY=") == ["INPUT", "AUTO"]
    assert texts("  MUSIC(") == ["START", "STOP", "ERROR", "ATTENTION"]
    assert texts("  LIGHT(") == ["SLOW", "FAST", "ON", "FAZE"]
    assert "V>" in texts("  IF(") and "STOP_FAZE" in texts("  IF(V>4.1S) ")
    assert texts("MACRO Li") == [] and texts("CONSTANT_I=1C") == [] and texts("  // CONS") == []


def test_accepting_replaces_the_whole_word_and_does_not_double_the_equals_sign(editor, qtbot):
    editor.setPlainText("      CONSTNAT_I=1C")
    cursor = editor.textCursor()
    cursor.setPosition(len("      CONS"))
    editor.setTextCursor(cursor)
    assert editor.completer.open()
    assert editor.completer.current_text() == "CONSTANT_I="
    qtbot.keyClick(editor, Qt.Key.Key_Return)
    assert editor.toPlainText() == "      CONSTANT_I=1C"
    assert editor.textCursor().positionInBlock() == len("      CONSTANT_I=")
    editor.undo()
    assert editor.toPlainText() == "      CONSTNAT_I=1C"


def test_ctrl_period_applies_the_did_you_mean_fix(editor, qtbot):
    from zuml_studio.lang.compiler import compile_source

    text = "MACRO X\n  AKK_TYPE=LiPo\n  CHARGE_SECTION\n    FAZE\n      CONSTNAT_I=1C\n" \
           "      IF(V>4.2S) STOP_FAZE\n    END_FAZE\n  END_SECTION\nEND_MACRO\n"
    editor.setPlainText(text)
    (diag,) = [d for d in compile_source(text).diagnostics if d.code == "E110"]
    assert diag.fix == "CONSTANT_I"
    editor.set_diagnostics([diag])
    assert "Ctrl+. writes CONSTANT_I" in editor.tooltip_at_line_column(5, 8)
    assert editor.fix_at(editor.document().findBlockByNumber(0).position()) is None     # another line
    editor.goto(5, 1)
    qtbot.keyClick(editor, Qt.Key.Key_Period, Qt.KeyboardModifier.ControlModifier)
    assert compile_source(editor.toPlainText()).ok
    editor.undo()
    assert editor.toPlainText() == text
