"""The log viewer on a recording with a 3.2 h hole (the real iCharger 3010B charge laid out as
LogView writes it, tests/logs/logdata.py): nothing is drawn in the hole at any zoom, the phase
band leaves it out, the readout says "no data" there."""
import math
import sys
from pathlib import Path

import pytest

from zuml_studio.ui.logs import LogWindow

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "logs"))
from logdata import GAP_AFTER_LINE, GAP_S, gapped_3010b_lov

READ_MS = 30_000
BEFORE = 2.0 * GAP_AFTER_LINE                       # the last sample before the hole
AFTER = 2.0 * (GAP_AFTER_LINE + 1) + int(GAP_S)     # the first after it


@pytest.fixture
def document(qtbot, tmp_path):
    path = tmp_path / "gapped_3010b.lov"
    path.write_bytes(gapped_3010b_lov())
    window = LogWindow()
    qtbot.addWidget(window)
    window.resize(1366, 768)
    window.show()
    with qtbot.waitSignal(window.documentOpened, timeout=READ_MS) as blocker:
        window.open_path(str(path))
    return blocker.args[0]


def drawn_in_hole(curve) -> list[tuple[float, float]]:
    """Points or segments of the curve's data that lie in the hole."""
    x, y = curve.getData()
    bad = [(x[k], y[k]) for k in range(len(x)) if math.isfinite(y[k]) and BEFORE < x[k] < AFTER]
    bad += [(x[k], x[k + 1]) for k in range(len(x) - 1)
            if math.isfinite(y[k]) and math.isfinite(y[k + 1]) and x[k] <= BEFORE and x[k + 1] >= AFTER]
    return bad


@pytest.mark.parametrize("view", [None, (BEFORE - 600, AFTER + 600), (BEFORE - 20, AFTER + 20)])
def test_no_curve_crosses_the_hole_at_any_zoom(document, qtbot, view):
    plot = document.plot
    if view:
        plot.tplot.setXRange(*view, padding=0)
    curves = [curve for _plot, curve, _role in plot.items]
    assert len(curves) >= 4                         # voltage, cell, current, temperatures
    assert all(c.getData()[0] is not None and len(c.getData()[0]) for c in curves)   # set with the view
    for curve in curves:
        assert drawn_in_hole(curve) == []


def test_the_band_leaves_the_hole_out_and_the_readout_says_no_data(document):
    plot = document.plot
    spans = plot.band_items[0].spans()
    assert spans == [(0.0, BEFORE), (AFTER, plot._t[-1])]
    text = plot.set_cursor((BEFORE + AFTER) / 2)
    assert "no data" in text and " V" not in text
    assert document.readout.text() == text
    assert "V" in plot.set_cursor(BEFORE - 1)
