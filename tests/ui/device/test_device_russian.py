"""The device panel in Russian (issue 17): during a run on the built-in virtual charger every text
it shows (labels, buttons, choices, tooltips, the plot's legends, the messages) is Russian, keywords,
units, numbers and names aside; and at 1366x768 none of it is cut off."""
import html
import os
import re
from pathlib import Path

import pytest
from PySide6.QtWidgets import (QAbstractButton, QAbstractSpinBox, QComboBox, QLabel, QLineEdit, QTableWidget,
                               QWidget)

from device_helpers import WAIT_MS, connect, flash_and_start
from zuml_studio import i18n
from zuml_studio.ui.device.confirm_dialogs import restore_text
from zuml_studio.ui.device.device_style import ElidedCombo, ElidedLabel
from zuml_studio.ui.device.unsafe_dialog import unsafe_dialog

pytestmark = pytest.mark.skipif(os.name != "posix", reason="the built-in virtual charger uses a pty here")

DATA = Path(__file__).resolve().parents[2] / "data" / "realdata"
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
    if isinstance(widget, ElidedCombo):           # elides its face; the tooltip heads with the whole choice
        return ""
    if isinstance(widget, QComboBox) and widget.currentText():
        room = widget.width() - widget.style().pixelMetric(widget.style().PixelMetric.PM_ScrollBarExtent) - 12
        return widget.currentText() if fm.horizontalAdvance(widget.currentText()) > room else ""
    return ""


@pytest.fixture
def russian():
    i18n.install("ru")
    yield
    i18n.install("en")


def _walk(panel) -> tuple[dict, dict]:
    """The panel's English texts and clipped texts, by widget."""
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
    for legend in panel.plot.legends.values():
        for name in legend.names():
            if _english_words(name):
                english.setdefault("legend", []).append((name, _english_words(name)))
    return english, clipped


def test_the_panel_speaks_russian_during_a_run_and_cuts_nothing_off(qtbot, make_panel, russian):
    panel = make_panel(size=(1354, 358))          # the Device dock's room in a 1366x768 window
    english, clipped = _walk(panel)
    assert not english and not clipped, (english, clipped)
    connect(qtbot, panel)
    ok, message = flash_and_start(qtbot, panel)
    assert ok and CYRILLIC.search(message), message
    first_phase = i18n._("C{index}").format(index=1)          # Зар1
    qtbot.waitUntil(lambda: panel.plot.points > 10 and first_phase in panel.run_label.full_text(), timeout=WAIT_MS)
    english, clipped = _walk(panel)
    assert not english, english
    assert not clipped, clipped
    assert CYRILLIC.search(panel.message_text())
    assert CYRILLIC.search(panel.session_label.full_text())


def test_a_monitor_only_charger_in_russian(qtbot, make_panel, russian, tmp_path):
    src = tmp_path / "icharger.txt"
    src.write_bytes(b"".join((DATA / "icharger306B_RB_1000_lines_head300.txt").read_bytes().splitlines(True)[:40]))
    panel = make_panel(size=(1354, 358))
    with qtbot.waitSignal(panel.connectedChanged, timeout=WAIT_MS):
        assert panel.replay(src, speed=1000)
    qtbot.waitUntil(lambda: panel.monitor.link.good == 40, timeout=WAIT_MS)
    qtbot.waitUntil(lambda: "40" in panel.info_label.full_text(), timeout=WAIT_MS)
    english, clipped = _walk(panel)
    assert not english and not clipped, (english, clipped)
    assert CYRILLIC.search(panel.flash_button.toolTip()) and CYRILLIC.search(panel.info_label.full_text())
    with qtbot.waitSignal(panel.connectedChanged, timeout=WAIT_MS):
        panel.disconnect()
    assert CYRILLIC.search(panel.message_text()), panel.message_text()


def test_the_device_questions_in_russian(qtbot, russian):
    box = unsafe_dialog(None, i18n._("Flash"), ["V > 4.25 V/cell"])
    qtbot.addWidget(box)
    for text in (box.windowTitle(), box.text(), box.informativeText(), box.go_ahead.text()):
        assert CYRILLIC.search(text), text
    assert "1 опасность" in box.text()             # the singular of three forms
    text = restore_text("backup.bin", ["NiMh-dV", "LiPo"], ["NiMh-dV"])
    assert "2 макроса" in text and "1 макрос:" in text
    assert not _english_words(text.replace("backup.bin", ""))
