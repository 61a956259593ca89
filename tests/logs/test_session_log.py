"""The session CSV, without Qt: the simulator's columns plus an event column, one row per
telemetry frame and per event, flushed at least every second by its writer thread."""
import csv
import datetime

import pytest

from helpers import until
from zuml_studio.protocol.messages import DeviceEvent, Telemetry
from zuml_studio.domain.samples import COLUMNS as SIM_COLUMNS
from zuml_studio.logs.session_log import COLUMNS, SessionLog, display_path, event_text, session_path


def telemetry(t=12.0, running=True, temp=25.5):
    return Telemetry(t, "charge", "charge" if running else "", 1, 0, 1 if running else 0, 1 if running else 0,
                     running, False, temp is not None, 5.123, -1.5, temp, 30.25, 120.04, 3.0)


def read(path):
    with open(path, encoding="utf-8", newline="") as fh:
        return list(csv.reader(fh))


def test_columns_are_the_simulators_plus_event():
    assert COLUMNS[:-1] == tuple(SIM_COLUMNS) and COLUMNS[-1] == "event"


def test_session_path_is_dated_and_never_overwrites(tmp_path):
    when = datetime.datetime(2025, 3, 4, 5, 6, 7)
    first = session_path(tmp_path, when)
    assert first.name == "session-20250304-050607.csv"
    first.write_text("")
    assert session_path(tmp_path, when).name == "session-20250304-050607-2.csv"


def test_rows_for_telemetry_and_events(tmp_path):
    path = tmp_path / "s.csv"
    with SessionLog(path, threaded=False) as log:
        log.add_telemetry(telemetry())
        log.add_telemetry(telemetry(13.0, running=False, temp=None))
        log.add_event(DeviceEvent(2, 14.0, "phase_end", "charge", 1, 1, 17, "IF(DELTA_PEAK>0.01S) STOP_FAZE"))
        log.add_event(DeviceEvent(3, 14.0, "finish", "", 0, 0, -1, "end of macro"))
        assert log.rows == 4
    rows = read(path)
    assert rows[0] == list(COLUMNS)
    assert rows[1] == ["12.0", "charge", "1", "5.123", "-1.500", "25.50", "30.25", "120.0", "3.0", ""]
    assert rows[2] == ["13.0", "", "0", "5.123", "-1.500", "", "30.25", "120.0", "3.0", ""]
    assert rows[3] == ["14.0", "charge", "", "", "", "", "", "", "", "phase_end charge 1: IF(DELTA_PEAK>0.01S) STOP_FAZE"]
    assert rows[4][-1] == "finish: end of macro"


def test_the_writer_thread_flushes_by_itself_while_the_log_is_open(tmp_path):
    # It flushes every 0.5 s; a loaded machine may run its thread late, so the test waits for the rows
    # on disk (a state), with a bound far above the period, and never closes the log first.
    path = tmp_path / "live.csv"
    log = SessionLog(path)                   # its own writer thread, flushing every 0.5 s
    try:
        assert read(path) == [list(COLUMNS)]   # the header is on disk at once
        for k in range(100):
            log.add_telemetry(telemetry(float(k)))
        assert until(lambda: len(read(path)) == 101), "not flushed while open"
        # a quiet spell after one more row: flushed too, without anything else arriving
        log.add_event(DeviceEvent(0, 100.0, "section", "charge"))
        assert until(lambda: read(path)[-1][-1] == "section charge"), "the last row not flushed while open"
    finally:
        log.close()
    assert log.rows == 101
    assert not log._thread
    log.add_telemetry(telemetry())          # after close: ignored, never raises
    log.close()


def test_a_failing_disk_is_reported_not_raised(tmp_path):
    log = SessionLog(tmp_path / "x.csv", threaded=False)
    read_only = tmp_path / "ro.csv"
    read_only.write_text("")
    log._fh.close()
    log._fh = open(read_only, "r", encoding="utf-8")     # as a disk that refuses writes would
    log._writer = csv.writer(log._fh)
    log.add_telemetry(telemetry())
    assert log.error and "cannot write" in log.error
    log.close()


def test_event_text_and_display_path(tmp_path, monkeypatch):
    assert event_text(DeviceEvent(0, 0.0, "phase_start", "discharge", 2)) == "phase_start discharge 2"
    assert event_text(DeviceEvent(0, 0.0, "pause", "", 0, 0, -1, "Tc>70")) == "pause: Tc>70"
    monkeypatch.setenv("HOME", str(tmp_path))
    assert display_path(tmp_path / "a" / "b.csv") == "~/a/b.csv"
    assert display_path("/elsewhere/b.csv") == "/elsewhere/b.csv"


def test_add_row_checks_its_length(tmp_path):
    with SessionLog(tmp_path / "r.csv", threaded=False) as log:
        with pytest.raises(ValueError):
            log.add_row(("1", "2"))
        log.add_row(tuple(str(i) for i in range(len(COLUMNS))))
    assert read(tmp_path / "r.csv")[1] == [str(i) for i in range(len(COLUMNS))]


def test_cell_columns_follow_the_first_telemetry(tmp_path):
    """A charger that measures cells adds cell1_v..cellN_v after event; N from the first sample."""
    from dataclasses import replace
    path = tmp_path / "cells.csv"
    log = SessionLog(path, threaded=False, cells=None)
    log.add_telemetry(replace(telemetry(), cells_v=(4.2, 4.19, 4.21)))
    log.add_telemetry(replace(telemetry(13.0), cells_v=(4.2,)))
    log.add_telemetry(replace(telemetry(14.0), cells_v=(4.2, 4.2, 4.2, 4.2)))
    log.close()
    rows = read(path)
    assert rows[0] == list(COLUMNS) + ["cell1_v", "cell2_v", "cell3_v"]
    assert rows[1][-3:] == ["4.200", "4.190", "4.210"]
    assert rows[2][-3:] == ["4.200", "", ""] and len(rows[3]) == len(rows[0])
    assert log.rows == 3


def test_an_empty_session_with_open_cells_still_gets_its_header(tmp_path):
    path = tmp_path / "empty.csv"
    SessionLog(path, threaded=False, cells=None).close()
    assert read(path) == [list(COLUMNS)]


def test_an_idle_charger_is_logged_every_ten_seconds_not_at_the_telemetry_rate(tmp_path):
    now = [0.0]
    with SessionLog(tmp_path / "s.csv", threaded=False, idle_s=10.0, clock=lambda: now[0]) as log:
        for _ in range(300):                    # 30 s of idle frames at 10 Hz
            log.add_telemetry(telemetry(running=False))
            now[0] += 0.1
        assert log.rows == 3
        log.add_telemetry(telemetry(1.0))       # a run: every frame
        log.add_telemetry(telemetry(1.1))
        log.add_telemetry(telemetry(running=False))    # the first idle frame after it is written
        log.add_telemetry(telemetry(running=False))
        assert log.rows == 6

