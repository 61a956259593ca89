"""Measuring in the log viewer: two cursors and the figures between them, curves and cells hidden
and the choice remembered per log format, a legend entry per cell, the cell deviation curve
(the real X8 5S charge, tests/data/logs)."""
from pathlib import Path

import pytest
from PySide6.QtCore import QSettings, Qt

from zuml_studio.ui.logs import LogWindow

LOGS = Path(__file__).resolve().parents[2] / "data" / "logs"
X8 = LOGS / "X8_LiPo_5S_2200mA_Charge_4.txt"
READ_MS = 30_000


@pytest.fixture
def window(qtbot, tmp_path):
    w = LogWindow(QSettings(str(tmp_path / "settings.ini"), QSettings.Format.IniFormat))
    qtbot.addWidget(w)
    w.resize(1366, 768)
    w.show()
    return w


def open_log(window, qtbot, path):
    with qtbot.waitSignal(window.documentOpened, timeout=READ_MS) as blocker:
        window.open_path(str(path))
    return blocker.args[0]


def test_two_cursors_show_what_the_log_says_between_them(window, qtbot):
    document = open_log(window, qtbot, X8)
    plot = document.plot
    document.cursors_box.setChecked(True)
    assert all(line.isVisible() for line in plot.ab_lines["a"] + plot.ab_lines["b"])
    with qtbot.waitSignal(plot.cursorsMoved) as moved:
        plot.set_cursors(300.0, 900.0)
    assert moved.args == [300.0, 900.0]
    samples = {s.time_s: s for s in document.log.samples}
    text = document.between.text()
    assert "0:05:00 – 0:15:00" in text and "10:00 min" in text
    assert f"{samples[900.0].voltage_v - samples[300.0].voltage_v:+.3f} V" in text
    net = (samples[900.0].mah_in - samples[900.0].mah_out) - (samples[300.0].mah_in - samples[300.0].mah_out)
    assert f"{net:+.0f}" in text
    inside = [s.voltage_v for t, s in samples.items() if 300 <= t <= 900]
    assert f"{min(inside):.3f} – {max(inside):.3f} V" in text and f"{sum(inside) / len(inside):.3f}" in text
    # a line dragged in one plot moves in all three
    plot.ab_lines["b"][2].setValue(600.0)
    assert [line.value() for line in plot.ab_lines["b"]] == [600.0] * 3
    assert "0:05:00 – 0:10:00" in document.between.text()
    document.cursors_box.setChecked(False)
    assert not document.between.isVisible() and not plot.ab_lines["a"][0].isVisible()


def test_cells_have_their_own_entries_and_the_deviation_its_axis(window, qtbot):
    document = open_log(window, qtbot, X8)
    plot = document.plot
    keys = [key for key, _name in plot.curve_keys()]
    assert keys == ["voltage", "cell 1", "cell 2", "cell 3", "cell 4", "cell 5", "deviation", "current", "temp",
                    "heatsink"]
    assert "cell deviation (mV, right axis)" in plot.legends[plot.tplot].names()
    deviation = next(curve for _p, curve, role in plot.items if role == "deviation")
    x, y = deviation.getData()
    first = document.log.samples[0]
    assert y[0] == pytest.approx((max(first.cells_v) - min(first.cells_v)) * 1000)
    assert plot.tplot.getAxis("right").labelText == "mV"


def test_hidden_curves_are_remembered_for_logs_of_that_format(window, qtbot):
    document = open_log(window, qtbot, X8)
    document.set_curve_shown("cell 3", False)
    document.set_curve_shown("temp", False)
    plot = document.plot
    shown = {role if isinstance(role, str) else f"cell {role[1] + 1}": curve.isVisible()
             for _p, curve, role in plot.items}
    assert not shown["cell 3"] and not shown["temp"] and shown["cell 2"] and shown["voltage"]
    assert "cell 3" not in plot.legends[plot.vplot].names() and "battery" not in plot.legends[plot.tplot].names()
    # another DUO/X log opens with the same curves hidden; a log of another format shows all
    other = open_log(window, qtbot, LOGS / "406DUO_Turnigy_4S_1500_A_Charge_0_CH1.txt")
    assert other.plot.hidden == {"cell 3", "temp"}
    items = {other.curve_list.item(k).data(Qt.ItemDataRole.UserRole): other.curve_list.item(k).checkState()
             for k in range(other.curve_list.count())}
    assert items["cell 3"] == Qt.CheckState.Unchecked and items["cell 2"] == Qt.CheckState.Checked
    osd = open_log(window, qtbot, LOGS / "PolaronPro_2014-08-23_5S_NiMh_cycle.osd")
    assert osd.plot.hidden == set()
