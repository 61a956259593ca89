"""ZUML Studio in Russian (issue 17): with the Russian catalogue installed before the window is
built, every visible text of the main window (docks, menus, actions, tooltips, status bar) and of
its dialogs has Cyrillic in it, but for what is never translated (keywords, units, numbers, file
names, chemistry names, key names); and at 1366x768 nothing of it is cut off (the widgets' own
font metrics and size hints decide, never a particular font)."""
from __future__ import annotations

import re

import pytest
from PySide6.QtCore import QEventLoop, Qt, QTimer
from PySide6.QtGui import QTextDocumentFragment
from PySide6.QtWidgets import (QAbstractButton, QAbstractItemView, QAbstractSpinBox, QCheckBox, QComboBox,
                               QDialog, QDockWidget, QGroupBox, QHeaderView, QLabel, QLineEdit, QMainWindow, QMenu,
                               QMessageBox, QPlainTextEdit, QPushButton, QRadioButton, QStyle, QStyleOptionComboBox,
                               QTableWidget, QTabBar, QToolBar, QToolButton, QTreeWidget, QWidget)

from helpers import MACROS, ROOT
from test_truncation import _cut_labels
from zuml_studio import data, i18n
from zuml_studio.lang import opcodes
from zuml_studio.lang.operands import AKK_TYPE, DISPLAY_NAMES
from zuml_studio.streams.drivers import DRIVERS
from zuml_studio.ui.device import confirm_dialogs, unsafe_dialog
from zuml_studio.ui.device.device_style import ElidedCombo, ElidedLabel
from zuml_studio.sim.charger_model import load_charger
from zuml_studio.domain.chemistry import chemistry_names



CURVES = ROOT / "tests" / "data" / "curves"
POT_TEXT = (ROOT / "resources" / "locale" / "zuml_studio.pot").read_text(encoding="utf-8")
LOGS = ROOT / "tests" / "data" / "logs"
CYRILLIC = re.compile("[а-яёА-ЯЁ]")
LATIN = re.compile("[A-Za-z]")
# What is the same in every language: keywords, opcode names and other upper-case codes (INPUT,
# CSV, E303), units, names (of chemistries, programs, file formats, keys) and file names.
UNITS = ("mAh", "mA", "mV/cell", "V/cell", "mV", "mΩ", "°C", "min", "pt", "px", "V", "A", "C", "S", "s", "h",
         "B", "T", "Tc", "dT/dt", "dV", "x", "Hz")
NAMES = ("ZUML Studio", "ZUML", "Qt", "Junsi", "iCharger", "LogView", "DataExplorer", "Ctrl", "Shift", "Enter", "Esc",
         "h:mm:ss", "h:mm", "WxH", "OUT.png", "FILE")
FILE_NAME = re.compile(r"\S+\.(zuml|bin|csv|png|txt|osd|lov|log|cap|qm)\b|(?<!\S)(/\S+)+")
UPPER_CODE = re.compile(r"\b[A-Z][A-Z0-9_]+\b")
SHORTCUT = re.compile(r"\b(?:Ctrl|Shift|Alt|Meta)(?:\+[^\s)]+)+|\bF\d+\b")


def _allowed_words() -> list[str]:
    words = set(NAMES) | set(UNITS) | set(i18n.LANGUAGES.values()) | set(chemistry_names()) | set(AKK_TYPE.names) | set(DISPLAY_NAMES.values())
    words |= {path.stem for path in data.standard_macros()}
    words |= {load_charger(name).name for name in data.names("chargers")}     # the simulator's Charger box
    words |= {op.mnemonic for op in opcodes.OPCODES} | {op.keyword for op in opcodes.OPCODES}
    # Chargers called by their makers' names alone (the titles with words are in the catalogue).
    words |= {d.title for d in DRIVERS.values() if f'msgid "{d.title}"' not in POT_TEXT}
    return sorted(words, key=len, reverse=True)


ALLOWED = re.compile("|".join(rf"(?<![\w]){re.escape(w)}(?![\w])" for w in _allowed_words()))


def untranslated(text: str) -> bool:
    """Whether a visible text is English: no Cyrillic, and Latin letters left once the
    allow-list is taken out."""
    if CYRILLIC.search(text):
        return False
    rest = UPPER_CODE.sub(" ", ALLOWED.sub(" ", FILE_NAME.sub(" ", SHORTCUT.sub(" ", text.replace("&", "")))))
    return bool(LATIN.search(rest))


def _plain(text: str) -> str:
    return QTextDocumentFragment.fromHtml(text).toPlainText() if "<" in text else text


def _settle(ms: int = 150) -> None:
    loop = QEventLoop()
    QTimer.singleShot(ms, loop.quit)
    loop.exec()


# -- the walk ----------------------------------------------------------------------------------

def _action_texts(actions, where: str) -> list[tuple[str, str]]:
    out = []
    for action in actions:
        if action.isSeparator():
            continue
        name = f"{where} ▸ {action.text().replace('&', '')}"
        for kind, text in (("text", action.text()), ("tooltip", action.toolTip()), ("status tip", action.statusTip())):
            out.append((f"{name} ({kind})", text))
        if action.menu() is not None:
            out += _action_texts(action.menu().actions(), name)
    return out


def _own_texts(w: QWidget) -> list[tuple[str, str]]:
    """The texts a widget shows itself (not its children's)."""
    texts = [("tooltip", w.toolTip()), ("status tip", w.statusTip()), ("what's this", w.whatsThis())]
    if w.isWindow() or isinstance(w, QDockWidget):
        texts.append(("title", w.windowTitle()))
    if isinstance(w, ElidedLabel):          # its whole text, wherever the width cuts it
        texts.append(("text", w.full_text()))
    elif isinstance(w, (QLabel, QAbstractButton)):
        texts.append(("text", w.text()))
    if isinstance(w, QLineEdit):
        texts.append(("placeholder", w.placeholderText()))
    if isinstance(w, QPlainTextEdit):
        texts.append(("placeholder", w.placeholderText()))
    if isinstance(w, QAbstractSpinBox):
        texts += [("prefix", w.prefix()), ("suffix", w.suffix()), ("special value", w.specialValueText())]
    if isinstance(w, QComboBox) and not w.isEditable():
        for i in range(w.count()):
            texts += [(f"item {i}", w.itemText(i)), (f"item {i} tooltip", w.itemData(i, Qt.ItemDataRole.ToolTipRole))]
    if isinstance(w, QGroupBox):
        texts.append(("title", w.title()))
    if isinstance(w, QTabBar):
        for i in range(w.count()):
            texts += [(f"tab {i}", w.tabText(i)), (f"tab {i} tooltip", w.tabToolTip(i))]
    if isinstance(w, QTreeWidget):
        header = w.headerItem()
        for c in range(w.columnCount()):
            if not w.isColumnHidden(c):
                texts += [(f"column {c}", header.text(c)), (f"column {c} tooltip", header.toolTip(c))]
    if isinstance(w, QTableWidget):
        for c in range(w.columnCount()):
            item = w.horizontalHeaderItem(c)
            if item is not None:
                texts += [(f"column {c}", item.text()), (f"column {c} tooltip", item.toolTip())]
    where = f"{type(w).__name__} {w.objectName() or w.metaObject().className()}"
    return [(f"{where} ({kind})", _plain(str(text))) for kind, text in texts if text and str(text).strip()]


def walk(root: QWidget) -> list[tuple[str, str]]:
    """Every visible text under ``root`` (menus and actions included), as (where, text)."""
    out = []
    for w in [root] + root.findChildren(QWidget):
        if not w.isVisible() or isinstance(w, QMenu):
            continue
        out += _own_texts(w)
        if isinstance(w, (QMainWindow, QToolBar)) or w.actions():
            out += _action_texts(w.actions(), type(w).__name__)
    if isinstance(root, QMainWindow):
        out += _action_texts(root.menuBar().actions(), "menu")
    return out


def english(texts: list[tuple[str, str]]) -> list[str]:
    return sorted({f"{where}: {text!r}" for where, text in texts if untranslated(text)})


# -- clipping --------------------------------------------------------------------------------------

def _combo_cut(w: QComboBox) -> bool:
    option = QStyleOptionComboBox()
    w.initStyleOption(option)
    field = w.style().subControlRect(QStyle.ComplexControl.CC_ComboBox, option,
                                     QStyle.SubControl.SC_ComboBoxEditField, w)
    icon = w.iconSize().width() + 4 if not w.itemIcon(w.currentIndex()).isNull() else 0
    return w.fontMetrics().horizontalAdvance(w.currentText()) + icon > field.width()


def _dock_title_cut(dock: QDockWidget) -> bool:
    buttons = [b for b in dock.findChildren(QAbstractButton, options=Qt.FindChildOption.FindDirectChildrenOnly)
               if b.isVisible()]
    right = min((b.geometry().left() for b in buttons), default=dock.width())
    margin = dock.style().pixelMetric(QStyle.PixelMetric.PM_DockWidgetTitleMargin, None, dock)
    return dock.fontMetrics().horizontalAdvance(dock.windowTitle()) + 2 * margin > right


def clipped(root: QWidget) -> list[str]:
    """Texts under ``root`` that do not fit where they are shown: labels (as test_truncation
    has it), buttons, check boxes, tabs, combo and spin boxes narrower than their text, dock
    titles, and menus or tool buttons pushed into an overflow."""
    out = [line for line in _cut_labels(root)]
    for w in [root] + root.findChildren(QWidget):
        if not w.isVisible():
            continue
        where = f"{type(w).__name__} {w.objectName()!r}"
        if isinstance(w, (QPushButton, QCheckBox, QRadioButton)) and w.text():
            if w.width() < w.sizeHint().width():
                out.append(f"{where} {w.text()!r}: {w.width()} px of {w.sizeHint().width()}")
        elif isinstance(w, QToolButton) and w.text() and not isinstance(w.parent(), QTabBar) \
                and w.objectName() not in ("qt_toolbar_ext_button", "qt_menubar_ext_button"):
            if w.width() < w.sizeHint().width():
                out.append(f"{where} {w.text()!r}: {w.width()} px of {w.sizeHint().width()}")
        elif isinstance(w, QTabBar):
            for i in range(w.count()):
                if w.isTabVisible(i) and w.tabRect(i).width() < w.tabSizeHint(i).width():
                    out.append(f"tab {w.tabText(i)!r}: {w.tabRect(i).width()} px of {w.tabSizeHint(i).width()}")
        elif isinstance(w, QComboBox) and not isinstance(w, ElidedCombo) and not w.isEditable() \
                and w.currentText() and _combo_cut(w):       # an ElidedCombo shows the whole choice on hover
            out.append(f"{where} {w.currentText()!r}: wider than its box ({w.width()} px)")
        elif isinstance(w, QAbstractSpinBox):
            edit = w.findChild(QLineEdit)
            need = edit.fontMetrics().horizontalAdvance(edit.text())
            if need > edit.contentsRect().width() - 4:
                out.append(f"{where} {edit.text()!r}: {need} px in {edit.contentsRect().width()}")
        elif isinstance(w, QLineEdit) and not w.text() and w.placeholderText() and \
                w.fontMetrics().horizontalAdvance(w.placeholderText()) > w.contentsRect().width() - 4:
            out.append(f"{where} placeholder {w.placeholderText()!r}: {w.width()} px")
        elif isinstance(w, QDockWidget) and not w.isFloating() and _dock_title_cut(w):
            out.append(f"dock title {w.windowTitle()!r} is elided")
        elif isinstance(w, QHeaderView) and isinstance(w.parent(), QAbstractItemView):
            model = w.model()
            for c in range(model.columnCount()):
                text = str(model.headerData(c, Qt.Orientation.Horizontal) or "")
                if w.isSectionHidden(c) or not text or w.stretchLastSection() and c == model.columnCount() - 1:
                    continue
                if w.sectionSizeFromContents(c).width() > w.sectionSize(c) and \
                        not model.headerData(c, Qt.Orientation.Horizontal, Qt.ItemDataRole.ToolTipRole):
                    out.append(f"{w.parent().objectName()} column {text!r}: {w.sectionSize(c)} px")
        if w.objectName() in ("qt_toolbar_ext_button", "qt_menubar_ext_button"):
            out.append(f"{type(w.parent()).__name__} {w.parent().objectName()!r} overflows (its » button is shown)")
    return out


# -- fixtures ------------------------------------------------------------------------------------

@pytest.fixture
def russian(qapp):
    """The Russian catalogue (compiled by ./dev from the .po) and Qt's, installed before the
    window is built, as the application does at start."""
    from zuml_studio.ui.language import install_qt_catalogue

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
    from zuml_studio.ui.help_browser import HelpBrowser
    from zuml_studio.ui.plot_export import PlotExportDialog
    from zuml_studio.ui.preferences import PreferencesDialog
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
    from zuml_studio.ui.preferences import Preferences, PreferencesDialog

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
