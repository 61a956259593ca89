"""The log viewer, offscreen: a log as a document, its totals, the cursor readout, overlays."""
from pathlib import Path

import pytest

from zuml_studio.ui.logs import LogWindow

LOGS = Path(__file__).resolve().parents[2] / "data" / "logs"
X8 = str(LOGS / "X8_LiPo_5S_2200mA_Charge_4.txt")


@pytest.fixture
def viewer(qtbot):
    window = LogWindow()
    qtbot.addWidget(window)
    window.resize(1366, 768)
    window.show()
    return window


def test_a_log_opens_as_a_document_with_totals_and_bands(viewer):
    document = viewer.open_path(X8)
    assert viewer.tabs.count() == 1 and viewer.tabs.tabText(0) == "X8_LiPo_5S_2200mA_Charge_4.txt"
    totals = document.totals.text()
    assert "Junsi iCharger X8" in totals and "2016 mAh" in totals and "6.02 A" in totals
    plot = document.plot
    assert len(plot.layers) == 1 and [p.state for p in plot._phases] == ["charge"]
    assert plot.vplot.getAxis("right").scale == pytest.approx(1 / 5)        # the per-cell axis
    assert "5 cells (right axis)" in plot.legends[plot.vplot].names()


def test_cursor_readout_names_time_values_and_phase(viewer):
    document = viewer.open_path(X8)
    text = document.plot.set_cursor(600.2)
    sample = document.log.samples[600]
    assert text.startswith("0:10:00  ")
    assert f"{sample.voltage_v:.3f} V" in text and f"{sample.current_a:+.3f} A" in text
    assert f"{sample.temp_c:.1f} °C" in text and "charge" in text
    assert "cells " + " ".join(f"{c:.3f}" for c in sample.cells_v) in text
    assert document.readout.text() == text
    assert all(line.isVisible() for line in document.plot.cursor_lines)


def test_cycles_of_one_log_are_laid_over_from_zero(viewer):
    document = viewer.open_path(str(LOGS / "eStationBC6_2008-07-05_EmpfaengerAA.osd"))
    assert document.cycles_box.isEnabled()
    document.cycles_box.setChecked(True)
    layers = document.plot.layers
    assert [layer.name for layer in layers] == ["charge 1", "charge 2"]
    assert all(layer.data["t"][0] == 0.0 for layer in layers)
    assert document.plot._phases == []               # bands belong to one time line, not to laid-over cycles
    assert "charge 2: " in document.plot.readout(600.0)


def test_another_log_laid_over_and_hidden_again(viewer):
    document = viewer.open_path(X8)
    assert viewer.add_path(str(LOGS / "406DUO_Turnigy_4S_1500_A_Charge_0_CH1.txt"))
    assert [layer.name for layer in document.plot.layers] == ["X8_LiPo_5S_2200mA_Charge_4.txt",
                                                              "406DUO_Turnigy_4S_1500_A_Charge_0_CH1.txt"]
    from PySide6.QtCore import Qt
    document.layer_list.item(0).setCheckState(Qt.CheckState.Unchecked)
    assert len(document.plot.layers) == 1 and len(document.plot._phases) == 1


def test_a_file_that_is_no_log_gets_a_message_not_a_tab(viewer, tmp_path, qtbot):
    junk = tmp_path / "junk.txt"
    junk.write_bytes(b"hello\n")
    assert viewer.open_path(str(junk)) is None
    assert viewer.tabs.count() == 0
    box = viewer.findChild(object, "logErrorBox")
    assert box is not None and "not a log file" in box.text()


def test_export_csv_from_the_window(viewer, tmp_path):
    viewer.open_path(X8)
    target = tmp_path / "x8.csv"
    assert viewer.export_csv(str(target))
    lines = target.read_text(encoding="utf-8").splitlines()
    assert len(lines) == 1376 and lines[0].endswith("cell5_v")


def test_main_window_file_menu_opens_the_log_viewer(make_window):
    window = make_window()
    assert window.act_open_log in window.menuBar().actions()[0].menu().actions()
    viewer = window.open_log(X8)
    assert viewer.tabs.count() == 1 and viewer.isVisible()
    assert window.open_log(str(LOGS / "X6_LiFe_10-3A_Cycle_2.txt")) is viewer and viewer.tabs.count() == 2
    viewer.close()


def test_a_raw_capture_opens_with_its_driver_phases(viewer):
    """A raw serial capture (iCharger 306B lines) opens like any log, decoded by its driver."""
    document = viewer.open_path(str(LOGS.parent / "realdata" / "icharger306B_RB_1000_lines_head300.txt"))
    assert document.log.format == "raw-capture"
    assert "Junsi iCharger (106B/206B/208B/306B/3010B)" in document.totals.text()
    # the bands: the "info" pause (idle) between the first two charges has none
    assert [p.state for p in document.plot._phases] == ["charge", "charge", "discharge", "charge"]
