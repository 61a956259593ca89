"""The inline find / replace bar."""
import pytest
from PySide6.QtCore import Qt

from helpers import bare_seed
from zuml_studio.ui.editor.code_editor import EditorWithFind

LIPO = bare_seed("LiPo")


@pytest.fixture
def box(qtbot):
    b = EditorWithFind()
    qtbot.addWidget(b)
    b.resize(700, 500)
    b.show()
    b.editor.setPlainText(LIPO)
    b.editor.goto(1)
    return b


def selection(editor):
    c = editor.textCursor()
    return c.blockNumber() + 1, c.selectedText()


def test_find_next_previous_wraps_and_counts(box, qtbot):
    bar, editor = box.find_bar, box.editor
    editor.show_find()
    assert bar.isVisible() and not bar.replace_edit.isVisible()
    qtbot.keyClicks(bar.find_edit, "end_faze")             # incremental, case-insensitive
    assert selection(editor) == (7, "END_FAZE")
    assert bar.status.text() == "1 of 3"
    assert bar.find_next() and selection(editor) == (13, "END_FAZE")
    qtbot.keyClick(bar.find_edit, Qt.Key.Key_Return)
    assert selection(editor) == (17, "END_FAZE")
    assert bar.find_next() and selection(editor) == (7, "END_FAZE")      # wrapped
    assert bar.find_next(backward=True) and selection(editor) == (17, "END_FAZE")
    assert len(editor._find) == 3                           # all matches marked
    bar.match_case.setChecked(True)
    assert not bar.find_next()
    assert bar.status.text() == "No results"


def test_escape_closes_the_bar_and_returns_to_the_editor(box, qtbot):
    box.editor.show_find(replace=True)
    assert box.find_bar.replace_edit.isVisible()
    qtbot.keyClicks(box.find_bar.find_edit, "FAZE")
    qtbot.keyClick(box.find_bar.find_edit, Qt.Key.Key_Escape)
    assert not box.find_bar.isVisible()
    assert box.editor._find == []


def test_replace_and_replace_all_as_one_undo_step(box, qtbot):
    bar, editor = box.find_bar, box.editor
    editor.show_find(replace=True)
    qtbot.keyClicks(bar.find_edit, "STOP_FAZE()")
    bar.replace_edit.setText("STOP_FAZE")
    assert selection(editor) == (6, "STOP_FAZE()")
    bar.replace()
    assert editor.toPlainText().split("\n")[5] == "    IF(V<2.8S) STOP_FAZE"
    assert selection(editor) == (12, "STOP_FAZE()")
    assert bar.replace_all() == 2
    assert "STOP_FAZE()" not in editor.toPlainText()
    assert editor.toPlainText() == LIPO.replace("STOP_FAZE()", "STOP_FAZE")
    editor.undo()
    assert editor.toPlainText().count("STOP_FAZE()") == 2
    editor.undo()
    assert editor.toPlainText() == LIPO


def test_find_seeds_from_the_selection(box):
    editor = box.editor
    cursor = editor.document().find("CONSTANT_V")
    editor.setTextCursor(cursor)
    editor.show_find()
    assert box.find_bar.find_edit.text() == "CONSTANT_V"
