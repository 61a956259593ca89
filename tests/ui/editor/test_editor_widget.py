"""The editor widget: diagnostics, tooltips, comments, indentation, navigation, linked lines."""
import pytest
from PySide6.QtCore import Qt
from PySide6.QtGui import QColor, QFont, QFontDatabase, QFontMetricsF, QTextCharFormat, QTextFormat

from helpers import WAIT_MS, bare_seed
from zuml_studio.lang.diagnostics import Diagnostic, Severity
from zuml_studio.ui.editor.code_editor import CodeEditor, EditorWithFind

LIPO = bare_seed("LiPo")
WAVE = QTextCharFormat.UnderlineStyle.WaveUnderline


def underlines(editor):
    return [(s.cursor.selectionStart(), s.cursor.selectionEnd(), s.format.underlineColor().name())
            for s in editor.extraSelections() if s.format.underlineStyle() == WAVE]


def backgrounds(editor):
    return [(s.cursor.blockNumber() + 1, s.format.background().color().name()) for s in editor.extraSelections()
            if s.format.property(QTextFormat.Property.FullWidthSelection)]


def pos(editor, line, column):
    return editor.document().findBlockByNumber(line - 1).position() + column - 1


def diag(line, col, end, severity=Severity.ERROR, message="bad", hint="fix it"):
    return Diagnostic(severity, line, col, end, "E999", message, hint)


def _glyph_widths(font) -> set:
    metrics = QFontMetricsF(font)
    return {metrics.horizontalAdvance(c) for c in "iW0 _m.(|"}


def test_object_name_font_and_tab(editor):
    assert editor.objectName() == "editor"
    # What matters is that every glyph is as wide as the next, not Qt's fixed-pitch flag (false
    # for some monospaced fonts, Noto Sans Mono among them).
    if len(_glyph_widths(editor.font())) > 1 and not any(
            len(_glyph_widths(QFont(family))) == 1 for family in QFontDatabase.families()):
        pytest.skip("no monospaced font is installed (install fonts-dejavu-core)")
    assert len(_glyph_widths(editor.font())) == 1
    assert editor.tabStopDistance() == pytest.approx(editor.fontMetrics().horizontalAdvance(" ") * 2)


def test_diagnostics_are_wave_underlines_with_colours_and_ranges(editor):
    editor.setPlainText(LIPO)
    editor.set_diagnostics([diag(12, 10, (12, 13)), diag(5, 16, (5, 18), Severity.WARNING)])
    got = sorted(underlines(editor))
    red, orange = "#e0201b", "#f08c00"
    assert got == sorted([(pos(editor, 12, 10), pos(editor, 12, 13), red),
                          (pos(editor, 5, 16), pos(editor, 5, 18), orange)])
    # Replaced wholesale, and the current-line highlight is still there.
    editor.set_diagnostics([diag(3, 3, (3, 3))])
    assert underlines(editor) == [(pos(editor, 3, 3), pos(editor, 3, 4), red)]    # zero width: one character
    assert any(line == editor.current_line() for line, _ in backgrounds(editor))
    editor.set_diagnostics([])
    assert underlines(editor) == []


def test_zero_width_at_the_line_end_marks_the_last_character(editor):
    editor.setPlainText("FAZE\n\nEND_FAZE")
    editor.set_diagnostics([diag(1, 5, (1, 5)), diag(2, 1, (2, 1)), diag(99, 1, (99, 1))])
    spans = sorted((s, e) for s, e, _ in underlines(editor))
    assert (3, 4) in spans                                  # the E of FAZE
    assert editor.line_markers() == {0: Severity.ERROR, 1: Severity.ERROR, 2: Severity.ERROR}


def test_gutter_markers_follow_the_text(editor, qtbot):
    editor.setPlainText(LIPO)
    editor.set_diagnostics([diag(12, 10, (12, 13)), diag(5, 16, (5, 18), Severity.WARNING),
                            diag(5, 5, (5, 7))])
    assert editor.line_markers() == {11: Severity.ERROR, 4: Severity.ERROR}
    editor.goto(1, 1)
    qtbot.keyClick(editor, Qt.Key.Key_Return)
    assert editor.line_markers() == {12: Severity.ERROR, 5: Severity.ERROR}


def test_tooltip_for_a_diagnostic_then_for_a_keyword(editor):
    editor.setPlainText(LIPO)
    editor.set_diagnostics([diag(12, 10, (12, 13), message="The limit of IF(V>x) needs a unit: 4.2V or 4.2S",
                                 hint="a bare 4.1 is never guessed")])
    assert editor.tooltip_at(pos(editor, 12, 11)) == ("The limit of IF(V>x) needs a unit: 4.2V or 4.2S\n"
                                                      "a bare 4.1 is never guessed")
    assert editor.tooltip_at_line_column(12, 11) == editor.tooltip_at(pos(editor, 12, 11))
    # Outside the range: the help of IF(V>x) from the opcode table.
    tip = editor.tooltip_at(pos(editor, 12, 6))
    assert tip.startswith("IF(V>x) STOP_FAZE\n") and "rises above" in tip
    tip = editor.tooltip_at(pos(editor, 5, 6))                          # CONSTANT_I
    assert tip.startswith("CONSTANT_I=I\nHold the current")
    assert editor.tooltip_at(pos(editor, 1, 8)) == ""                   # the macro's name
    assert editor.tooltip_at(pos(editor, 19, 9)) == ""                  # STOP in MUSIC(STOP)
    assert editor.tooltip_at(pos(editor, 19, 3)).startswith("MUSIC(n)\n")


def test_tooltip_for_a_condition_lists_the_matching_table_rows(editor):
    editor.setPlainText("IF(Tc>70) PAUSE_MACRO\nIF(t>2h) STOP_FAZE")
    assert editor.tooltip_at(pos(editor, 1, 1)).startswith("IF(Tc>x) PAUSE_MACRO\n")
    assert editor.tooltip_at(pos(editor, 1, 4)).startswith("IF(Tc>x) PAUSE_MACRO\n")   # the variable
    assert editor.tooltip_at(pos(editor, 2, 10)).startswith("IF(tf>x) STOP_FAZE\n")     # the outcome


def test_hover_position_maps_to_characters_only(editor):
    editor.setPlainText("FAZE")
    rect = editor.cursorRect(editor.textCursor())
    assert editor.position_at(rect.center() + type(rect.center())(3, 0)) == 0
    assert editor.position_at(rect.center() + type(rect.center())(400, 0)) is None


def test_toggle_comment_round_trip_is_one_undo_step_each(editor):
    editor.setPlainText(LIPO)
    editor.goto(4, 1)
    cursor = editor.textCursor()
    cursor.setPosition(pos(editor, 7, 3), cursor.MoveMode.KeepAnchor)
    editor.setTextCursor(cursor)
    editor.toggle_comment()
    lines = editor.toPlainText().split("\n")
    assert lines[3:7] == ["    // FAZE", "    // CONSTANT_I=1C", "    // IF(V<2.8S) STOP_FAZE()", "    // END_FAZE"]
    assert lines[7] == "  END_SECTION"
    editor.toggle_comment()
    assert editor.toPlainText() == LIPO
    editor.undo()
    assert editor.toPlainText().split("\n")[3] == "    // FAZE"
    editor.undo()
    assert editor.toPlainText() == LIPO


def test_ctrl_slash_toggles_the_current_line(editor, qtbot):
    editor.setPlainText(LIPO)
    editor.goto(2, 5)
    qtbot.keyClick(editor, Qt.Key.Key_Slash, Qt.KeyboardModifier.ControlModifier)
    assert editor.toPlainText().split("\n")[1] == "  // AKK_TYPE=LiPo"
    qtbot.keyClick(editor, Qt.Key.Key_Slash, Qt.KeyboardModifier.ControlModifier)
    assert editor.toPlainText() == LIPO


def test_return_keeps_indentation_and_indents_after_faze_then_end_faze_dedents(editor, qtbot):
    editor.setPlainText("MACRO x\n  CHARGE_SECTION")
    editor.moveCursor(editor.textCursor().MoveOperation.End)
    qtbot.keyClick(editor, Qt.Key.Key_Return)
    qtbot.keyClicks(editor, "FAZE")
    qtbot.keyClick(editor, Qt.Key.Key_Return)
    qtbot.keyClicks(editor, "CONSTANT_V=4.2S")
    qtbot.keyClick(editor, Qt.Key.Key_Return)
    assert editor.toPlainText().split("\n")[2:] == ["    FAZE", "      CONSTANT_V=4.2S", "      "]
    qtbot.keyClicks(editor, "END_FAZE")
    assert editor.toPlainText().split("\n")[-1] == "    END_FAZE"
    qtbot.keyClick(editor, Qt.Key.Key_Return)
    qtbot.keyClicks(editor, "END_SECTION")
    assert editor.toPlainText().split("\n")[-2:] == ["    END_FAZE", "  END_SECTION"]
    # The dedent is its own undo step: undo puts the typed indentation back.
    editor.undo()
    assert editor.toPlainText().split("\n")[-1] == "    END_SECTION"


def test_return_after_a_one_line_phase_does_not_indent(editor, qtbot):
    editor.setPlainText("    FAZE CONSTANT_I=1C IF(V>1S) STOP_FAZE END_FAZE")
    editor.moveCursor(editor.textCursor().MoveOperation.End)
    qtbot.keyClick(editor, Qt.Key.Key_Return)
    assert editor.toPlainText().split("\n")[-1] == "    "


def test_return_is_a_single_undo_step(editor, qtbot):
    editor.setPlainText("  FAZE")
    editor.moveCursor(editor.textCursor().MoveOperation.End)
    qtbot.keyClick(editor, Qt.Key.Key_Return)
    assert editor.toPlainText() == "  FAZE\n    "
    editor.undo()
    assert editor.toPlainText() == "  FAZE"


def test_backspace_in_leading_spaces_goes_to_the_previous_multiple_of_two(editor, qtbot):
    editor.setPlainText("     X")
    editor.goto(1, 6)
    qtbot.keyClick(editor, Qt.Key.Key_Backspace)
    assert editor.toPlainText() == "    X"
    qtbot.keyClick(editor, Qt.Key.Key_Backspace)
    assert editor.toPlainText() == "  X"
    editor.setPlainText("  AB")
    editor.moveCursor(editor.textCursor().MoveOperation.End)
    qtbot.keyClick(editor, Qt.Key.Key_Backspace)
    assert editor.toPlainText() == "  A"                    # in text: one character


def test_tab_inserts_spaces_and_indents_selected_lines(editor, qtbot):
    editor.setPlainText("X")
    qtbot.keyClick(editor, Qt.Key.Key_Tab)
    assert editor.toPlainText() == "  X"
    editor.setPlainText("A\nB")
    editor.selectAll()
    qtbot.keyClick(editor, Qt.Key.Key_Tab)
    assert editor.toPlainText() == "  A\n  B"
    qtbot.keyClick(editor, Qt.Key.Key_Backtab, Qt.KeyboardModifier.ShiftModifier)
    assert editor.toPlainText() == "A\nB"


def test_goto_current_line_and_cursor_line_changed(editor, qtbot):
    editor.setPlainText(LIPO)
    editor.goto(1)
    with qtbot.waitSignal(editor.cursorLineChanged, timeout=WAIT_MS) as blocker:
        editor.goto(12, 10)
    assert blocker.args == [12]
    assert editor.current_line() == 12
    cursor = editor.textCursor()
    assert (cursor.blockNumber() + 1, cursor.positionInBlock() + 1) == (12, 10)
    assert editor.hasFocus() or not editor.isActiveWindow()
    with qtbot.assertNotEmitted(editor.cursorLineChanged):
        editor.goto(12, 3)                                   # same line: no signal
    editor.goto(999, 999)                                    # clamped
    assert editor.current_line() == editor.document().blockCount()
    assert editor.textCursor().atBlockEnd()


def test_current_line_highlight_follows_the_cursor(editor, qtbot):
    editor.setPlainText(LIPO)
    editor.goto(7)
    assert backgrounds(editor) == [(7, "#edf2fa")]
    qtbot.keyClick(editor, Qt.Key.Key_Down)
    assert backgrounds(editor) == [(8, "#edf2fa")]


def test_linked_lines_get_a_soft_background(editor):
    editor.setPlainText(LIPO)
    editor.goto(1)
    editor.set_linked_lines({14, 15, 500})
    linked = [(line, colour) for line, colour in backgrounds(editor) if line != 1]
    assert linked == [(14, "#e2f4e8"), (15, "#e2f4e8")]
    current = [colour for line, colour in backgrounds(editor) if line == 1]
    assert current and current[0] != "#e2f4e8"
    assert editor.linked_lines() == {14, 15}
    editor.set_linked_lines(set())
    assert [line for line, _ in backgrounds(editor)] == [1]


def test_undo_redo_are_the_editors_own(editor, qtbot):
    editor.setPlainText("A")
    editor.moveCursor(editor.textCursor().MoveOperation.End)
    qtbot.keyClicks(editor, "B")
    qtbot.keyClick(editor, Qt.Key.Key_Z, Qt.KeyboardModifier.ControlModifier)
    assert editor.toPlainText() == "A"
    qtbot.keyClick(editor, Qt.Key.Key_Z, Qt.KeyboardModifier.ControlModifier | Qt.KeyboardModifier.ShiftModifier)
    assert editor.toPlainText() == "AB"


def test_editor_with_find_places_the_bar_under_the_editor(qtbot):
    box = EditorWithFind()
    qtbot.addWidget(box)
    box.resize(600, 400)
    box.show()
    assert isinstance(box.editor, CodeEditor)
    assert not box.find_bar.isVisible()
    box.editor.show_find()
    assert box.find_bar.isVisible()
    assert box.find_bar.geometry().top() >= box.editor.geometry().bottom()


def test_gutter_is_wide_enough_and_tooltips_markers(editor):
    editor.setPlainText("\n".join(["FAZE"] * 120))
    area = editor.line_number_area
    assert area.width() >= editor.fontMetrics().horizontalAdvance("120")
    assert editor.viewportMargins().left() == area.width()
    editor.set_diagnostics([diag(1, 1, (1, 5), message="first")])
    editor.goto(1)
    top = editor.blockBoundingGeometry(editor.document().firstBlock()).translated(editor.contentOffset()).top()
    assert editor.gutter_tooltip(int(top) + 2) == "first\nfix it"
    assert QColor(area.grab().toImage().pixel(6, int(top) + editor.fontMetrics().height() // 2)) != QColor("#f6f7f9")


def test_hovering_shows_the_tooltip(editor):
    from PySide6.QtCore import QEvent, QPoint
    from PySide6.QtGui import QHelpEvent
    from PySide6.QtWidgets import QApplication, QToolTip

    editor.setPlainText("    CONSTANT_I=1\n")
    editor.set_diagnostics([diag(1, 16, (1, 17), message="CONSTANT_I needs a unit: 2A or 0.5C")])

    def hover(column):
        cursor = editor.textCursor()
        cursor.setPosition(column - 1)
        rect = editor.cursorRect(cursor)
        point = QPoint(rect.x() + 2, rect.center().y())
        QApplication.sendEvent(editor.viewport(),
                               QHelpEvent(QEvent.Type.ToolTip, point, editor.viewport().mapToGlobal(point)))
        return QToolTip.text() if QToolTip.isVisible() else ""

    assert "CONSTANT_I=I" in hover(6) and "Hold the current" in hover(6)
    assert "needs a unit" in hover(16) and "fix it" in hover(16)        # the diagnostic wins
    QToolTip.hideText()
