"""The live plot over a session with a hole (the real iCharger 3010B charge with a 3.2 h hole,
tests/logs/logdata.py, fed sample by sample as a charger would send them): no line and no area
under the current crosses the hole, from the whole session down to the seconds around it."""
import math
import sys
from pathlib import Path

import pytest

from zuml_studio.logs import read_log
from zuml_studio.ui.device.live_view import LiveView

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "logs"))
from logdata import GAP_AFTER_LINE, GAP_S, gapped_3010b_lov

BEFORE = 2.0 * GAP_AFTER_LINE
AFTER = 2.0 * (GAP_AFTER_LINE + 1) + int(GAP_S)


def crossing(x, y) -> list:
    """Finite points inside the hole, and segments joining its two sides."""
    inside = [x[k] for k in range(len(x)) if math.isfinite(y[k]) and BEFORE < x[k] < AFTER]
    joins = [(x[k], x[k + 1]) for k in range(len(x) - 1)
             if math.isfinite(y[k]) and math.isfinite(y[k + 1]) and x[k] <= BEFORE + 1 and x[k + 1] >= AFTER - 1]
    return inside + joins


@pytest.mark.parametrize("view", [None, (BEFORE - 3000, AFTER + 3000), (BEFORE - 30, AFTER + 30)])
def test_the_live_plot_never_draws_across_a_hole(qtbot, view):
    live = LiveView()
    qtbot.addWidget(live)
    live.resize(1366, 500)
    live.show()
    plot = live.plot
    for sample in read_log(gapped_3010b_lov()).samples:
        live.series.add_telemetry(sample)
    plot.refresh()
    if view is None:
        plot.show_all()
    else:
        plot.set_follow(False)
        plot.tplot.setXRange(*view, padding=0)
    plot.refresh()
    if view is None:
        assert plot.level > 0                     # the envelope, not the samples, is drawn
    for name, curve in plot.curves.items():
        x, y = curve.getData()
        assert len(x) and crossing(x, y) == [], name
    x, y = plot.current_fill.getData()
    assert len(x) and crossing(x, y) == []


def test_the_live_readout_says_no_data_in_the_hole(qtbot):
    live = LiveView()
    qtbot.addWidget(live)
    live.resize(1366, 500)
    live.show()
    for sample in read_log(gapped_3010b_lov()).samples:
        live.series.add_telemetry(sample)
    live.plot.refresh()
    assert live.readout.show_at((BEFORE + AFTER) / 2)
    assert live.readout.text().endswith("· no data")
    assert live.readout.show_at(BEFORE - 1) and " V · " in live.readout.text()
