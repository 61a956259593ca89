"""The live view shows the charger's per-cell voltages as the simulator plot shows a pack's cells:
each cell on the per-cell axis, in the same colour, with a legend entry and in the readout; a
six-slot balance port's empty slots (0 V) are no cells; a session without cells costs no table."""
from dataclasses import dataclass

import numpy as np
import pytest

from zuml_studio.ui.plots.cell_curves import cell_hue
from zuml_studio.ui.device.live_view import LiveView


@dataclass
class Tel:
    time_s: float
    voltage_v: float
    cells_v: tuple = ()
    running: bool = True
    current_a: float = 2.0
    temp_c: float = 25.0
    heatsink_c: float = 30.0
    mah_in: float = 0.0
    mah_out: float = 0.0
    run: int = 1
    cycle: int = 0


def four_cells(t: float) -> tuple:
    """A 4S pack on a 6-slot balance port: cell 3 runs 30 mV high; slots 5 and 6 read 0 V."""
    base = 3.7 + 0.4 * t / 600.0
    return (base, base, base + 0.03, base, 0.0, 0.0)


@pytest.fixture
def live(qtbot):
    view = LiveView()
    qtbot.addWidget(view)
    view.resize(1366, 500)
    view.show()
    view.plot.set_series_count(4)
    return view


def feed(live, cells=four_cells, seconds=600):
    for t in range(seconds):
        live.series.add_telemetry(Tel(float(t), sum(cells(t)), cells(t)))
    live.plot.refresh()
    live.plot.show_all()
    live.plot.refresh()


def test_each_cell_drawn_on_the_per_cell_axis_in_the_simulators_colours(live):
    feed(live)
    plot = live.plot
    assert plot.legends[plot.vplot].names() == ["pack voltage", "cell 1", "cell 2", "cell 3", "cell 4"]
    assert sorted(plot.cells.items) == ["cell1_v", "cell2_v", "cell3_v", "cell4_v"]
    for k in range(1, 5):
        assert plot.cells.items[f"cell{k}_v"].opts["pen"].color().name() == cell_hue(plot, k)
    x, y = plot.cells.items["cell3_v"].getData()
    assert len(x) > 10
    k = int(np.argmin(abs(x - 300.0)))
    assert y[k] == pytest.approx(4 * four_cells(x[k])[2], abs=0.02)      # read on the per-cell axis


def test_the_readout_lists_the_cells(live):
    feed(live)
    live.readout.show_at(300.0)
    assert "cells 3.900 · 3.900 · 3.930 · 3.900 V" in live.readout.text()


def test_cells_that_come_later_stand_beside_their_frames(live):
    feed(live, cells=lambda t: four_cells(t) if t >= 200 else ())
    table, first_row, count = live.series.cell_table()
    assert (first_row, count, len(table)) == (200, 4, 400)
    live.readout.show_at(100.0)
    assert live.readout.text() and "cells" not in live.readout.text()
    live.readout.show_at(300.0)
    assert "cells 3.900" in live.readout.text()


def test_a_session_without_cells_has_no_table_and_no_cell_curves(live):
    feed(live, cells=lambda t: (0.0,) * 6)
    assert live.series.cell_table() == (None, 0, 0)
    assert not live.plot.cells.items and live.plot.legends[live.plot.vplot].names() == ["pack voltage"]
    live.readout.show_at(300.0)
    assert "cells" not in live.readout.text()


def test_clear_forgets_the_cells_and_keeps_the_plots(live):
    feed(live)
    live.plot.clear_session()
    assert live.series.cell_table() == (None, 0, 0) and not live.plot.cells.items
    assert len(live.plot.ci.items) == 3 and live.plot.points == 0      # pyqtgraph's clear took the plots away


def test_the_panels_clear_button_keeps_the_plots(make_panel):
    panel = make_panel()
    for t in range(100):
        panel.series.add_telemetry(Tel(float(t), 15.6, four_cells(t)))
    panel.plot.refresh()
    assert panel.plot.points == 100
    panel.clear_button.click()
    assert panel.plot.points == 0 and len(panel.plot.ci.items) == 3
