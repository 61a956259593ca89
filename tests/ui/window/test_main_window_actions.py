"""Menus, shortcuts and the Arduino-style actions of the main window."""
from pathlib import Path

from PySide6.QtCore import QPoint, QPointF, Qt
from PySide6.QtGui import QKeySequence, QWheelEvent

from helpers import MACROS

LIPO = str(MACROS / "LiPo.zuml")


def _menu_texts(window):
    return {a.text().replace("&", ""): a for a in window.menuBar().actions()}


def test_menus_show_the_shortcuts_ctrl_y_redo_and_replace(make_window, qtbot):
    w = make_window()
    edit = _menu_texts(w)["Edit"].menu()
    shortcuts = {a.text().replace("&", ""): a.shortcut().toString() for a in edit.actions() if a.text()}
    assert shortcuts["Replace…"] == "Ctrl+H"
    assert shortcuts["Redo"] == "Ctrl+Y"
    qtbot.keyClicks(w.editor, "x")
    w.editor.undo()
    assert "x" not in w.text().splitlines()[0]
    qtbot.keyClick(w.editor, Qt.Key.Key_Y, Qt.KeyboardModifier.ControlModifier)
    assert w.text().startswith("x")


def test_toolbar_and_device_menu(make_window):
    w = make_window()
    assert [a.text().replace("&", "") for a in w.toolbar.actions() if a.text()] == \
        ["New", "Open…", "Save", "Verify", "Upload", "Simulate"]
    menus = _menu_texts(w)
    assert "Device" in menus
    device = [a.text().replace("&", "") for a in menus["Device"].menu().actions() if a.text()]
    assert {"Connect", "Disconnect", "Upload", "Start the Macro", "Stop the Charger"} <= set(device)
    assert w.act_verify.shortcut() == QKeySequence("Ctrl+R")
    assert w.act_upload.shortcut() == QKeySequence("Ctrl+U")


def test_verify_reports_in_the_status_bar(make_window):
    w = make_window(LIPO)
    assert w.verify()
    assert w.statusBar().currentMessage().startswith("Verified:")
    w.editor.setPlainText(Path(LIPO).read_text().replace("END_MACRO", ""))
    assert not w.verify()
    assert "error" in w.statusBar().currentMessage()


def test_upload_connects_then_runs_the_panels_compile_and_flash(make_window, qtbot):
    w = make_window(LIPO)
    panel = w.device_panel
    with qtbot.waitSignal(panel.flashFinished, timeout=30_000) as flashed:
        w.upload()
    assert flashed.args[0], flashed.args
    assert panel.slot_names() == ["LiPo"]


def test_zoom_by_actions_and_ctrl_wheel_is_remembered(make_window, tmp_path):
    config = tmp_path / "zoom-config"
    w = make_window(None, config)
    size = w.editor.font_size()
    w.act_zoom_in.trigger()
    w.act_zoom_in.trigger()
    assert w.editor.font_size() == size + 2
    w.act_zoom_out.trigger()
    assert w.editor.font_size() == size + 1
    viewport = w.editor.viewport()
    wheel = QWheelEvent(QPointF(10, 10), QPointF(viewport.mapToGlobal(QPoint(10, 10))), QPoint(0, 0), QPoint(0, 120),
                        Qt.MouseButton.NoButton, Qt.KeyboardModifier.ControlModifier, Qt.ScrollPhase.NoScrollPhase,
                        False)
    w.editor.wheelEvent(wheel)
    assert w.editor.font_size() == size + 2
    assert {s.toString() for s in w.act_zoom_in.shortcuts()} >= {"Ctrl+="}
    assert w.act_zoom_out.shortcut().toString() == "Ctrl+-"
    assert w.close()
    again = make_window(None, config)
    assert again.editor.font_size() == size + 2
    again.act_zoom_reset.trigger()
    assert again.editor.font_size() == again.editor.default_font_size()


def test_f1_opens_help_on_the_command_under_the_cursor_and_it_searches(make_window):
    w = make_window(LIPO)
    w.editor.goto(5, 8)                                 # inside CONSTANT_I=1C
    w.act_reference.trigger()
    browser = w._help
    assert browser.isVisible()
    assert browser.shown_title() == "CONSTANT_I=I"
    page = browser.page.toPlainText()
    assert "Hold the current" in page and "do not edit" not in page
    browser.search.setText("pulse")
    assert browser.visible_titles() == ["CHARGE_EX(tch, Ich, tdis, Idis, [tV])"]
    assert browser.shown_title().startswith("CHARGE_EX")
    w.editor.goto(12, 5)                                # IF(V>4.1S) STOP_FAZE
    w.act_reference.trigger()
    assert browser.shown_title() == "IF(V>x) STOP_FAZE"
    assert len(browser.visible_titles()) > 20            # the search was cleared


def test_about_names_the_version(make_window):
    from importlib.metadata import version

    w = make_window()
    assert version("zuml-studio") in w.about_text()
