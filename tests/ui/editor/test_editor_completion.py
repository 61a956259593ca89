"""Completion: items from the opcode table, popup behaviour, insertion."""
from PySide6.QtCore import Qt

from zuml_studio.lang import opcodes
from zuml_studio.ui.editor.completion import completion_items, word_before


def test_items_cover_every_statement_form_and_symbolic_values(editor):
    items = editor.completer.items()
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
    assert shown == ["CONSTANT_I=", "CONSTANT_V=", "CONTINUE_MACRO"]
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
    qtbot.keyClicks(editor, "STOP")                       # STOP, STOP_FAZE, STOP_MACRO
    assert editor.completer.is_open()
    qtbot.keyClick(editor, Qt.Key.Key_Return)             # the word is complete: a new line
    assert editor.toPlainText() == "FAZE\n  STOP\n  "
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
    qtbot.keyClick(editor, Qt.Key.Key_Space)
    qtbot.keyClicks(editor, "IN")
    assert editor.completer.is_open()
    qtbot.keyClick(editor, Qt.Key.Key_Backspace)
    assert not editor.completer.is_open()
