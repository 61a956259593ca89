"""Nothing is cut off without a way to read it: at 1366x768 every visible label and every
cell of the editor side's lists shows its whole text or has a tooltip that does.
(The device panel is checked by its own tests.)"""
import pytest
from PySide6.QtCore import QEventLoop, QTimer
from PySide6.QtWidgets import QAbstractItemView, QLabel, QTableView, QTreeWidget

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
    connect(qtbot, panel)
    ok, text = flash_and_start(qtbot, panel)
    assert ok, text
    qtbot.waitUntil(lambda: len(panel.series) > 3 and "running" in panel.run_label.full_text(), timeout=WAIT_MS)
    _settle()
    problems = _cut_labels(w.device_dock) + _cut_cells(panel.table)
    readings = panel.readings           # rich text (colours): measured by its size hint, not by a tooltip
    assert "mAh" in readings.text()
    need, have = readings.sizeHint(), readings.size()               # both with the label's margins
    assert need.width() <= have.width() and need.height() <= have.height(), f"the live readout is cut: {need} in {have}"
    w.show_visual()
    _settle()
    problems += _cut_labels(w.visual_dock)
    assert not problems, "\n".join(problems)
