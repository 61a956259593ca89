"""The device panel watching monitor-only chargers: a replayed recording is recognised, plotted
and logged with its cells; Flash and Start are off with the reason; the driver chooser; HID
chargers in the port list."""
import csv
from pathlib import Path

from device_helpers import WAIT_MS
from zuml_studio.streams.drivers import DRIVERS
from zuml_studio.device.links.ports import PortInfo

DATA = Path(__file__).resolve().parents[2] / "data" / "realdata"


def test_replay_a_recording_into_the_panel(qtbot, make_panel, tmp_path):
    src = tmp_path / "icharger.txt"
    src.write_bytes(b"".join((DATA / "icharger306B_RB_1000_lines_head300.txt").read_bytes().splitlines(True)[:80]))
    panel = make_panel((1366, 520))
    with qtbot.waitSignal(panel.connectedChanged, timeout=WAIT_MS) as blocker:
        assert panel.replay(src, speed=1000)
    assert blocker.args == [True] and panel.is_monitoring()
    title = DRIVERS["icharger"].title
    qtbot.waitUntil(lambda: panel.monitor.link.good == 80, timeout=WAIT_MS)
    qtbot.waitUntil(lambda: "80 records" in panel.info_label.full_text(), timeout=WAIT_MS)
    assert panel.info_label.full_text() == f"{title} · monitor-only · 80 records · 0 bad"
    assert not panel.flash_button.isEnabled() and not panel.start_button.isEnabled()
    assert panel.flash_button.toolTip() == f"{title} cannot run ZUML macros: it is monitor-only: Flash and Start are off"
    assert "monitor-only" in panel.result_label.text()
    assert not panel.replay_button.isEnabled() and not panel.driver_combo.isEnabled()
    with qtbot.waitSignal(panel.connectedChanged, timeout=WAIT_MS) as blocker:
        panel.disconnect()
    assert blocker.args == [False] and not panel.is_monitoring()
    assert "80 records, 0 bad" in panel.message_text()
    assert panel.flash_button.toolTip().startswith("Write the editor's macro")
    assert panel.replay_button.isEnabled()
    with panel.session_file.open() as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) == 80 and rows[0]["cell3_v"] == "4.192" and rows[0]["voltage_v"] == "12.645"
    assert rows[-1]["time_s"] == "158.0"


def test_after_a_replay_the_port_is_the_one_chosen_before_and_connect_reaches_it(qtbot, make_panel, tmp_path):
    """The replay's pty went into "or a port / URL" and stayed: Connect with "Virtual charger
    (built-in)" chosen then tried the dead pty."""
    from device_helpers import connect
    src = tmp_path / "icharger.txt"
    src.write_bytes(b"".join((DATA / "icharger306B_RB_1000_lines_head300.txt").read_bytes().splitlines(True)[:20]))
    panel = make_panel((1366, 520))
    assert panel.ports.target() == "virtual"
    with qtbot.waitSignal(panel.connectedChanged, timeout=WAIT_MS):
        assert panel.replay(src, speed=1000)
    assert panel.ports.target() != "virtual"            # the pty, while the replay plays
    with qtbot.waitSignal(panel.connectedChanged, timeout=WAIT_MS):
        panel.disconnect()
    assert panel.ports.target() == "virtual" and panel.ports.url.text() == ""
    connect(qtbot, panel)
    assert "virtual" in panel.message_text()


def test_a_file_that_is_no_recording(qtbot, make_panel, tmp_path):
    bad = tmp_path / "x.txt"
    bad.write_text("nothing to see\n")
    panel = make_panel()
    assert not panel.replay(bad)
    assert "no recording recognised" in panel.message_text() and not panel.is_monitoring()
    (tmp_path / "folder.txt").mkdir()
    for path, said in ((tmp_path / "folder.txt", "is a folder, not a file"), (Path("/dev/zero"), "a device, not a file")):
        assert not panel.replay(path)         # /dev/zero was read until the memory ran out
        assert said in panel.message_text() and not panel.is_monitoring()


def test_driver_chooser_and_hid_chargers_in_the_port_list(qtbot, tmp_path, editor):
    from zuml_studio.ui.device import DevicePanel
    hid = PortInfo("hid:0483:5751", "Junsi iCharger 4010Duo USB HID (USB HID)", "USB VID:PID=0483:5751", 0x0483, 0x5751)
    panel = DevicePanel(editor, tmp_path / "s", port_lister=lambda: [hid])
    qtbot.addWidget(panel)
    panel.show()
    try:
        combo = panel.driver_combo
        assert [combo.itemData(i) for i in range(combo.count())] == ["auto", "zuml", *DRIVERS]
        assert combo.currentData() == "auto"
        assert not combo.isEnabled()                      # the built-in virtual charger speaks ZUML
        panel.ports.refresh()
        qtbot.waitUntil(lambda: panel.ports.ports() == ["hid:0483:5751"], timeout=WAIT_MS)
        panel.ports.set_target("hid:0483:5751")
        assert combo.isEnabled()
    finally:
        panel.shutdown()


def test_a_hid_charger_is_watched_by_its_usb_ids(qtbot, make_panel, monkeypatch):
    import sys
    import threading
    import types
    report = bytes.fromhex("2C 10 01 F8 7D 07 00 02 01 00 E5 FF 04 87 2B 3C CF FF FF FF 64 01 00 00 02 0F 0B 0F 0E "
                           "0F 00 0F")          # icharger_logview.md, section C
    hid = types.ModuleType("hid")
    hid.enumerate = lambda vid=0, pid=0: [{"vendor_id": 0x0483, "product_id": 0x5751, "path": b"p"}]

    class Device:
        queue = [report] * 5

        def open_path(self, path):
            pass

        def read(self, n, timeout_ms):
            if Device.queue:
                return list(Device.queue.pop())
            threading.Event().wait(timeout_ms / 1000)
            return []

        def write(self, data):
            return len(data)

        def close(self):
            pass

    hid.device = Device
    monkeypatch.setitem(sys.modules, "hid", hid)
    panel = make_panel()
    panel.driver_combo.setCurrentIndex(panel.driver_combo.findData("zuml"))   # ZUML is serial: the ids decide
    with qtbot.waitSignal(panel.connectedChanged, timeout=WAIT_MS) as blocker:
        assert panel.connect_to("hid:0483:5751")
    assert blocker.args == [True]
    qtbot.waitUntil(lambda: panel.info_label.full_text().startswith(
        f"{DRIVERS['icharger-hid'].title} · monitor-only · 5 records"), timeout=WAIT_MS)
    assert not panel.start_button.isEnabled()
    with qtbot.waitSignal(panel.connectedChanged, timeout=WAIT_MS):
        panel.disconnect()


def test_a_replay_after_a_virtual_charger_session_starts_a_fresh_run(qtbot, make_panel):
    """Replaying the real iCharger 208B .lov (3 cells, tests/data/logs) after a run on the 4-cell
    virtual charger: a run of its own from 0 s (the virtual run kept in the run list), the per-cell
    axis by the recording's 3 cells, and the virtual charger's macros and passport gone."""
    from device_helpers import connect, flash_and_start

    panel = make_panel((1366, 520))
    panel.series_spin.setValue(4)
    connect(qtbot, panel)
    assert flash_and_start(qtbot, panel)[0]
    qtbot.waitUntil(lambda: len(panel.live.series) > 5, timeout=WAIT_MS)
    assert panel.run.run_slot.count() and panel.charger.table.rowCount()
    panel.run.stop_and_wait()
    with qtbot.waitSignal(panel.connectedChanged, timeout=WAIT_MS):
        panel.disconnect()
    virtual = panel.live.series
    virtual_points = len(virtual)
    lov = DATA.parent / "logs" / "iCharger208B_Storage.lov"
    with qtbot.waitSignal(panel.connectedChanged, timeout=WAIT_MS) as blocker:
        assert panel.replay(lov, speed=1000)
    assert blocker.args == [True]
    qtbot.waitUntil(lambda: panel.monitor.link.good == 68, timeout=WAIT_MS)
    qtbot.waitUntil(lambda: len(panel.live.series) == 68, timeout=WAIT_MS)
    series = panel.live.series
    assert series is not virtual and len(virtual) == virtual_points          # nothing appended to the old run
    assert any(s is virtual for _name, s in panel.live.runs)
    t = series.buffer.column("t")
    assert t[0] == 0.0 and t[67] == 134.0                                 # 2 s records, from 0
    assert panel.plot.vplot.getAxis("right").scale == 1 / 3               # per cell by the recording's 3 cells
    assert panel.charger.table.rowCount() == 0 and panel.run.run_slot.count() == 0
    assert panel.passport.pp_labels["serial"].text() == "—"
    assert panel.run.run_name == "iCharger208B_Storage.lov"
