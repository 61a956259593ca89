"""Nothing is cut off without a way to read it: at 1366x768 every visible label and every
cell of the editor side's lists shows its whole text or has a tooltip that does; no control is
squeezed below the size it needs or hidden behind its neighbours (in every mode), and no two
tick labels of a plot overlap. (The device panel is checked by its own tests.)"""
import pyqtgraph as pg
import pytest
from PySide6.QtCore import QEventLoop, QTimer
from PySide6.QtGui import QImage, QPainter
from PySide6.QtWidgets import (QAbstractButton, QAbstractItemView, QAbstractScrollArea, QAbstractSpinBox, QComboBox,
                               QDockWidget, QLabel, QLineEdit, QTableView, QTabBar, QTreeWidget, QWidget)

from helpers import MACROS

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
