"""Nothing is cut off without a way to read it: at 1366x768 every visible label and every
cell of the editor side's lists shows its whole text or has a tooltip that does; no control is
squeezed below the size it needs or hidden behind its neighbours (in every mode), and no two
tick labels of a plot overlap. (The device panel is checked by its own tests.)"""
import pytest
from PySide6.QtWidgets import QTableView, QTreeWidget

from helpers import MACROS
from window_checks import _cut_cells, _cut_controls, _cut_labels, _overlapping_ticks, _settle


@pytest.mark.parametrize("macro", ["NiMh", "LiPo"])
def test_nothing_is_cut_off_without_a_tooltip_at_1366x768(make_window, macro):
    w = make_window(str(MACROS / f"{macro}.zuml"))
    w.resize(1366, 768)
    w.sim_panel.simulate()
    w.sim_panel.wait(60_000)
    _settle()
    problems = []
    for dock in (w.library_dock, w.hex_dock, w.problems_dock, w.sim_dock):
        problems += _cut_labels(dock)
    problems += _cut_labels(w.statusBar())
    for view in (w.problems, w.hex_view.tree, w.library, w.sim_panel.table):
        assert isinstance(view, (QTreeWidget, QTableView))
        problems += _cut_cells(view)
    assert not problems, "\n".join(problems)


def test_the_device_panel_and_the_visual_tab_cut_nothing_without_a_tooltip_at_1366x768(make_window, qtbot):
    from device_helpers import WAIT_MS, connect, flash_and_start
    w = make_window(str(MACROS / "NiMh-dV.zuml"))
    w.resize(1366, 768)
    panel = w.device_panel
    w.device_dock.show()
    w.device_dock.raise_()
    _settle()
    before = _cut_controls(w.device_dock) + _overlapping_ticks(panel.plot)     # right after start
    assert not before, "\n".join(before)
    connect(qtbot, panel)
    ok, text = flash_and_start(qtbot, panel)
    assert ok, text
    qtbot.waitUntil(lambda: len(panel.series) > 3 and "running" in panel.run_label.full_text(), timeout=WAIT_MS)
    _settle()
    problems = _cut_labels(w.device_dock) + _cut_cells(panel.table) + _cut_controls(w.device_dock)
    problems += _overlapping_ticks(panel.plot)
    readings = panel.readings           # rich text (colours): measured by its size hint, not by a tooltip
    assert "mAh" in readings.text()
    need, have = readings.sizeHint(), readings.size()               # both with the label's margins
    assert need.width() <= have.width() and need.height() <= have.height(), f"the live readout is cut: {need} in {have}"
    w.show_visual()
    _settle()
    problems += _cut_labels(w.visual_dock)
    assert not problems, "\n".join(problems)


@pytest.mark.parametrize("mode", ["write", "simulate"])
def test_no_control_is_cut_and_no_tick_labels_overlap_at_1366x768(make_window, mode):
    w = make_window(str(MACROS / "NiMh.zuml"))
    w.resize(1366, 768)
    w.modes.switch(mode)
    w.sim_panel.simulate()
    w.sim_panel.wait(60_000)
    _settle()
    problems = _cut_controls(w) + _overlapping_ticks(w.sim_panel.plot)
    assert not problems, "\n".join(problems)


def test_the_charge_mode_cuts_no_control_and_its_live_plot_no_tick_label_at_1366x768(make_window, qtbot):
    from device_helpers import WAIT_MS, connect, flash_and_start
    w = make_window(str(MACROS / "NiMh-dV.zuml"))
    w.resize(1366, 768)
    w.modes.switch("charge")
    panel = w.device_panel
    connect(qtbot, panel)
    ok, text = flash_and_start(qtbot, panel)
    assert ok, text
    qtbot.waitUntil(lambda: len(panel.series) > 3 and "running" in panel.run_label.full_text(), timeout=WAIT_MS)
    _settle()
    problems = _cut_controls(w) + _overlapping_ticks(panel.plot) + _cut_labels(w.device_dock)
    assert not problems, "\n".join(problems)
