"""The device column on a laptop: the wheel scrolls the column, not the box under the pointer; a
refusal is one line above Backup/Restore (the reasons in the message line, one paragraph); the
charger's "balance lead 3 cells" said with the count the PC asked for."""
from PySide6.QtCore import QPoint, QPointF, Qt
from PySide6.QtGui import QWheelEvent
from PySide6.QtWidgets import QApplication

from zuml_studio.device.errors import DeviceError
from zuml_studio.sim.reasons import lead_cells_text
from zuml_studio.ui.device.connection import describe_error


def wheel(widget, down: bool = True) -> None:
    at = QPointF(widget.width() / 2, widget.height() / 2)
    event = QWheelEvent(at, widget.mapToGlobal(at), QPoint(), QPoint(0, -120 if down else 120),
                        Qt.MouseButton.NoButton, Qt.KeyboardModifier.NoModifier, Qt.ScrollPhase.NoScrollPhase, False)
    QApplication.sendEvent(widget, event)


def test_the_wheel_over_a_box_scrolls_the_column_until_the_box_is_clicked(qtbot, make_panel):
    panel = make_panel((1366, 200))             # a low dock: the column scrolls
    scroll = panel.controls_scroll
    qtbot.waitUntil(lambda: scroll.verticalScrollBar().maximum() > 0)
    task = panel.run.task
    before = task.currentIndex()
    wheel(task)
    assert task.currentIndex() == before and scroll.verticalScrollBar().value() > 0
    task.setFocus()
    qtbot.waitUntil(task.hasFocus)
    wheel(task)                                 # the user clicked it: the wheel is the box's
    assert task.currentIndex() != before


def test_a_refusal_is_one_line_in_the_charger_column_and_one_paragraph_below():
    from zuml_studio.ui.device.device_style import MessageLine
    from zuml_studio.ui.device.unsafe_dialog import refusal_text
    text = refusal_text("Not flashed", ["E303: 4.50 V per cell is above LiPo's 4.20 V", "E304: 2.5 V per cell"])
    assert text.count("\n") >= 3
    line = MessageLine()
    line.say(text, "error")
    assert "\n" not in line.text() and "E303" in line.text() and "E304" in line.text()
    assert line.full_text == text


def test_a_refused_flash_leaves_backup_and_restore_in_view(qtbot, make_panel, monkeypatch):
    panel = make_panel((1366, 360))
    text = "Not flashed: the safety check refused it:\n• E303: a\n• E304: b\n• E305: c\nZUML Studio never sends it"
    panel.charger._flash_done(False, text)
    assert panel.result_label.text() == "Not flashed: the safety check refused it:"
    assert panel.result_label.toolTip() == text


def test_balance_lead_is_said_with_the_cells_entered_or_declared():
    assert lead_cells_text("balance lead 3 cells", 4, 0) == "you entered 4 cells; the balance lead shows 3"
    assert lead_cells_text("balance lead 3 cells", 4, 2) == \
        "the macro declares 2 cells (SERIES); the balance lead shows 3"
    assert lead_cells_text("balance lead 3 cells", 0, 0) == "balance lead 3 cells"      # nothing known: as said
    assert lead_cells_text("no battery", 4, 0) == "no battery"
    refused = DeviceError(17, "balance lead 3 cells")
    refused.lines = [lead_cells_text(line, 4, 0) for line in refused.lines]
    assert "you entered 4 cells; the balance lead shows 3" in describe_error(refused, "start")


def test_a_run_ended_by_the_balance_lead_says_the_cells_entered(qtbot, make_panel):
    """A live end reason from the charger ("protection: balance lead 3 cells") in the device panel's
    message says what the user entered at start, in words."""
    from zuml_studio.protocol.messages import DeviceEvent
    panel = make_panel((1366, 360))
    said = []
    panel.run.message.connect(lambda text, _kind: said.append(text))
    panel.run.run_name, panel.run.run_cells = "LiPo", (4, 0)
    panel.run.follow(None, None, [(DeviceEvent(7, 65.0, "finish", detail="protection: balance lead 3 cells"), None)])
    assert said == ["LiPo finished at 0:01:05: protection: you entered 4 cells; the balance lead shows 3."]


def test_the_virtual_battery_note_reads_whole_where_the_row_has_room(qtbot, make_panel, editor):
    """At 1500 px (a 1920x1080 screen's first window) the battery's note beside the virtual charger's
    fields is whole, not "LiPo 4S…" beside a "not connected" standing in hundreds of pixels of its own."""
    editor.set("LiPo")
    panel = make_panel((1500, 380))
    note, info = panel.bar.battery_note, panel.bar.info_label
    panel.virtual_battery()                 # as a change of the battery's choice or of the macro does
    qtbot.waitUntil(lambda: note.isVisible() and note.full_text() != "")
    def whole():
        assert note.text() == note.full_text(), (note.text(), note.width(), panel.bar.virtual_box.width())
    qtbot.waitUntil(whole)
    assert info.text() == info.full_text(), info.text()
