"""The log viewer, offscreen: a log as a document, its totals, the cursor readout, overlays."""
from pathlib import Path

import pytest

from zuml_studio.ui.logs import LogWindow

LOGS = Path(__file__).resolve().parents[2] / "data" / "logs"
X8 = str(LOGS / "X8_LiPo_5S_2200mA_Charge_4.txt")


READ_MS = 30_000


@pytest.fixture
def viewer(qtbot):
    window = LogWindow()
    qtbot.addWidget(window)
    window.resize(1366, 768)
    window.show()
    return window


def opened(viewer, qtbot, path):
    """Open a log (read in the background) and wait for its document."""
    with qtbot.waitSignal(viewer.documentOpened, timeout=READ_MS) as blocker:
        assert viewer.open_path(path) is None           # it returns at once
    return blocker.args[0]


def test_a_log_opens_as_a_document_with_totals_and_bands(viewer, qtbot):
    document = opened(viewer, qtbot, X8)
    assert viewer.tabs.count() == 1 and viewer.tabs.tabText(0) == "X8_LiPo_5S_2200mA_Charge_4.txt"
    totals = document.totals.text()
    assert "Junsi iCharger X8" in totals and "2016 mAh" in totals and "6.02 A" in totals
    plot = document.plot
    assert len(plot.layers) == 1 and [p.state for p in plot._phases] == ["charge"]
    assert plot.vplot.getAxis("right").scale == pytest.approx(1 / 5)        # the per-cell axis
    assert plot.legends[plot.vplot].names() == ["pack voltage", "cell 1 (right axis)", "cell 2", "cell 3", "cell 4",
                                                "cell 5"]          # each cell its own entry


def test_cursor_readout_names_time_values_and_phase(viewer, qtbot):
    document = opened(viewer, qtbot, X8)
    text = document.plot.set_cursor(600.2)
    sample = document.log.samples[600]
    assert text.startswith("0:10:00  ")
    assert f"{sample.voltage_v:.3f} V" in text and f"{sample.current_a:+.3f} A" in text
    assert f"{sample.temp_c:.1f} °C" in text and "charge" in text
    assert "cells " + " ".join(f"{c:.3f}" for c in sample.cells_v) in text
    assert document.readout.text() == text
    assert all(line.isVisible() for line in document.plot.cursor_lines)


def test_cycles_of_one_log_are_laid_over_from_zero(viewer, qtbot):
    document = opened(viewer, qtbot, str(LOGS / "eStationBC6_2008-07-05_EmpfaengerAA.osd"))
    assert document.cycles_box.isEnabled()
    document.cycles_box.setChecked(True)
    layers = document.plot.layers
    assert [layer.name for layer in layers] == ["charge 1", "charge 2"]
    assert all(layer.data["t"][0] == 0.0 for layer in layers)
    assert document.plot._phases == []               # bands belong to one time line, not to laid-over cycles
    assert "charge 2: " in document.plot.readout(600.0)


def test_another_log_laid_over_and_hidden_again(viewer, qtbot):
    document = opened(viewer, qtbot, X8)
    with qtbot.waitSignal(viewer.overlayAdded, timeout=READ_MS) as blocker:
        viewer.add_path(str(LOGS / "406DUO_Turnigy_4S_1500_A_Charge_0_CH1.txt"))
    assert blocker.args == [document]
    assert [layer.name for layer in document.plot.layers] == ["X8_LiPo_5S_2200mA_Charge_4.txt",
                                                              "406DUO_Turnigy_4S_1500_A_Charge_0_CH1.txt"]
    from PySide6.QtCore import Qt
    document.layer_list.item(0).setCheckState(Qt.CheckState.Unchecked)
    assert len(document.plot.layers) == 1 and len(document.plot._phases) == 1


def test_a_file_that_is_no_log_gets_a_message_not_a_tab(viewer, tmp_path, qtbot):
    junk = tmp_path / "junk.txt"
    junk.write_bytes(b"hello\n")
    with qtbot.waitSignal(viewer.readFailed, timeout=READ_MS) as blocker:
        viewer.open_path(str(junk))
    assert "not a log file" in blocker.args[0]
    assert viewer.tabs.count() == 0 and not viewer.is_reading() and not viewer.busy.isVisible()
    box = viewer.findChild(object, "logErrorBox")
    assert box is not None and "not a log file" in box.text()


def test_export_csv_from_the_window(viewer, tmp_path, qtbot):
    opened(viewer, qtbot, X8)
    target = tmp_path / "x8.csv"
    assert viewer.export_csv(str(target))
    lines = target.read_text(encoding="utf-8").splitlines()
    assert len(lines) == 1376 and lines[0].endswith("cell5_v")


def test_main_window_file_menu_opens_the_log_viewer(make_window, qtbot):
    window = make_window()
    assert window.act_open_log in window.menuBar().actions()[0].menu().actions()
    viewer = window.open_log(X8)
    assert viewer.isVisible()
    qtbot.waitUntil(lambda: viewer.tabs.count() == 1, timeout=READ_MS)
    assert window.open_log(str(LOGS / "X6_LiFe_10-3A_Cycle_2.txt")) is viewer
    qtbot.waitUntil(lambda: viewer.tabs.count() == 2, timeout=READ_MS)
    viewer.close()


def test_a_raw_capture_opens_with_its_driver_phases(viewer, qtbot):
    """A raw serial capture (iCharger 306B lines) opens like any log, decoded by its driver."""
    document = opened(viewer, qtbot, str(LOGS.parent / "realdata" / "icharger306B_RB_1000_lines_head300.txt"))
    assert document.log.format == "raw-capture"
    assert "Junsi iCharger (106B/206B/208B/306B/3010B)" in document.totals.text()
    # the bands: the "info" pause (idle) between the first two charges has none
    assert [p.state for p in document.plot._phases] == ["charge", "charge", "discharge", "charge"]


def test_reading_runs_off_the_gui_thread_in_order_with_progress_shown(viewer, qtbot, monkeypatch):
    """Two logs asked for at once: the window says what it reads and keeps handling events;
    they open one after the other, in the order asked for."""
    import threading

    from zuml_studio.ui.logs import log_window
    threads = []
    real = log_window._read_and_prepare

    def read(path, choices, progress=None):
        threads.append(threading.current_thread())
        return real(path, choices, progress)
    monkeypatch.setattr(log_window, "_read_and_prepare", read)
    docs = []
    viewer.documentOpened.connect(docs.append)
    viewer.open_path(X8)
    viewer.open_path(str(LOGS / "X6_LiFe_10-3A_Cycle_2.txt"))
    assert viewer.is_reading() and viewer.busy.isVisible()
    assert "X8_LiPo_5S_2200mA_Charge_4.txt" in viewer.busy_label.text() and "1 more" in viewer.busy_label.text()
    qtbot.waitUntil(lambda: len(docs) == 2, timeout=READ_MS)
    assert [d.name for d in docs] == ["X8_LiPo_5S_2200mA_Charge_4.txt", "X6_LiFe_10-3A_Cycle_2.txt"]
    assert threading.main_thread() not in threads and len(threads) == 2
    assert viewer.tabs.count() == 2 and not viewer.is_reading() and not viewer.busy.isVisible()


def test_a_reader_bug_is_said_in_the_window(viewer, qtbot, monkeypatch):
    def broken(path, choices, progress=None):
        raise ZeroDivisionError("division by zero")
    monkeypatch.setattr("zuml_studio.ui.logs.log_window._read_and_prepare", broken)
    with qtbot.waitSignal(viewer.readFailed, timeout=READ_MS) as blocker:
        viewer.open_path(X8)
    assert "internal error: ZeroDivisionError" in blocker.args[0] and "X8_LiPo" in blocker.args[0]
    assert viewer.findChild(object, "logErrorBox") is not None and viewer.tabs.count() == 0


def test_the_readout_and_the_cycles_are_named_in_the_users_language(viewer, qtbot):
    from zuml_studio import i18n

    i18n.install("ru")
    try:
        document = opened(viewer, qtbot, str(LOGS / "eStationBC6_2008-07-05_EmpfaengerAA.osd"))
        assert document.plot.set_cursor(600.0).endswith("  разряд")        # the cycle starts with a discharge
        document.cycles_box.setChecked(True)
        assert [layer.name for layer in document.plot.layers] == ["заряд 1", "заряд 2"]
    finally:
        i18n.install("en")


def test_a_long_raw_capture_shows_how_far_its_reading_is(viewer, qtbot, monkeypatch, tmp_path):
    """Issue 27: a day-long capture is megabytes; its decoding reports its progress to the bar."""
    from zuml_studio.streams.drivers import CHOOSE_ON
    from zuml_studio.ui.logs import log_window
    lines = (LOGS.parent / "realdata" / "icharger306B_RB_1000_lines_head300.txt").read_bytes()
    capture = tmp_path / "day.txt"
    capture.write_bytes(lines * (3 * CHOOSE_ON // len(lines) + 1))
    seen = []
    real = log_window.LogWindow._show_progress

    def _show_progress(self, done, total):       # PySide resolves a connected method by its name
        real(self, done, total)
        seen.append((done, total, self.busy.maximum(), self.busy.value()))
    monkeypatch.setattr(log_window.LogWindow, "_show_progress", _show_progress)
    document = opened(viewer, qtbot, str(capture))
    assert document.log.format == "raw-capture"
    size = capture.stat().st_size
    assert [d for d, _t, _m, _v in seen] == sorted(d for d, _t, _m, _v in seen) and len(seen) >= 3
    assert seen[-1] == (size, size, 1000, 1000) and all(t == size for _d, t, _m, _v in seen)
    assert viewer.busy.maximum() == 0 or not viewer.busy.isVisible()


def test_a_nimh_log_without_cell_voltages_has_no_per_cell_axis(viewer, qtbot):
    # The iCharger 3010B charging 4 NiMH cells sends 5.2 V in its first cell slot: no cell (issue 33).
    document = opened(viewer, qtbot, str(LOGS.parent / "realdata" / "icharger3010B_2500NiMh_lines.txt"))
    assert document.log.cells == 0
    right = document.plot.vplot.getAxis("right")
    assert not document.plot.per_cell_axis and not right.style["showValues"] and right.labelText == ""
    assert document.plot.legends[document.plot.vplot].names() == ["pack voltage"]


def test_the_totals_say_what_their_figures_cannot(viewer, qtbot):
    # The 3010B's counter says 684 mAh, its current integrates to 660: shown, and the difference said.
    document = opened(viewer, qtbot, str(LOGS.parent / "realdata" / "icharger3010B_2500NiMh_lines.txt"))
    text = document.totals.text()
    assert "660 mAh" in text and "the charger&#x27;s counter says in 684 mAh" in text and "differ by 4 %" in text
    document = opened(viewer, qtbot, str(LOGS / "eStationBC6_2008-07-05_EmpfaengerAA.osd"))
    assert "no temperature in this log" in document.totals.text()


def test_a_csv_being_read_fills_the_progress_bar(viewer, qtbot, monkeypatch, tmp_path):
    # Issue 33 §1: a large CSV says how far its reading is, block by block (blocks made small here).
    from zuml_studio.logs import csv_import
    monkeypatch.setattr(csv_import, "TEXT_BLOCK", 256)
    path = tmp_path / "long.csv"
    path.write_text("Zeit [s];Spannung [V];Strom [A]\n" +
                    "".join(f"{k};{7.4 + k * 0.001:.3f};2,0\n".replace(".", ",") for k in range(400)))
    shown = []
    real = viewer._show_progress

    def record(done, total):
        real(done, total)
        shown.append((done, total, viewer.busy.maximum(), viewer.busy.value()))
    monkeypatch.setattr(viewer, "_show_progress", record)
    document = opened(viewer, qtbot, str(path))
    assert len(document.log.samples) == 400
    size = path.stat().st_size
    assert len(shown) > 5 and shown[-1] == (size, size, 1000, 1000)
    assert [s[3] for s in shown] == sorted(s[3] for s in shown)        # it only goes forward
