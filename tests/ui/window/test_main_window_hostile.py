"""The main window against hostile text and crashes (issue 12, points 2 and 7)."""
from PySide6.QtCore import Qt
from PySide6.QtGui import QTextCursor

from helpers import MACROS, WAIT_MS

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
    import zuml_studio.ui.editor.validation as validation
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
                    timeout=WAIT_MS)
    qtbot.keyClick(w.editor, Qt.Key.Key_Backspace)
    qtbot.waitUntil(lambda: recovery.read_text().endswith("// typed just no"), timeout=WAIT_MS)
    assert not list(w.recovery.root.glob(".*.tmp"))          # written beside, renamed over: no leftovers
    w.editor.document().setModified(False)


def test_a_recovery_folder_that_cannot_be_written_is_said_once_not_raised(make_window, qtbot):
    w = make_window(LIPO)
    w.recovery.root.parent.mkdir(parents=True, exist_ok=True)
    w.recovery.root.write_text("a file where the folder should be")
    qtbot.keyClicks(w.editor, " ")
    qtbot.waitUntil(lambda: "Crash recovery cannot write" in w.statusBar().currentMessage(), timeout=5000)
    w.editor.document().setModified(False)


def test_compile_and_flash_of_a_macro_past_its_chemistry_is_refused_in_words(make_window, qtbot, tmp_path):
    from helpers import HOT_LIION
    path = tmp_path / "hot.zuml"
    path.write_text(HOT_LIION)
    w = make_window(str(path))
    assert "E303" in _codes(w)
    panel = w.device_panel
    w.upload()          # not connected: Upload stops at the macro's errors and the Device tab says why
    assert panel.message_text().startswith("Not uploaded: the safety check refused it:")
    assert "4.96 V per cell" in panel.message_text() and "pick a port" not in panel.message_text().lower()
    with qtbot.waitSignal(panel.connectedChanged, timeout=30_000):
        panel.connect_to("virtual")
    qtbot.waitUntil(lambda: not panel.connection.busy, timeout=30_000)
    for _attempt in range(2):           # no dialog offers to go ahead: the same answer every time
        with qtbot.waitSignal(panel.flashFinished, timeout=30_000) as flashed:
            panel.flash()
        assert flashed.args[0] is False and flashed.args[1].startswith("Not flashed: the safety check refused it:")
        assert "4.96 V per cell" in flashed.args[1]
    assert panel.slot_names() == []


HOSTILE_SETTINGS = (  # findings of benchmarks/fuzz_files.py: each of these killed the window at start or on Open
    "[General]\n"
    "geometry=not a byte array\n"            # a string: restoreGeometry raised TypeError
    "windowState=1, 2\n"                     # a list: restoreState raised TypeError
    "lastDir=/home/u/a, /home/u/b\n"         # a comma: QSettings reads a list, QFileDialog raised TypeError
    "lastOpen=@Invalid()\n"
    "recentFiles=@Variant(\\0\\0\\0\\x7f\\0\\0)\n"
    "lastLogDir=1, 2, 3\n"
    "[editor]\nfontSize=nan\n[appearance]\ntheme=1, 2\nlanguage=@ByteArray(ru)\n"
    "[layout]\nmode=1, 2\nwrite=1, 2\nsimulate=not a layout\n")    # a list, a string: the first layout instead


def test_a_hand_edited_settings_file_with_garbage_values_reads_as_defaults(make_window, tmp_path, monkeypatch):
    config = tmp_path / "config"
    config.mkdir()
    (config / "settings.ini").write_text(HOSTILE_SETTINGS)
    w = make_window(config=config)
    assert w.isVisible() and w.path is None
    asked = []
    monkeypatch.setattr(w, "ask_open_path", lambda title, start, filters: asked.append(start) or "")
    w.open_dialog()
    from zuml_studio.ui.window.documents import documents_dir
    assert asked == [str(documents_dir())]          # where the user keeps documents, not a hidden config folder
    from pathlib import Path

    from zuml_studio.ui.logs import LogWindow
    viewer = LogWindow(w.settings, w)
    assert viewer._folder() == str(Path.home())


def test_a_recovery_note_of_the_wrong_shape_still_offers_the_text(make_window, tmp_path):
    config = tmp_path / "config"
    (config / "recovery").mkdir(parents=True)
    (config / "recovery" / "0123456789abcdef.zuml").write_text("MACRO Lost\n")
    (config / "recovery" / "0123456789abcdef.json").write_text('[{"original": 5, "pid": 1e999}]')
    w = make_window(config=config)
    w.ask_recover = lambda found: True
    assert w.offer_recovery()
    assert w.text() == "MACRO Lost\n" and w.path is None


def test_file_open_of_a_garbage_file_says_why_and_keeps_the_window(make_window, tmp_path, qtbot):
    w = make_window(LIPO)
    before = w.text()
    for garbage, said in ((bytes(range(256)) * 4, "not UTF-8 text"), (b"MACRO x\0\0\1", "a binary file"),
                          (None, "is a folder"), (b"/dev/zero", "a device, not a file")):
        if garbage is None:
            path = tmp_path / "folder.zuml"
            path.mkdir()
        elif garbage == b"/dev/zero":
            path = garbage.decode()
        else:
            path = tmp_path / "garbage.zuml"
            path.write_bytes(garbage)
        assert not w.open_file(str(path), ask=False)
        assert said in w.statusBar().currentMessage()
        assert w.text() == before and w.isVisible()
