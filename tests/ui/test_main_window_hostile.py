"""The main window against hostile text and crashes (issue 12, points 2 and 7)."""
from PySide6.QtCore import Qt
from PySide6.QtGui import QTextCursor

from helpers import MACROS

LIPO = str(MACROS / "LiPo.zuml")


def _codes(window):
    return [window.problems.topLevelItem(i).text(3) for i in range(window.problems.topLevelItemCount())]


def test_a_29_digit_number_is_a_range_error_not_a_stale_ok(make_window, qtbot):
    w = make_window(LIPO)
    assert "valid" in w.state_label.text()
    cursor = w.editor.document().find("AKK_TYPE=LiPo")
    cursor.movePosition(QTextCursor.MoveOperation.EndOfLine)
    cursor.insertText("\n  CAPACITY=" + "9" * 29)
    qtbot.waitUntil(lambda: "E204" in _codes(w), timeout=5000)
    assert "✖" in w.state_label.text()
    assert w._current_record() is None


def test_a_check_that_fails_never_leaves_the_last_result_standing(make_window, qtbot, monkeypatch):
    import zuml_studio.ui.validation as validation
    w = make_window(LIPO)
    assert "valid" in w.state_label.text()

    def broken(text, **kw):
        raise ArithmeticError("boom")
    monkeypatch.setattr(validation, "compile_source", broken)
    qtbot.keyClicks(w.editor, " ")
    qtbot.waitUntil(lambda: "E000" in _codes(w), timeout=5000)
    assert "✖" in w.state_label.text() and w._current_record() is None
    with qtbot.waitSignal(w.device_panel.flashFinished, timeout=5000) as flashed:
        w.device_panel.flash()
    assert flashed.args[0] is False


def test_every_debounced_change_reaches_the_recovery_file(make_window, qtbot):
    w = make_window(LIPO)
    w.editor.moveCursor(QTextCursor.MoveOperation.End)
    qtbot.keyClicks(w.editor, "// typed just now")
    recovery = w.recovery.root / f"{w._recovery_key}.zuml"
    # Well before any periodic autosave: the debounced check (250 ms) writes it.
    qtbot.waitUntil(lambda: recovery.exists() and recovery.read_text().endswith("// typed just now"),
                    timeout=2000)
    qtbot.keyClick(w.editor, Qt.Key.Key_Backspace)
    qtbot.waitUntil(lambda: recovery.read_text().endswith("// typed just no"), timeout=2000)
    assert not list(w.recovery.root.glob(".*.tmp"))          # written beside, renamed over: no leftovers
    w.editor.document().setModified(False)


def test_a_recovery_folder_that_cannot_be_written_is_said_once_not_raised(make_window, qtbot):
    w = make_window(LIPO)
    w.recovery.root.parent.mkdir(parents=True, exist_ok=True)
    w.recovery.root.write_text("a file where the folder should be")
    qtbot.keyClicks(w.editor, " ")
    qtbot.waitUntil(lambda: "Crash recovery cannot write" in w.statusBar().currentMessage(), timeout=5000)
    w.editor.document().setModified(False)


def test_compile_and_flash_of_a_macro_past_its_chemistry_asks_naming_the_danger(make_window, qtbot,
                                                                                  monkeypatch, tmp_path):
    from helpers import HOT_LIION
    from zuml_studio.ui.device import unsafe_dialog
    path = tmp_path / "hot.zuml"
    path.write_text(HOT_LIION)
    w = make_window(str(path))
    assert "E303" in _codes(w)
    asked = []
    monkeypatch.setattr(unsafe_dialog, "confirm_unsafe", lambda parent, action, problems:
                        asked.append(problems) or len(asked) > 1)      # cancel, then go ahead
    panel = w.device_panel
    with qtbot.waitSignal(panel.connectedChanged, timeout=30_000):
        panel.connect_to("virtual")
    qtbot.waitUntil(lambda: not panel.connection.busy, timeout=30_000)
    with qtbot.waitSignal(panel.flashFinished, timeout=30_000) as flashed:
        panel.flash()
    assert flashed.args[0] is False and "E303" in flashed.args[1]
    assert any("4.96 V per cell" in p for p in asked[0])
    with qtbot.waitSignal(panel.flashFinished, timeout=30_000) as flashed:
        panel.flash()
    assert flashed.args[0] is True, flashed.args[1]
    assert panel.slot_names() == ["Hot"]
