"""The visual editor as a user drives it (offscreen): a view of the text, every card edit a
text patch with one undo history, bytes following through the normal check."""
import pytest
from PySide6.QtCore import QMimeData, QPoint, QPointF, Qt
from PySide6.QtGui import QDropEvent, QDragEnterEvent, QTextCursor
from PySide6.QtWidgets import QApplication, QScrollBar

from helpers import WAIT_MS, bare_seed
from zuml_studio.lang import visual_edits as ve
from zuml_studio.lang import opcodes as ops
from zuml_studio.lang.ast import Cycle
from zuml_studio.lang.compiler import compile_source
from zuml_studio.ui.visual.cards import MIME, CycleBox, PhaseCard, encode_path

LIPO_TEXT = bare_seed("LiPo")


def record(text):
    result = compile_source(text)
    assert result.ok, result.diagnostics
    return result.record


def settle(qtbot, v, text):
    """Wait until the check of ``text`` ran and the cards show its macro."""
    want = compile_source(text)

    def done():
        last = v.validator.last
        return (last is not None and last.ok == want.ok and (not want.ok or last.record == want.record) and
                v.view.macro() is not None and ve.shape(v.view.macro()) == ve.shape(want.macro))
    qtbot.waitUntil(done, timeout=WAIT_MS)


def cards(view, kind=None):
    return [w for p, w in sorted(view.items.items(), key=lambda kv: str(kv[0]))
            if isinstance(w, PhaseCard) and (kind is None or p[0] == kind)]


def type_into(qtbot, line_edit, text):
    line_edit.setFocus()
    line_edit.selectAll()
    qtbot.keyClicks(line_edit, text)
    qtbot.keyClick(line_edit, Qt.Key.Key_Return)


# -- showing ------------------------------------------------------------------------------------

def test_commands_between_the_sections_are_chips_of_their_own(visual, qtbot):
    text = LIPO_TEXT.replace("  CHARGE_SECTION", "  MUSIC(ATTENTION)\n  LIGHT(FAST)\n  CHARGE_SECTION")
    v = visual(text)
    settle(qtbot, v, text)
    view = v.view
    assert view.between_box.isVisible()
    assert [c.field.value_text() for c in view.between_chips] == ["ATTENTION", "FAST"]
    assert [c.field.value_text() for c in view.conclusion_chips] == ["STOP"]
    assert ve.node_at(view.macro(), ("between", 1)).op is ops.BY_CODE[101]
    view.remove_statement(("between", 0))                  # the chip's ✕
    text = text.replace("  MUSIC(ATTENTION)\n", "")
    settle(qtbot, v, text)
    assert v.editor.toPlainText() == text
    assert [c.field.value_text() for c in view.between_chips] == ["FAST"]
    v.editor.setPlainText(LIPO_TEXT)
    settle(qtbot, v, LIPO_TEXT)
    assert not view.between_box.isVisible() and view.between_chips == []


def test_the_lipo_macro_as_cards(visual):
    v = visual()
    view = v.view
    assert view.objectName() == "visualEditor"
    assert not view.banner.isVisible()
    discharge = view.items[("discharge", 0)]
    charge1, charge2 = view.items[("charge", 0)], view.items[("charge", 1)]
    assert discharge.sentence.text().replace("\u00a0", " ") == "Discharge at 1C until V < 2.8 V/cell"
    assert charge2.sentence.text().replace("\u00a0", " ") == "Hold 4.2 V/cell until I < 0.1 A"
    assert discharge.property("section") == "discharge" and charge1.property("section") == "charge"
    assert charge1.action_combo.currentData() == "CONSTANT_I"
    (k, i, field), = charge1.action_fields
    assert field.value_text() == "INPUT"
    assert [f.value_text() for _, f in charge2.condition_fields] == ["0.1A"]
    assert view.intro.akk.currentText() == "LiPo"
    assert view.intro.series.text() == "at start"
    assert [c.field.value_text() for c in view.conclusion_chips] == ["STOP"]
    # the add-condition menu lists the phase conditions from the opcode table that are not there yet
    listed = {a.data() for a in charge2.add_menu.actions()}
    assert listed == {op.code for op in ve.missing_conditions(charge2.phase)}
    assert ops.BY_CODE[84].code not in listed and ops.BY_CODE[87].code not in listed


def test_editing_the_text_changes_the_cards(visual, qtbot):
    v = visual()
    cursor = v.editor.document().find("CONSTANT_V=4.2S")
    cursor.insertText("CONSTANT_V=4.1S")
    qtbot.waitUntil(lambda: "4.1 V/cell" in v.view.items[("charge", 1)].sentence.text().replace("\u00a0", " "),
                    timeout=WAIT_MS)
    # a new phase in the text is a new card
    cursor = v.editor.document().find("  END_SECTION", v.editor.document().find("  CHARGE_SECTION"))
    cursor.movePosition(QTextCursor.MoveOperation.StartOfBlock)
    cursor.insertText("    FAZE\n      CONSTANT_I=0.1C\n      IF(tf>1h) STOP_FAZE\n    END_FAZE\n")
    qtbot.waitUntil(lambda: ("charge", 2) in v.view.items, timeout=WAIT_MS)
    assert v.view.items[("charge", 2)].sentence.text().replace("\u00a0", " ") == "Charge at 0.1C for 1 h"


# -- values ---------------------------------------------------------------------------------------

def test_changing_a_value_on_a_card_changes_the_text_and_the_bytes(window_with_visual, qtbot):
    w, view = window_with_visual()
    before = w.validator.last.record
    card = view.items[("discharge", 0)]
    (_k, _i, field), = card.action_fields
    type_into(qtbot, field.line, "0.5")
    expected = LIPO_TEXT.replace("CONSTANT_I=1C", "CONSTANT_I=0.5C")
    assert w.editor.toPlainText() == expected
    qtbot.waitUntil(lambda: w.validator.last.ok and w.validator.last.record == record(expected), timeout=3000)
    assert w.validator.last.record != before
    assert w.hex_view.record_hex() == record(expected).hex(" ")
    assert "0.5C" in card.sentence.text()


def test_a_unit_change_applies_at_once_and_input_hides_the_number(visual, qtbot):
    v = visual()
    card = v.view.items[("charge", 0)]
    (_k, _i, field), = card.action_fields
    assert not field.line.isVisibleTo(card)
    field.unit.setCurrentIndex(field.unit.findData("C"))
    field.unit.activated.emit(field.unit.currentIndex())
    assert "    CONSTANT_I=1C\n    IF(V>4.1S)" in v.editor.toPlainText()
    assert field.line.isVisibleTo(card)


def test_a_comment_next_to_an_edited_value_survives(visual, qtbot):
    text = LIPO_TEXT.replace("IF(V<2.8S) STOP_FAZE()", "IF(V<2.8S) STOP_FAZE() // cut-off, see datasheet")
    v = visual(text)
    card = v.view.items[("discharge", 0)]
    (_k, field), = card.condition_fields
    type_into(qtbot, field.line, "3")
    assert "    IF(V<3S) STOP_FAZE // cut-off, see datasheet\n" in v.editor.toPlainText()
    assert "Removed comment" not in v.view.status.text()


def test_a_bad_value_is_refused_with_a_message_and_the_text_stays(visual, qtbot):
    v = visual()
    messages = []
    v.view.statusMessage.connect(messages.append)
    card = v.view.items[("charge", 1)]
    (_k, field), = card.condition_fields
    type_into(qtbot, field.line, "abc")
    assert v.editor.toPlainText() == LIPO_TEXT
    assert messages and v.view.status.property("problem") is True
    assert field.value_text() == "0.1A"                   # the field shows the stored value again


@pytest.mark.parametrize("typed", ["abc", "99"])       # not a value; a value the check refuses (over 5 V/cell)
def test_a_refused_value_leaves_the_field_even_while_it_keeps_the_focus(visual, qtbot, typed):
    v = visual()
    card = v.view.items[("charge", 1)]
    (_k, _i, field), = card.action_fields                 # CONSTANT_V=4.2S
    field.line.hasFocus = lambda: True                    # Enter commits; the cursor stays in the field (no
    type_into(qtbot, field.line, typed)                   # window has the focus offscreen)
    assert v.editor.toPlainText() == LIPO_TEXT
    assert v.view.status.property("problem") is True
    assert field.value_text() == "4.2S"                   # the field, the text and the card agree


def test_one_card_edit_is_one_undo_step_and_undo_restores_text_and_cards(visual, qtbot):
    v = visual()
    card = v.view.items[("charge", 1)]
    (_k, _i, field), = card.action_fields
    type_into(qtbot, field.line, "4.15")
    assert v.editor.document().isUndoAvailable()
    settle(qtbot, v, v.editor.toPlainText())
    qtbot.waitUntil(lambda: "4.15" in card.sentence.text(), timeout=WAIT_MS)
    (_k, field), = v.view.items[("charge", 1)].condition_fields
    type_into(qtbot, field.line, "0.05")                 # a second edit, with a rewritten statement
    after_first = LIPO_TEXT.replace("CONSTANT_V=4.2S", "CONSTANT_V=4.15S")
    assert v.editor.toPlainText() == after_first.replace("IF(I<0.1A) STOP_FAZE()", "IF(I<0.05A) STOP_FAZE")
    v.editor.undo()                                      # one undo: exactly the second edit
    assert v.editor.toPlainText() == after_first
    v.editor.undo()
    assert v.editor.toPlainText() == LIPO_TEXT
    qtbot.waitUntil(lambda: "4.2\u00a0V/cell" in v.view.items[("charge", 1)].sentence.text(), timeout=WAIT_MS)
    assert v.view.items[("charge", 1)].action_fields[0][2].value_text() == "4.2S"


def test_ctrl_z_in_the_visual_editor_undoes_the_last_card_edit(visual, qtbot):
    v = visual()
    assert v.view.move_item(("charge", 1), -1)
    moved = v.editor.toPlainText()
    assert moved != LIPO_TEXT
    settle(qtbot, v, moved)
    card = v.view.items[("charge", 0)]
    card.setFocus()
    qtbot.keyClick(card, Qt.Key.Key_Z, Qt.KeyboardModifier.ControlModifier)
    assert v.editor.toPlainText() == LIPO_TEXT
    settle(qtbot, v, LIPO_TEXT)
    qtbot.waitUntil(lambda: v.view.items[("charge", 0)].action_combo.currentData() == "CONSTANT_I", timeout=WAIT_MS)
    qtbot.keyClick(v.view, Qt.Key.Key_Z, Qt.KeyboardModifier.ControlModifier | Qt.KeyboardModifier.ShiftModifier)
    assert v.editor.toPlainText() == moved


# -- reordering -----------------------------------------------------------------------------------

def _swapped_lipo():
    lines = LIPO_TEXT.split("\n")
    return "\n".join(lines[:9] + lines[13:17] + lines[9:13] + lines[17:])


def test_reordering_phases_by_drop_changes_the_byte_code(window_with_visual, qtbot):
    w, view = window_with_visual()
    before = w.validator.last.record
    assert view.drop_item(("charge",), 0, 1)          # what the column's drop handler calls
    assert w.editor.toPlainText() == _swapped_lipo()
    qtbot.waitUntil(lambda: w.validator.last.record == record(_swapped_lipo()), timeout=3000)
    assert w.validator.last.record != before
    qtbot.waitUntil(lambda: view.items[("charge", 0)].action_combo.currentData() == "CONSTANT_V", timeout=WAIT_MS)


def _drop(widget, target_y, path):
    data = QMimeData()
    data.setData(MIME, encode_path(path))
    pos = QPointF(widget.width() / 2, target_y)
    enter = QDragEnterEvent(pos.toPoint(), Qt.DropAction.MoveAction, data, Qt.MouseButton.LeftButton,
                            Qt.KeyboardModifier.NoModifier)
    QApplication.sendEvent(widget, enter)
    accepted = enter.isAccepted()
    drop = QDropEvent(pos, Qt.DropAction.MoveAction, data, Qt.MouseButton.LeftButton, Qt.KeyboardModifier.NoModifier)
    QApplication.sendEvent(widget, drop)
    return accepted


def test_a_drop_event_on_the_column_reorders(visual, qtbot):
    v = visual()
    column = v.view.columns["charge"]
    second = v.view.items[("charge", 1)]
    below_second = second.mapTo(column, QPoint(0, second.height())).y() + 2
    assert _drop(column, below_second, ("charge", 0))
    assert v.editor.toPlainText() == _swapped_lipo()
    # a drag from another section is not taken
    settle(qtbot, v, _swapped_lipo())
    assert not _drop(v.view.columns["charge"], 5, ("discharge", 0))
    assert v.editor.toPlainText() == _swapped_lipo()


def test_the_move_buttons_are_a_mouse_path(visual, qtbot):
    v = visual()
    first = v.view.items[("charge", 0)]
    assert not first.up.isEnabled() and first.down.isEnabled()
    qtbot.mouseClick(first.down, Qt.MouseButton.LeftButton)
    assert v.editor.toPlainText() == _swapped_lipo()
    settle(qtbot, v, _swapped_lipo())
    qtbot.waitUntil(lambda: v.view.items[("charge", 1)].action_combo.currentData() == "CONSTANT_I", timeout=WAIT_MS)
    qtbot.mouseClick(v.view.items[("charge", 1)].up, Qt.MouseButton.LeftButton)
    assert v.editor.toPlainText() == LIPO_TEXT


def test_clicking_a_card_puts_the_cursor_on_its_faze_line(visual, qtbot):
    v = visual()
    v.editor.goto(1)
    card = v.view.items[("charge", 1)]
    qtbot.mouseClick(card.sentence, Qt.MouseButton.LeftButton)
    assert v.editor.current_line() == 14
    assert v.editor.textCursor().block().text().strip() == "FAZE"


# -- cycles ---------------------------------------------------------------------------------------

def _action(menu, text):
    (action,) = [a for a in menu.actions() if a.text() == text]
    return action


def test_wrap_in_cycle_from_the_card_menu_then_count_then_unwrap(visual, qtbot):
    v = visual()
    card = v.view.items[("charge", 1)]
    menu = card._menu()
    assert not _action(menu, "Remove from cycle").isEnabled()
    _action(menu, "Wrap in cycle").trigger()
    text = v.editor.toPlainText()
    assert "    CYCLE(2)\n      FAZE\n      CONSTANT_V=4.2S\n" in text and "      END_FAZE\n    END_CYCLE\n" in text
    settle(qtbot, v, text)
    box = v.view.items[("charge", 1)]
    assert isinstance(box, CycleBox) and box.count.value() == 2
    assert isinstance(v.view.items[("charge", 1, 0)], PhaseCard)
    assert bytes([ops.CYCLE.code, 2]) in v.validator.last.record

    box.count.setValue(4)                      # the arrows: applied at once
    assert "CYCLE(4)" in v.editor.toPlainText()
    assert compile_source(v.editor.toPlainText()).macro.charge.items[1].count.raw == 4
    settle(qtbot, v, v.editor.toPlainText())

    qtbot.mouseClick(v.view.items[("charge", 1)].unwrap_button, Qt.MouseButton.LeftButton)
    assert v.editor.toPlainText() == LIPO_TEXT
    settle(qtbot, v, LIPO_TEXT)
    assert not any(isinstance(w, CycleBox) for w in v.view.items.values())


def test_remove_from_cycle_in_the_card_menu(visual, qtbot):
    text = LIPO_TEXT.replace("  CHARGE_SECTION\n", "  CHARGE_SECTION\n    CYCLE(3)\n").replace(
        "  END_SECTION\n  MUSIC", "    END_CYCLE\n  END_SECTION\n  MUSIC")
    v = visual(text)
    inner = v.view.items[("charge", 0, 1)]
    assert inner.in_cycle
    _action(inner._menu(), "Remove from cycle").trigger()
    m = compile_source(v.editor.toPlainText()).macro
    assert isinstance(m.charge.items[0], Cycle) and len(m.charge.items[0].items) == 1
    assert ve.action_key(m.charge.items[1]) == "CONSTANT_V"


# -- conditions -----------------------------------------------------------------------------------

def test_add_and_remove_a_condition(visual, qtbot):
    v = visual()
    card = v.view.items[("charge", 0)]
    (timer,) = [a for a in card.add_menu.actions() if a.data() == 88]
    timer.trigger()
    text = v.editor.toPlainText()
    assert "    IF(V>4.1S) STOP_FAZE()\n    IF(tf>2h) STOP_FAZE\n    END_FAZE\n" in text
    settle(qtbot, v, text)
    card = v.view.items[("charge", 0)]
    assert [f.value_text() for _, f in card.condition_fields] == ["4.1S", "2h"]
    assert card.sentence.text().replace("\u00a0", " ").endswith("until V > 4.1 V/cell or 2 h")
    assert 88 not in {a.data() for a in card.add_menu.actions()}
    remove = card.grid.itemAtPosition(card.grid.rowCount() - 1, 2).widget()
    qtbot.mouseClick(remove, Qt.MouseButton.LeftButton)
    assert v.editor.toPlainText() == LIPO_TEXT


def test_removing_the_only_action_is_refused(visual, qtbot):
    v = visual()
    assert not v.view.remove_statement(("charge", 1, "st", 0))
    assert v.editor.toPlainText() == LIPO_TEXT
    assert "no action" in v.view.status.text()


def test_changing_the_action_kind(visual, qtbot):
    v = visual()
    card = v.view.items[("charge", 0)]
    index = card.action_combo.findData("CC-CV")
    card.action_combo.setCurrentIndex(index)
    card.action_combo.activated.emit(index)
    assert "    CONSTANT_I=INPUT\n    CONSTANT_V=4.2S\n" in v.editor.toPlainText()
    settle(qtbot, v, v.editor.toPlainText())
    assert v.view.items[("charge", 0)].sentence.text().startswith("CC-CV")


# -- introduction ---------------------------------------------------------------------------------

def test_declarations_from_the_form(visual, qtbot):
    v = visual()
    form = v.view.intro
    form.series.setValue(3)                  # arrows/wheel: applied at once
    assert "  AKK_TYPE=LiPo\n  SERIES=3\n" in v.editor.toPlainText()
    settle(qtbot, v, v.editor.toPlainText())
    index = form.capacity_mode.findData("mAh")
    form.capacity_mode.setCurrentIndex(index)
    form.capacity_mode.activated.emit(index)
    assert "  SERIES=3\n  CAPACITY=1000\n" in v.editor.toPlainText()
    settle(qtbot, v, v.editor.toPlainText())
    index = form.akk.findData("LiIon")
    form.akk.setCurrentIndex(index)
    form.akk.activated.emit(index)
    assert "AKK_TYPE=LiIon" in v.editor.toPlainText()
    settle(qtbot, v, v.editor.toPlainText())
    (tm,) = [a for a in form.add_limit_menu.actions() if a.data() == 87]
    tm.trigger()
    assert "  IF(tm>6h) STOP_MACRO\n" in v.editor.toPlainText()
    settle(qtbot, v, v.editor.toPlainText())
    assert len(form.chips) == 1


# -- invalid text ---------------------------------------------------------------------------------

def test_invalid_text_greys_the_cards_under_a_banner_and_blocks_editing(visual, qtbot):
    v = visual()
    cursor = v.editor.document().find("CONSTANT_V=4.2S")
    cursor.insertText("CONSTANT_V=4.2")               # a voltage without its unit: an error
    qtbot.waitUntil(lambda: v.view.banner.isVisible(), timeout=WAIT_MS)
    assert v.view.is_stale()
    assert "showing the last valid version" in v.view.banner.text()
    assert not v.view.content.isEnabled() and not v.view.intro.isEnabled()
    card = v.view.items[("charge", 1)]
    assert "4.2\u00a0V/cell" in card.sentence.text()         # the last valid version
    assert not card.isEnabled()
    broken = v.editor.toPlainText()
    assert not v.view.move_item(("charge", 1), -1)
    assert v.editor.toPlainText() == broken
    cursor = v.editor.document().find("CONSTANT_V=4.2")
    cursor.insertText("CONSTANT_V=4.25S")
    qtbot.waitUntil(lambda: not v.view.banner.isVisible(), timeout=WAIT_MS)
    assert v.view.content.isEnabled() and v.view.items[("charge", 1)].isEnabled()
    assert "4.25" in v.view.items[("charge", 1)].sentence.text()


def test_a_macro_that_never_was_valid_shows_only_the_banner(visual, qtbot):
    v = visual("MACRO X\n  FAZE\n")
    assert v.view.banner.isVisible() and "no valid version" in v.view.banner.text()
    assert not v.view.items


# -- phases and layout ----------------------------------------------------------------------------

def test_add_and_delete_a_phase(visual, qtbot):
    v = visual()
    qtbot.mouseClick(v.view.columns["discharge"].add_phase, Qt.MouseButton.LeftButton)
    settle(qtbot, v, v.editor.toPlainText())
    assert ("discharge", 1) in v.view.items
    _action(v.view.items[("discharge", 1)]._menu(), "Delete phase").trigger()
    assert v.editor.toPlainText() == LIPO_TEXT


def test_readable_at_700_by_600(visual, qtbot):
    v = visual(size=(700, 600))
    QApplication.processEvents()
    bar: QScrollBar = v.view.scroll.horizontalScrollBar()
    assert bar.maximum() == 0                          # nothing sticks out sideways
    for card in cards(v.view):
        assert card.width() >= card.minimumSizeHint().width()
        assert card.sentence.height() >= card.sentence.heightForWidth(card.sentence.width()) - 1


def test_pulling_a_card_starts_a_drag_of_its_path(visual, qtbot, monkeypatch):
    v = visual()
    card = v.view.items[("charge", 1)]
    started = []
    monkeypatch.setattr(card, "start_drag", lambda: started.append(card.mime()))
    press = QPoint(10, card.sentence.height() // 2)
    qtbot.mousePress(card.sentence, Qt.MouseButton.LeftButton, pos=press)
    qtbot.mouseMove(card.sentence, press + QPoint(0, 40))
    qtbot.mouseRelease(card.sentence, Qt.MouseButton.LeftButton, pos=press + QPoint(0, 40))
    assert len(started) == 1
    assert started[0].hasFormat(MIME) and bytes(started[0].data(MIME)) == encode_path(("charge", 1))
    assert v.editor.toPlainText() == LIPO_TEXT            # a drag is not a click: nothing changed
