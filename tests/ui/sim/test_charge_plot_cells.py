"""The pack's cells on the simulator plot: each cell (up to eight) with its legend entry, read on the
per-cell axis; more as the lowest and highest with the spread shaded; the balancer's bleeding drawn
over the cell and named in the readout; without cell columns the plot as before."""
import numpy as np
import pytest
from PySide6.QtWidgets import QVBoxLayout, QWidget

from cell_logs import WEAK_CELL, lipo_run
from zuml_studio.ui.base import theme
from zuml_studio.ui.plots.cell_curves import cell_hue
from zuml_studio.ui.sim.charge_plot import ChargePlot
from zuml_studio.ui.plots.plot_data import HIGHEST, LOWEST, cell_columns, prepare_plot


@pytest.fixture
def plot(qtbot):
    # In a container, as in the panel: closing a pyqtgraph view of its own crashes PySide6 here.
    box = QWidget()
    qtbot.addWidget(box)
    p = ChargePlot(box)
    QVBoxLayout(box).addWidget(p)
    box.resize(1100, 520)
    box.show()
    qtbot.waitExposed(box)
    yield p
    box.hide()


def legend(plot):
    return plot.legends[plot.vplot].names()


def drawn(plot, column):
    x, y = plot.cells.items[column].getData()
    return np.asarray(x), np.asarray(y)


def test_cell_columns_run_from_cell1_without_a_hole():
    data = {"cell1_v": 0, "cell2_v": 0, "cell4_v": 0, "time_s": 0}
    assert cell_columns(data) == ("cell1_v", "cell2_v")
    assert cell_columns({"cell1_v": 0}) == ()               # one cell: nothing to tell apart
    assert cell_columns({"voltage_v": 0}) == ()


def test_four_cells_each_with_its_entry_colour_and_the_balancer(plot):
    run = prepare_plot(lipo_run(4))
    plot.show_result(run)
    assert legend(plot) == ["pack voltage", "cell 1", "cell 2", "cell 3", "cell 4"]
    kinds = [(c.cell, c.kind) for c in run.cell_curves]
    assert kinds == [(k, "cell") for k in range(1, 5)] + [(k, "bleed") for k in range(1, 5)]
    # Read on the per-cell axis: drawn at the cell's voltage times the pack's cells.
    x, y = drawn(plot, "cell1_v")
    k = np.searchsorted(run.data["time_s"], x[len(x) // 2])
    assert len(x) > 100 and y[len(x) // 2] == pytest.approx(4 * run.data["cell1_v"][k], rel=0.01)
    assert plot.cells.items["cell2_v"].opts["pen"].color().name() == cell_hue(plot, 2)
    # The weak cell bleeds over the last quarter of the run, and only then; the others never.
    x, y = drawn(plot, f"cell{WEAK_CELL}_bleed")
    t_end = run.data["time_s"][-1]
    assert np.isfinite(y).any() and x[np.isfinite(y)].min() >= 0.74 * t_end
    assert not np.isfinite(drawn(plot, "cell1_bleed")[1]).any()
    # The y range takes the highest cell in.
    assert plot.vplot.vb.viewRange()[1][1] >= run.data[HIGHEST].max() * 4


def test_the_readout_names_the_cells_and_the_bleeding_one(plot):
    run = prepare_plot(lipo_run(4))
    plot.show_result(run)
    t_end = float(run.data["time_s"][-1])
    assert plot.readout.show_at(0.9 * t_end)
    text = plot.readout.text()
    assert "cells " in text and text.count(" · ") >= 5 and f"the balancer bleeds cell {WEAK_CELL}" in text
    assert plot.readout.show_at(0.2 * t_end)
    assert "bleeds" not in plot.readout.text() and "cells " in plot.readout.text()


def test_twelve_cells_are_the_lowest_and_highest_with_the_spread(plot):
    run = prepare_plot(lipo_run(12))
    plot.show_result(run)
    assert legend(plot) == ["pack voltage", "lowest cell", "highest cell"]
    assert plot.cells.spread is not None
    _x, low = drawn(plot, LOWEST)
    _x, high = drawn(plot, HIGHEST)
    assert np.all(high >= low - 1e-9) and np.any(high > low)
    t_end = float(run.data["time_s"][-1])
    plot.readout.show_at(0.9 * t_end)
    assert f"highest: cell {WEAK_CELL}" in plot.readout.text() and "bleeds cell 3" in plot.readout.text()


def test_without_cells_the_plot_is_as_before_and_a_later_run_drops_them(plot):
    plot.show_result(prepare_plot(lipo_run(0)))
    assert legend(plot) == ["pack voltage"] and not plot.cells.items
    plot.show_result(prepare_plot(lipo_run(4, balancer=False)))
    assert legend(plot)[1:] == ["cell 1", "cell 2", "cell 3", "cell 4"]
    assert not any(c.kind == "bleed" for c in plot.cells.layout)
    plot.show_result(prepare_plot(lipo_run(0)))
    assert legend(plot) == ["pack voltage"] and not plot.cells.items
    assert plot.readout.show_at(600.0) and "cells" not in plot.readout.text()


def test_a_theme_change_keeps_the_cells_in_their_dark_colours(plot):
    plot.show_result(prepare_plot(lipo_run(4)))
    plot.set_colours(theme.DARK)
    assert legend(plot) == ["pack voltage", "cell 1", "cell 2", "cell 3", "cell 4"]
    assert plot.cells.items["cell1_v"].opts["pen"].color().name() == cell_hue(plot, 1) != \
        theme.LIGHT.quantities["voltage"]
