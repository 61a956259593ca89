"""The cursor readout on the simulator plot: time, V, I, T and the phase under the mouse."""
import numpy as np
import pytest
from PySide6.QtCore import QPointF

from helpers import MACROS
from zuml_studio.ui.plots.plot_cursor import readout_text


@pytest.fixture
def simulated(qtbot):
    from zuml_studio.ui.sim.sim_panel import SimulatorPanel
    from zuml_studio.lang.compiler import compile_source

    panel = SimulatorPanel()
    qtbot.addWidget(panel)
    panel.resize(1000, 360)
    panel.show()
    result = compile_source((MACROS / "LiPo.zuml").read_text())
    panel.set_record(result.record, "LiPo", {"chemistry": "LiPo", "series": 3, "capacity_mah": 2200})
    panel.simulate()
    assert panel.wait(60_000)
    yield panel
    panel.cancel()


def test_the_readout_names_time_values_and_phase(simulated):
    plot = simulated.plot
    phase = simulated.result().phases[0]
    at = (phase.start_s + phase.end_s) / 2
    assert plot.readout.show_at(at)
    text = plot.readout.text()
    first, second = text.split("\n")
    assert first.count(" V") == 1 and " A" in first and "°C" in first
    assert second.startswith("C1: IF(V>4.1S) STOP_FAZE")
    assert all(line.isVisible() and abs(line.value() - at) < 1e-6 for line in plot.readout.lines)


def test_the_mouse_moves_the_readout_and_leaving_hides_it(simulated):
    plot = simulated.plot
    vb = plot.iplot.vb
    inside = vb.sceneBoundingRect().center()
    plot.scene().sigMouseMoved.emit(inside)
    assert plot.readout.text()
    assert abs(plot.readout.lines[0].value() - vb.mapSceneToView(inside).x()) < 1e-6
    plot.scene().sigMouseMoved.emit(QPointF(-50, -50))
    assert plot.readout.text() == ""


def test_readout_text_takes_the_nearest_sample():
    t = np.array([0.0, 10.0, 20.0])
    data = {"voltage_v": np.array([1.0, 2.0, 3.0]), "current_a": np.array([0.5, 0.5, 0.5]),
            "temp_c": np.array([25.0, 25.5, 26.0])}
    assert readout_text(t, data, [], 12.0) == "0:00:10 · 2.000 V · 0.50 A · 25.5 °C"
    assert readout_text(np.zeros(0), {}, [], 1.0) == ""


def test_a_flat_temperature_keeps_a_readable_span(qtbot):
    from zuml_studio.ui.sim.sim_panel import SimulatorPanel
    from zuml_studio.ui.plots.stacked_plot import MIN_SPAN

    panel = SimulatorPanel()             # a bare pyqtgraph view crashes in close(); the panel does not
    qtbot.addWidget(panel)
    panel.resize(900, 300)
    panel.show()
    plot = panel.plot
    plot.curves["temp"].setData([0.0, 100.0, 200.0], [25.0, 25.0, 25.0])
    plot.curves["heatsink"].setData([0.0, 100.0, 200.0], [25.0, 25.0, 25.0])
    plot.tplot.vb.updateAutoRange()
    low, high = plot.tplot.vb.viewRange()[1]
    assert high - low >= MIN_SPAN["temp"] - 1e-9 and low < 25.0 < high
