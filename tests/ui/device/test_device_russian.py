"""The device panel in Russian (issue 17): during a run on the built-in virtual charger every text
it shows (labels, buttons, choices, tooltips, the plot's legends, the messages) is Russian, keywords,
units, numbers and names aside; and at 1366x768 none of it is cut off."""
import html
import os
import re

import pytest
from PySide6.QtWidgets import (QAbstractButton, QAbstractSpinBox, QComboBox, QLabel, QLineEdit, QTableWidget,
                               QWidget)

from device_helpers import WAIT_MS, connect, flash_and_start
from zuml_studio import i18n
from zuml_studio.ui.device.device_style import ElidedLabel

pytestmark = pytest.mark.skipif(os.name != "posix", reason="the built-in virtual charger uses a pty here")

CYRILLIC = re.compile("[А-Яа-яЁё]")
# What stays as it is in every language: units, ZUML keywords and passport fields, protocol and file
# names, chemistries, the charger's own words (its model, its firmware, the macro names).
KEPT = {"V", "A", "W", "mAh", "mA", "Hz", "min", "S", "C", "D", "T", "Tc", "h", "mm", "cell", "xNN", "pty", "URL",
        "INPUT", "CONSTANT_I", "CONSTANT_V", "AKK_TYPE", "ZUML", "EEPROM", "TEMP", "ERR", "CRIT", "CSV", "HID",
        "NiMh", "NiCd", "LiPo", "LiIon", "LiFe", "Pb", "dV", "Ctrl", "Shift", "F", "iMAX", "virtual", "zuml",
        "cheali", "iCharger", "Ultramat", "SkyRC", "ISDT", "DUO", "X", "socket", "dev", "ttyUSB", "COM", "pts",
        "VIRT", "N", "bin", "txt", "log", "hex", "csv", "tmp", "session", "sessions",
        "Junsi", "Graupner", "Ultra", "Duo", "Plus", "mini", "v"}     # charger names


def _plain(text: str) -> str:
    return html.unescape(re.sub(r"<[^>]+>", " ", text))


def _english_words(text: str) -> list[str]:
    """The Latin words of a text that has no Cyrillic and that are not kept as they are."""
    text = _plain(text)
    if CYRILLIC.search(text):
        return []
    text = re.sub(r"(socket://|/)\S+", " ", text)                     # port paths and URLs
    return [w for w in re.findall(r"[A-Za-z]+", text) if w not in KEPT and not w.isupper()]


def _texts(widget: QWidget) -> list[str]:
    out = [widget.toolTip()]
    if isinstance(widget, QLabel):
        out.append(widget.full_text() if isinstance(widget, ElidedLabel) else widget.text())
    elif isinstance(widget, QAbstractButton):
        out.append(widget.text())
    elif isinstance(widget, QComboBox):
        out += [widget.itemText(i) for i in range(widget.count())]
    elif isinstance(widget, QLineEdit):
        out.append(widget.placeholderText())
    elif isinstance(widget, QAbstractSpinBox):
        out += [widget.suffix(), widget.prefix(), widget.specialValueText()]
    elif isinstance(widget, QTableWidget):
        out += [widget.horizontalHeaderItem(c).text() for c in range(widget.columnCount())]
    return [t for t in out if t and t.strip()]


def _clipped(widget: QWidget) -> str:
    """What of a one-line text does not fit its widget ("" if it fits or may wrap or elide)."""
    fm = widget.fontMetrics()
    if isinstance(widget, ElidedLabel):           # elides to its width; the tooltip tells the whole
        return "" if widget.toolTip() else widget.full_text()
    if isinstance(widget, QLabel) and not widget.wordWrap() and widget.text():
        text = _plain(widget.text())
        longest = max(fm.horizontalAdvance(line) for line in text.splitlines() or [""])
        return text if longest > widget.contentsRect().width() + 1 else ""
    if isinstance(widget, QAbstractButton) and widget.text():
        need = widget.sizeHint().width()
        return f"{widget.text()} ({widget.width()} < {need} px)" if widget.width() + 1 < need else ""
    if isinstance(widget, QComboBox) and widget.currentText():
        room = widget.width() - widget.style().pixelMetric(widget.style().PixelMetric.PM_ScrollBarExtent) - 12
        return widget.currentText() if fm.horizontalAdvance(widget.currentText()) > room else ""
    return ""


@pytest.fixture
def russian():
    i18n.install("ru")
    yield
    i18n.install("en")


def test_the_panel_speaks_russian_during_a_run_and_cuts_nothing_off(qtbot, make_panel, russian):
    panel = make_panel(size=(1354, 358))          # the Device dock's room in a 1366x768 window
    connect(qtbot, panel)
    ok, message = flash_and_start(qtbot, panel)
    assert ok and CYRILLIC.search(message), message
    qtbot.waitUntil(lambda: panel.plot.points > 10 and "C1" in panel.run_label.full_text(), timeout=WAIT_MS)
    english, clipped = {}, {}
    for widget in [panel] + panel.findChildren(QWidget):
        if not widget.isVisibleTo(panel) or widget.objectName().startswith("qt_"):
            continue
        for text in _texts(widget):
            words = _english_words(text)
            if words:
                english.setdefault(f"{type(widget).__name__} {widget.objectName()}", []).append((text, words))
        cut = _clipped(widget)
        if cut:
            clipped[f"{type(widget).__name__} {widget.objectName()}"] = cut
    for plot_item, legend in panel.plot.legends.items():
        for name in legend.names():
            if _english_words(name):
                english.setdefault("legend", []).append((name, _english_words(name)))
    assert not english, english
    assert not clipped, clipped
    assert CYRILLIC.search(panel.message_text())
    assert CYRILLIC.search(panel.session_label.full_text())
