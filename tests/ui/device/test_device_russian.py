"""The device panel in Russian (issue 17): during a run on the built-in virtual charger every text
it shows (labels, buttons, choices, tooltips, the plot's legends, the messages) is Russian, keywords,
units, numbers and names aside; and at 1366x768 none of it is cut off."""
import os
import re
from pathlib import Path

import pytest

from device_helpers import WAIT_MS, connect, flash_and_start
from window_checks import clipped, english, untranslated, walk
from zuml_studio import i18n
from zuml_studio.ui.device.confirm_dialogs import restore_text
from zuml_studio.ui.device.unsafe_dialog import warnings_dialog

pytestmark = pytest.mark.skipif(os.name != "posix", reason="the built-in virtual charger uses a pty here")

DATA = Path(__file__).resolve().parents[2] / "data" / "realdata"
CYRILLIC = re.compile("[А-Яа-яЁё]")


@pytest.fixture
def russian():
    i18n.install("ru")
    yield
    i18n.install("en")


def _walk(panel) -> tuple[list[str], list[str]]:
    """The panel's English texts and its clipped texts, by the whole window's walk (and the
    live plot's legends, which are drawn, not widgets)."""
    texts = walk(panel) + [("legend", name) for legend in panel.plot.legends.values() for name in legend.names()]
    return english(texts), clipped(panel)


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
    box = warnings_dialog(None, i18n._("Flash"), ["V > 4.20 V/cell"])
    qtbot.addWidget(box)
    for text in (box.windowTitle(), box.text(), box.informativeText(), box.go_ahead.text()):
        assert CYRILLIC.search(text), text
    assert "1 предупреждение" in box.text()        # the singular of three forms
    text = restore_text("backup.bin", ["NiMh-dV", "LiPo"], ["NiMh-dV"])
    assert "2 макроса" in text and "1 макрос:" in text
    assert not untranslated(text)
