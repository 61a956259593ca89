"""A walk through every mode on a laptop screen (1366x768), in English and Russian, light and
dark, and again after a restart: no control clipped, no label cut that could wrap, the plot of
the mode's task with at least its 60 % of the window, and no window of its own larger than the
screen it opens on. Each language runs once per theme; a run on the virtual charger is started
from the Write mode, as a user does, and must land where its curve can be read."""
from pathlib import Path

import pytest
from PySide6.QtWidgets import QApplication

from helpers import MACROS
from window_checks import WATCHED_SHARE, _cut_controls, _cut_labels, _settle, share

LAPTOP = (1366, 768)
READABLE = {"problems": 240}    # px: narrower, the Problems list reads a word or two a line
LOG = Path(__file__).resolve().parents[2] / "data" / "logs" / "X8_LiPo_5S_2200mA_Charge_4.txt"


def elided_with_room(root) -> list[str]:
    """One-line labels that elide their text although they stand two lines high (they could wrap)."""
    from zuml_studio.ui.device.device_style import ElidedLabel
    out = []
    for label in root.findChildren(ElidedLabel):
        if label.isVisible() and label.text() != label.full_text() \
                and label.height() >= 2 * label.fontMetrics().lineSpacing():
            out.append(f"{label.objectName() or label.full_text()!r}: elided in {label.width()}x{label.height()} px")
    return out


def too_big_windows() -> list[str]:
    """Windows of their own (not the main window, which the test sizes) larger than their screen."""
    out = []
    for widget in QApplication.topLevelWidgets():
        if not widget.isVisible() or not widget.isWindow() or widget.objectName() == "mainWindow":
            continue
        available = widget.screen().availableGeometry()
        frame = widget.frameGeometry()
        if frame.width() > available.width() or frame.height() > available.height():
            out.append(f"{type(widget).__name__} {frame.width()}x{frame.height()} on {available.width()}x"
                       f"{available.height()}")
    return out


def squeezed_docks(w) -> list[str]:
    """Docks on screen narrower than the width they read at (the Problems list one word a line)."""
    out = []
    for spec in w.dock_specs:
        dock = w.docks[spec.name]
        if READABLE.get(spec.name) and dock.isVisible() and not dock.visibleRegion().isEmpty() \
                and dock.width() < READABLE[spec.name]:
            out.append(f"{spec.name} dock {dock.width()} px wide, reads from {READABLE[spec.name]}")
    return out


def problems_of(w) -> list[str]:
    return _cut_controls(w) + _cut_labels(w.statusBar()) + elided_with_room(w) + squeezed_docks(w)


@pytest.fixture(params=[("en", "light"), ("en", "dark"), ("ru", "light"), ("ru", "dark")],
                ids=lambda p: "-".join(p))
def laptop_walk(request, qapp, system_theme):
    from zuml_studio import i18n
    from zuml_studio.ui.base import theme
    from zuml_studio.ui.base.language import install_qt_catalogue
    language, look = request.param
    i18n.install(language)
    install_qt_catalogue(language)
    theme.apply_theme(look)
    yield language
    i18n.install("en")
    install_qt_catalogue("en")


def test_every_mode_reads_on_a_laptop_screen(laptop_walk, make_window, qtbot, tmp_path):
    from device_helpers import WAIT_MS, connect, flash_and_start
    config = tmp_path / "walk"
    w = make_window(str(MACROS / "NiMh-dV.zuml"), config)
    w.resize(*LAPTOP)
    qtbot.waitUntil(lambda: w.width() == LAPTOP[0])
    _settle()
    found = [f"write: {p}" for p in problems_of(w)]

    w.modes.switch("simulate")
    w.sim_panel.simulate()
    assert w.sim_panel.wait(60_000)
    qtbot.waitUntil(lambda: share(w.sim_panel.plot, w) >= WATCHED_SHARE)
    _settle()
    found += [f"simulate: {p}" for p in problems_of(w)]

    w.modes.switch("write")                 # a run started where the editor is: the Charge mode shows it
    w.show_visual()
    panel = w.device_panel
    connect(qtbot, panel)
    ok, text = flash_and_start(qtbot, panel)
    assert ok, text
    qtbot.waitUntil(lambda: w.modes.current == "charge" and panel.is_running(), timeout=WAIT_MS)
    qtbot.waitUntil(lambda: share(panel.plot, w) >= WATCHED_SHARE)
    _settle()
    found += [f"charge: {p}" for p in problems_of(w)]

    logs = w.open_log(str(LOG))                 # the status line and "Add a log to compare…" on the screen
    qtbot.waitUntil(lambda: logs.current() is not None, timeout=WAIT_MS)
    _settle()
    found += too_big_windows() + [f"logs: {p}" for p in _cut_controls(logs)]
    logs.close()
    w.modes.switch("write")
    w.ask_close_run = lambda: "stop"
    w.close()

    again = make_window(str(MACROS / "NiMh-dV.zuml"), config)     # Preferences > Restart: the layouts kept
    again.resize(*LAPTOP)
    qtbot.waitUntil(lambda: again.width() == LAPTOP[0])
    _settle()
    assert again.problems_dock.width() >= 200, f"Problems came back {again.problems_dock.width()} px wide"
    found += [f"after a restart: {p}" for p in problems_of(again)]
    assert not found, "\n".join(found)


WIDTHS = (1366, 1280, 1024, 1100, 1366)     # a laptop, a smaller one, a 1024 px screen, and back


def test_the_problems_list_reads_at_every_width(qapp, make_window, qtbot, tmp_path):
    """Narrowed from a wide window and widened again, the Problems list (with an error in it) is
    never squeezed to a word a line: beside the simulator where the window leaves it its readable
    width, else a tab of the simulator's set, and back beside it when the window is wide again."""
    macro = tmp_path / "wrong.zuml"
    macro.write_text((MACROS / "NiMh-dV.zuml").read_text().replace("IF(tf>4h)", "IF(tf>4h) STOP_FAZE IF("))
    w = make_window(str(macro))
    qtbot.waitUntil(lambda: w.problems.topLevelItemCount() > 0)
    found = []
    for width in WIDTHS:
        w.resize(width, LAPTOP[1])
        qtbot.waitUntil(lambda: w.width() == width)
        _settle()
        found += [f"{width} px: {p}" for p in squeezed_docks(w)]
        if not w.problems_dock.visibleRegion().isEmpty():
            continue
        tabbed = w.sim_dock in w.tabifiedDockWidgets(w.problems_dock)
        found += [] if tabbed else [f"{width} px: the Problems list neither beside the simulator nor its tab"]
    assert w.sim_dock not in w.tabifiedDockWidgets(w.problems_dock), "wide again, Problems stayed a tab"
    assert not found, "\n".join(found)
