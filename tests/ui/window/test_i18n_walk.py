"""ZUML Studio in Russian (issue 17): with the Russian catalogue installed before the window is
built, every visible text of the main window (docks, menus, actions, tooltips, status bar) and of
its dialogs has Cyrillic in it, but for what is never translated (keywords, units, numbers, file
names, chemistry names, key names); and at 1366x768 nothing of it is cut off (the widgets' own
font metrics and size hints decide, never a particular font)."""
from __future__ import annotations

import pytest
from PySide6.QtCore import QEventLoop, QTimer
from PySide6.QtWidgets import QDialog, QMainWindow, QMessageBox, QPushButton

from helpers import MACROS, ROOT
from window_checks import clipped, english, untranslated, walk
from zuml_studio import i18n
from zuml_studio.lang import opcodes
from zuml_studio.ui.device import confirm_dialogs, unsafe_dialog

CURVES = ROOT / "tests" / "data" / "curves"
LOGS = ROOT / "tests" / "data" / "logs"


def _settle(ms: int = 150) -> None:
    loop = QEventLoop()
    QTimer.singleShot(ms, loop.quit)
    loop.exec()


# -- fixtures ------------------------------------------------------------------------------------

@pytest.fixture
def russian(qapp):
    """The Russian catalogue (compiled by ./dev from the .po) and Qt's, installed before the
    window is built, as the application does at start."""
    from zuml_studio.ui.base.language import install_qt_catalogue

    i18n.install("ru")
    install_qt_catalogue("ru")
    yield
    i18n.install("en")
    install_qt_catalogue("en")


@pytest.fixture
def message_boxes(monkeypatch):
    """Every QMessageBox a test makes is shown, walked and answered Cancel instead of waiting."""
    seen: list[tuple[list, list]] = []

    def exec_(box):
        box.show()
        _settle(50)
        seen.append((walk(box), clipped(box)))
        box.hide()
        return QMessageBox.StandardButton.Cancel
    monkeypatch.setattr(QMessageBox, "exec", exec_)
    return seen


@pytest.fixture
def window(russian, make_window, qtbot):
    w = make_window(str(MACROS / "NiMh.zuml"))
    w.resize(1366, 768)
    w.device_panel              # built now, not by its timer in the middle of a walk (a loaded machine)
    qtbot.waitUntil(lambda: w.size().width() == 1366)
    w.sim_panel.simulate()
    assert w.sim_panel.wait(60_000)
    _settle()
    return w


def _views(w: QMainWindow):
    """The window with each tabified dock in front in turn (and the Visual tab with its cards)."""
    yield "editor side"
    w.show_visual()
    _settle()
    yield "visual tab"
    w.hex_dock.raise_()
    w.device_dock.raise_()
    _settle()
    yield "device tab"
    w.sim_dock.raise_()
    w.editor.show_find(True)
    _settle()
    yield "find bar"


# -- the tests --------------------------------------------------------------------------------

def test_the_russian_catalogue_is_the_one_installed(russian):
    assert i18n.current_language() == "ru"
    assert i18n._("&File") == "&Файл"
    assert i18n.ngettext("{n} warning", "{n} warnings", 21).format(n=21) == "21 предупреждение"
    assert i18n.ngettext("{n} warning", "{n} warnings", 3).format(n=3) == "3 предупреждения"
    assert i18n.ngettext("{n} warning", "{n} warnings", 5).format(n=5) == "5 предупреждений"


def test_the_allow_list_lets_through_only_what_is_never_translated():
    for text in ("CONSTANT_I=INPUT", "2000 mAh", "× 3", "NiMh-dV", "0:15", "LiPo.zuml", "E303", "Ctrl+Shift+N",
                 "4 V/cell", "ZUML Studio", "—", "/tmp/x/NiMh.zuml"):
        assert not untranslated(text), text
    for text in ("Simulate", "Open Log…", "cells", "from AKK_TYPE", "2000 mAh model"):
        assert untranslated(text), text


def test_every_text_of_the_main_window_is_russian(window, message_boxes):
    texts = []
    for _view in _views(window):
        texts += walk(window)
    window.editor.setPlainText("MACRO X\n  FAZE\nEND_MACRO\n")
    window.validate_now()
    window.export_record()              # the macro has errors: a (non-modal) error box
    _settle()
    for box in window.findChildren(QMessageBox, "errorBox"):
        texts += walk(box)
    window.statusBar().showMessage(window.statusBar().currentMessage())
    texts.append(("status bar message", window.statusBar().currentMessage()))
    window.ask_unsaved()
    texts += [t for walked, _cut in message_boxes for t in walked]
    assert any("Сохранить" in text for _where, text in texts), "Qt's own buttons are not in Russian"
    found = english(texts)
    assert not found, "\n".join(found)


def test_nothing_of_the_main_window_is_cut_off_in_russian_at_1366x768(window):
    problems = []
    for view in _views(window):
        problems += [f"{view}: {p}" for p in clipped(window)]
    assert not problems, "\n".join(problems)


def _dialogs(w: QMainWindow, qtbot):
    """Each dialog of the window, built as the window builds it, with something in it."""
    from zuml_studio.ui.editor.help_browser import HelpBrowser
    from zuml_studio.ui.plots.plot_export import PlotExportDialog
    from zuml_studio.ui.window.preferences import PreferencesDialog
    from zuml_studio.ui.sim.compare_dialog import CompareDialog
    from zuml_studio.ui.visual import NewMacroWizard

    yield "preferences", PreferencesDialog(w.prefs, w.editor.font_size(), w)
    yield "wizard", NewMacroWizard(w)
    wizard = NewMacroWizard(w)
    wizard.rate.setText("lots")
    yield "wizard with a bad answer", wizard
    compare = CompareDialog(w.sim_panel.current_record, w)
    assert compare.load_log(str(CURVES / "lipo_4s_406duo_3c.csv"))
    with qtbot.waitSignal(compare.workDone, timeout=120_000):
        compare.compare_macro()
    yield "compare with log", compare
    yield "plot export", PlotExportDialog("NiMh", w)
    help_browser = HelpBrowser(w)
    help_browser.show_ops((opcodes.BY_KEYWORD["CONSTANT_I"],))
    yield "command reference", help_browser
    log_window = w.open_log(str(LOGS / "X8_LiPo_5S_2200mA_Charge_4.txt"))
    yield "log window", log_window


def test_every_dialog_is_russian_and_cuts_nothing_off(window, qtbot, message_boxes):
    problems, english_texts = [], []
    for name, dialog in _dialogs(window, qtbot):
        if isinstance(dialog, QDialog):
            qtbot.addWidget(dialog)
        dialog.show()
        _settle()
        english_texts += [f"{name}: {line}" for line in english(walk(dialog))]
        problems += [f"{name}: {p}" for p in clipped(dialog)]
        dialog.close()
    window.ask_recover(type("Found", (), {"original": "/tmp/a/NiMh.zuml"})())
    window.ask_restart()
    for walked, cut in message_boxes:
        english_texts += english(walked)
        problems += cut
    assert not english_texts, "\n".join(english_texts)
    assert not problems, "\n".join(problems)


# The real questions, taken before tests/ui/conftest.py replaces them for every test.
REAL_CONFIRM_RESTORE = confirm_dialogs.confirm_restore
REAL_CONFIRM_WARNINGS = unsafe_dialog.confirm_warnings


@pytest.mark.parametrize("which", ["confirm_dialogs", "unsafe_dialog"])
def test_the_device_confirmations_are_russian_and_cut_nothing_off(russian, qtbot, message_boxes, which):
    if which == "confirm_dialogs":
        REAL_CONFIRM_RESTORE(None, confirm_dialogs.restore_text("backup.bin", ["NiMh", "LiPo"], ["NiMh"]))
        confirm_dialogs.ask_close_during_run(None, "NiMh", True)
    else:
        REAL_CONFIRM_WARNINGS(None, "Записать", ["W303: 4.30 V per cell, above LiIon's usual 4.20 V"])
    assert message_boxes
    for walked, cut in message_boxes:
        assert not english(walked), "\n".join(english(walked))
        assert not cut, "\n".join(cut)


def test_the_walk_and_the_clipping_check_are_not_blind(make_window, qtbot):
    """In English the same walk finds the English texts (menus, docks, buttons, tooltips), and a
    dialog squeezed below its size has its texts reported cut."""
    from zuml_studio.ui.window.preferences import Preferences, PreferencesDialog

    w = make_window(str(MACROS / "NiMh.zuml"))
    found = "\n".join(english(walk(w)))
    for text in ("'&File'", "'Library'", "'Simulate'", "'Auto re-simulate'",
                 "'Run the macro against the battery model (F5)'", "'Line:Col'"):
        assert text in found, text
    dialog = PreferencesDialog(Preferences(), 10)
    qtbot.addWidget(dialog)
    dialog.theme.setFixedWidth(40)
    dialog.font_size.setFixedWidth(20)
    dialog.findChild(QPushButton).setFixedWidth(12)
    dialog.show()
    _settle()
    cut = "\n".join(clipped(dialog))
    for what in ("prefTheme", "prefFontSize", "QPushButton"):
        assert what in cut, cut
