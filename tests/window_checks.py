"""What the window's tests look for, shared by the tests of the main window, its walks and the device
panel: texts cut off at 1366x768 (labels, controls, list cells, overlapping tick labels, clipped
dialogs), texts left in English under the Russian catalogue, and a widget's share of the window."""
from __future__ import annotations

import re

import pyqtgraph as pg
from PySide6.QtCore import QEventLoop, Qt, QTimer
from PySide6.QtGui import QImage, QPainter, QTextDocumentFragment
from PySide6.QtWidgets import (QAbstractButton, QAbstractItemView, QAbstractScrollArea, QAbstractSpinBox, QCheckBox,
                               QComboBox, QDockWidget, QGroupBox, QHeaderView, QLabel, QLineEdit, QMainWindow, QMenu,
                               QPlainTextEdit, QPushButton, QRadioButton, QStyle, QStyleOptionComboBox, QTableWidget,
                               QTabBar, QToolBar, QToolButton, QTreeWidget, QWidget)

from helpers import ROOT
from zuml_studio import data, i18n
from zuml_studio.lang import opcodes
from zuml_studio.lang.operands import AKK_TYPE, DISPLAY_NAMES
from zuml_studio.streams.drivers import DRIVERS
from zuml_studio.ui.device.device_style import ElidedCombo, ElidedLabel
from zuml_studio.sim.charger_model import load_charger
from zuml_studio.domain.chemistry import chemistry_names

# -- a widget's share of the window (test_window_modes) ---------------------------------------------

WATCHED_SHARE = 0.60


def share(widget, window) -> float:
    return widget.width() * widget.height() / (window.width() * window.height())


# -- cut off at 1366x768 (test_truncation) ------------------------------------------------------------

PADDING_PX = 6          # a cell's margins (the focus frame's on each side)


def _settle():
    loop = QEventLoop()
    QTimer.singleShot(200, loop.quit)
    loop.exec()


def _cut_labels(root):
    out = []
    for label in root.findChildren(QLabel):
        if not label.isVisible() or label.wordWrap() or label.toolTip() or not label.text():
            continue
        if label.textFormat() != label.textFormat().PlainText and "<" in label.text():
            continue
        needed = label.fontMetrics().horizontalAdvance(label.text())
        if needed > label.contentsRect().width() + 1:
            out.append(f"label {label.objectName() or label.text()!r}: {needed} px in {label.contentsRect().width()}")
    return out


CONTROLS = (QAbstractButton, QComboBox, QAbstractSpinBox, QLineEdit)


def _scrolled(widget: QWidget) -> bool:
    """Inside a scroll area's page (it may stand partly out of view: the area scrolls to it)."""
    parent = widget.parentWidget()
    while parent is not None:
        if isinstance(parent, QAbstractScrollArea) and parent.viewport().isAncestorOf(widget):
            return True
        parent = parent.parentWidget()
    return False


def _cut_controls(root):
    """Buttons, boxes and fields smaller than they need, or partly covered by their parents'
    edges (a button clipped to a strip); a dock's and a tab bar's own buttons are the style's."""
    out = []
    for widget in root.findChildren(QWidget):
        if not isinstance(widget, CONTROLS) or not widget.isVisible() or widget.isWindow():
            continue
        if isinstance(widget.parentWidget(), (QDockWidget, QTabBar, *CONTROLS)) \
                or isinstance(widget, QAbstractButton) and isinstance(widget.parentWidget(), QAbstractScrollArea):
            continue
        name = widget.objectName() or getattr(widget, "text", lambda: "")() or type(widget).__name__
        scrolled = _scrolled(widget)
        shown = widget.visibleRegion().boundingRect()
        if shown.isEmpty() and not scrolled:     # a dock behind another's tab: not on screen at all
            continue
        need = widget.minimumSizeHint()
        if widget.height() < min(need.height(), widget.maximumHeight()) - 1:
            out.append(f"{name!r}: {widget.height()} px high, needs {need.height()}")
        if scrolled:
            continue
        if shown.height() < widget.height() - 1 or shown.width() < widget.width() - 1:
            out.append(f"{name!r}: {shown.width()}x{shown.height()} of {widget.width()}x{widget.height()} px shown")
    return out


def _overlapping_ticks(plot: pg.GraphicsLayoutWidget):
    """Tick labels of a plot's axes (all of them: a stacked plot's neighbours too) that overlap."""
    image = QImage(8, 8, QImage.Format.Format_ARGB32)
    painter = QPainter(image)
    labels = []
    for item in plot.scene().items():
        if isinstance(item, pg.AxisItem) and item.isVisible() and item.style["showValues"]:
            specs = item.generateDrawSpecs(painter)
            for rect, _flags, text in (specs[2] if specs else []):
                labels.append((item.mapRectToScene(rect), text))
    painter.end()
    out = []
    for i, (a, text_a) in enumerate(labels):
        for b, text_b in labels[i + 1:]:
            both = a.intersected(b)
            if both.width() > 1 and both.height() > 1:
                out.append(f"{plot.objectName()}: tick labels {text_a!r} and {text_b!r} overlap")
    return out


def _cut_cells(view: QAbstractItemView):
    out = []
    model = view.model()
    metrics = view.fontMetrics()
    header = view.header() if isinstance(view, QTreeWidget) else view.horizontalHeader()
    for row in range(model.rowCount()):
        for col in range(model.columnCount()):
            if header.isSectionHidden(col):
                continue
            index = model.index(row, col)
            text = index.data() or ""
            if not text or index.data(3):              # 3: the tooltip role
                continue
            icon = 20 if index.data(1) is not None else 0
            width = header.sectionSize(col)
            visible = view.viewport().width() - header.sectionViewportPosition(col)
            if metrics.horizontalAdvance(text) + icon + PADDING_PX > min(width, max(visible, 0)):
                out.append(f"{view.objectName()} row {row} col {col}: {text!r}")
    return out


# -- English left under the Russian catalogue, and clipped texts (test_i18n_walk) ----------------

POT_TEXT = (ROOT / "resources" / "locale" / "zuml_studio.pot").read_text(encoding="utf-8")
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
