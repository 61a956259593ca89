"""The Device panel against the built-in virtual charger (a VirtualCharger behind a pty, reached
through the same ChargerClient a real charger is): connect, Compile & Flash, START, the live
plot and its phase bands, STOP, disconnect, shutdown without a thread left."""
import csv
import os

import numpy as np
import pytest
from PySide6.QtCore import Qt

from device_helpers import WAIT_MS, click_flash, connect, flash_and_start, python_threads, wait_threads

pytestmark = pytest.mark.skipif(os.name != "posix", reason="the built-in virtual charger uses a pty here")


def test_virtual_charger_flash_run_plot_stop_shutdown(qtbot, make_panel):
    baseline = python_threads()
    panel = make_panel()
    assert panel.objectName() == "devicePanel"
    assert panel.plot.objectName() == "livePlot"
    assert panel.ports.combo.itemText(0) == "Virtual charger (built-in)"
    assert panel.ports.target() == "virtual"
    assert panel.ports.baudrate() == 115200
    panel.v_speed.setValue(2000)          # a 65-minute NiMh charge in about two seconds
    panel.rate.setValue(50)
    connect(qtbot, panel)
    assert panel.is_connected()
    assert "iMAX B6" in panel.info_label.full_text() and "EEPROM 1024 bytes" in panel.info_label.full_text()
    assert panel.slot_names() == []
    assert panel.free_label.text().startswith("1024 of 1024 bytes free")
    assert panel.pp_labels["serial"].text().startswith("ZUML-VIRT-0001")
    assert panel.virtual_battery() == "NiMh:2000:4"          # from the macro's AKK_TYPE

    # Compile & Flash in one click
    text = click_flash(qtbot, panel)
    assert text.startswith("Flashed NiMh-dV into slot 0: 38 bytes,") and text.endswith("verified.")
    assert panel.slot_names() == ["NiMh-dV"]
    assert panel.table.item(0, 1).text() == "NiMh-dV" and panel.table.item(0, 3).text() == "NiMh"
    assert panel.table.item(0, 4).text() == "ok"
    assert panel.free_label.text().startswith("986 of 1024 bytes free")
    assert panel.run_slot.currentData() == 0
    assert panel.connection.virtual_device.eeprom_image[:38] == panel._get_record()[0]

    # the same macro again: nothing to write
    with qtbot.waitSignal(panel.flashFinished, timeout=WAIT_MS) as again:
        panel.flash()
    assert again.args[0] and "nothing to write" in again.args[1]

    # START: charge, current 2 A, no sensor; the plot fills and the phase band appears
    panel.set_start_params(task="charge", capacity_mah=2000, current_a=2.0, series=4, sensor=False)
    # How many frames a 2-second run sends depends on how often the machine lets it run (36 on a loaded
    # one): the test waits for the plot to have some, not for a count.
    with qtbot.waitSignal(panel.telemetryReceived, timeout=WAIT_MS, check_params_cb=lambda n: n > 0):
        with qtbot.waitSignal(panel.startFinished, timeout=WAIT_MS) as started:
            qtbot.mouseClick(panel.start_button, Qt.MouseButton.LeftButton)
        assert started.args == [True, "Started NiMh-dV (slot 0): charge."]
    qtbot.waitUntil(lambda: panel.plot.points > 1, timeout=WAIT_MS)      # the plot redraws on its own timer
    qtbot.waitUntil(lambda: panel.plot.band_count() >= 1, timeout=WAIT_MS)
    qtbot.waitUntil(lambda: any(p.closed for p in panel.plot.phases()), timeout=WAIT_MS)
    phase = panel.plot.phases()[0]
    assert (phase.section, phase.index) == ("charge", 1)
    assert phase.reason == "IF(DELTA_PEAK>0.01S) STOP_FAZE"
    assert 3000 < phase.end_s - phase.start_s < 5000         # about 65 minutes of macro time
    spans = panel.plot.band_items[0].spans()
    assert spans and spans[0] == (phase.start_s, phase.end_s)
    qtbot.waitUntil(lambda: "finished" in panel.message_text(), timeout=WAIT_MS)
    assert "end of macro" in panel.message_text()
    # The run is over (the reader thread adds no more rows): once the plot has drawn all the buffer
    # holds, the two are compared.
    qtbot.waitUntil(lambda: panel.plot.points == panel.series.buffer.snapshot()[0], timeout=WAIT_MS)
    x, v = np.asarray(panel.series.buffer.column("t")), np.asarray(panel.series.buffer.column("voltage"))
    assert len(x) == panel.plot.points and (x[1:] >= x[:-1]).all()
    assert 4.5 < float(v.max()) < 7.5
    drawn_x, drawn_v = panel.plot.curves["voltage"].getData()
    # A NaN breaks the line where frames came late (a gap, more of them on a loaded machine): no value of its own
    drawn_v = drawn_v[~np.isnan(drawn_v)]
    assert len(drawn_x) and (drawn_x[1:] >= drawn_x[:-1]).all() and set(drawn_v) <= set(v)

    with qtbot.waitSignal(panel.operationFinished, timeout=WAIT_MS) as stopped:
        qtbot.mouseClick(panel.stop_button, Qt.MouseButton.LeftButton)
    assert stopped.args[0] == "stop" and stopped.args[1]

    # disconnect: the plot and the CSV stay
    points = panel.plot.points
    with qtbot.waitSignal(panel.connectedChanged, timeout=WAIT_MS) as gone:
        qtbot.mouseClick(panel.connect_button, Qt.MouseButton.LeftButton)
    assert gone.args == [False]
    assert not panel.is_connected() and panel.connect_button.text() == "Connect"
    assert panel.plot.points == points
    assert panel.session_file is not None and panel.session_file.exists()

    panel.shutdown()
    assert not panel.connection.thread.isRunning()
    assert wait_threads(baseline) == set()


def test_session_csv_is_written_and_flushed_while_connected(qtbot, make_panel):
    panel = make_panel()
    panel.v_speed.setValue(500)
    panel.rate.setValue(20)
    connect(qtbot, panel)
    path = panel.session_file
    assert path.parent == panel.session_dir and path.name.startswith("session-") and path.suffix == ".csv"
    assert path.name in panel.session_label.full_text()
    flash_and_start(qtbot, panel)
    qtbot.waitUntil(lambda: panel.plot.points > 10, timeout=WAIT_MS)

    def rows():
        with open(path, encoding="utf-8", newline="") as fh:
            return list(csv.reader(fh))

    # flushed at least every second: readable while the link is open
    qtbot.waitUntil(lambda: sum(1 for r in rows()[1:] if r[1] == "charge" and r[3]) > 10, timeout=5000)
    table = rows()
    assert table[0] == ["time_s", "section", "phase", "voltage_v", "current_a", "temp_c", "heatsink_c", "mah_in",
                        "mah_out", "event"]
    events = [r[-1] for r in table[1:] if r[-1]]
    assert "section charge" in events and "phase_start charge 1" in events
    measured = [r for r in table[1:] if r[1] == "charge" and r[3]]
    assert all(len(r) == 10 for r in measured)
    assert float(measured[-1][4]) == pytest.approx(2.0, abs=0.05)      # the current entered at start
    assert panel.is_connected()
    panel.stop()
    panel.disconnect()
    qtbot.waitUntil(lambda: not panel.is_connected() and not panel.connection.busy, timeout=WAIT_MS)
    assert len(rows()) >= len(table)


def test_follow_keeps_the_newest_minutes_and_a_user_zoom_stops_it(qtbot, make_panel):
    panel = make_panel()
    panel.v_speed.setValue(2000)
    panel.rate.setValue(50)
    panel.follow_minutes.setValue(10)
    connect(qtbot, panel)
    flash_and_start(qtbot, panel)
    qtbot.waitUntil(lambda: panel.series.last_x() > 800 and panel.plot.points > 20, timeout=WAIT_MS)

    def width() -> float:
        x0, x1 = panel.plot.tplot.vb.viewRange()[0]
        return x1 - x0

    # the view follows on the plot's next frame: wait for it, not for a time (a loaded machine paints late)
    qtbot.waitUntil(lambda: width() == pytest.approx(10 * 60 * 1.03, rel=0.05), timeout=WAIT_MS)
    # the user pans: follow goes off and the view stays while telemetry goes on coming
    panel.plot.tplot.vb.translateBy(x=-120)
    panel.plot.tplot.vb.sigRangeChangedManually.emit([True, False])
    assert not panel.follow.isChecked()
    view = panel.plot.tplot.vb.viewRange()[0]
    drawn = panel.plot.points          # the plot takes new points (and would follow) on its frames
    qtbot.waitUntil(lambda: panel.plot.points > drawn + 10, timeout=WAIT_MS)
    assert panel.plot.tplot.vb.viewRange()[0] == view
    panel.all_button.click()
    lo, hi = panel.plot.tplot.vb.viewRange()[0]
    assert lo <= panel.plot.phases()[0].start_s + 1


def test_speed_changes_live(qtbot, make_panel):
    panel = make_panel()
    connect(qtbot, panel)
    device = panel.connection.virtual_device
    assert device.speed == 60
    panel.v_speed.setValue(500)
    assert device.speed == 500


def test_layout_fits_a_small_dock(qtbot, make_panel):
    panel = make_panel(size=(1000, 320))
    qtbot.waitUntil(lambda: panel.plot.width() >= 280 and panel.plot.height() >= 150, timeout=WAIT_MS)
    assert panel.controls_scroll.width() + panel.plot.width() <= 1000
    for w in (panel.flash_button, panel.start_button, panel.stop_button, panel.connect_button):
        assert w.isVisibleTo(panel)
    panel.resize(1400, 380)
    qtbot.waitUntil(lambda: panel.plot.width() >= 700, timeout=WAIT_MS)
    # at the dock's size nothing in the controls scrolls
    assert not panel.controls_scroll.verticalScrollBar().isVisible()


@pytest.mark.parametrize("choice", ["dark", "light"])
def test_the_panel_s_coloured_texts_follow_the_palette(qtbot, make_panel, choice):
    from PySide6.QtWidgets import QApplication
    from zuml_studio.ui.base import theme
    panel = make_panel()
    panel.show_message("Flashed", "ok")
    try:
        theme.apply_theme(choice)
        QApplication.processEvents()
        colours = theme.DARK if choice == "dark" else theme.LIGHT
        assert panel.message.styleSheet() == f"color:{colours.ok};"
        assert panel.info_label.styleSheet() == f"color:{colours.muted};"
        assert panel.session_label.styleSheet() == f"color:{colours.muted};"
    finally:
        theme.apply_theme("system")
