"""Our own session CSV, the charge helper, summaries and the export CSV."""
import io

import pytest

from zuml_studio.protocol.messages import DeviceEvent, Telemetry
from zuml_studio.logs import LogFormatError, read_log
from zuml_studio.logs.charge import charge_from_counter, integrate_current
from zuml_studio.logs.export import write_csv
from zuml_studio.logs.summary import summarize
from zuml_studio.logs.session_log import SessionLog


def tel(t, v, i, section="charge", temp=25.0, q_in=0.0, q_out=0.0):
    return Telemetry(t, "charge", section, 0, 0, 1, 1, True, False, temp is not None, v, i, temp, 30.0, q_in, q_out)


def session_bytes(tmp_path, items):
    path = tmp_path / "s.csv"
    log = SessionLog(path, threaded=False)
    for item in items:
        (log.add_event if isinstance(item, DeviceEvent) else log.add_telemetry)(item)
    log.close()
    return path.read_bytes()


def test_session_csv_reads_back_with_its_charge_and_events(tmp_path):
    raw = session_bytes(tmp_path, [
        DeviceEvent(0, 0.0, "phase_start", "charge", 1),
        tel(0.0, 4.0, 1.0), tel(1.0, 4.1, 1.0, q_in=0.3), tel(2.0, 4.2, -0.5, "discharge", None, 0.6, 0.1),
        DeviceEvent(1, 2.0, "finish", detail="done"),
    ])
    log = read_log(raw, "s.csv")
    assert log.format == "session-csv" and log.bad_records == 0 and log.meta["events"] == 2
    assert [s.voltage_v for s in log.samples] == [4.0, 4.1, 4.2]
    assert log.samples[2].temp_c is None and log.samples[2].heatsink_c == 30.0
    assert (log.samples[-1].mah_in, log.samples[-1].mah_out) == (0.6, 0.1)   # the device's own count
    assert [p.state for p in log.phases()] == ["charge", "discharge"]


def test_a_new_run_in_a_session_continues_the_time_line(tmp_path):
    raw = session_bytes(tmp_path, [tel(0.0, 4.0, 1.0), tel(5.0, 4.0, 1.0), tel(0.0, 4.0, 1.0), tel(1.0, 4.0, 1.0)])
    assert [s.time_s for s in read_log(raw).samples] == [0.0, 5.0, 5.0, 6.0]


def test_session_rows_that_do_not_fit_are_counted():
    raw = (b"time_s,section,phase,voltage_v,current_a,temp_c,heatsink_c,mah_in,mah_out,event\n"
           b"0.0,charge,1,4.000,1.000,,,0.0,0.0,\n1.0,charge,1,x,1.0,,,0,0,\n2.0,charge\n"
           b"3.0,warp,1,4.0,1.0,,,0,0,\n")
    log = read_log(raw)
    assert len(log.samples) == 1 and log.bad_records == 3


def test_export_writes_si_rows_and_reads_back():
    raw = read_log(b"$N$;x\n$C$;U[V];I[A];T[\xc2\xb0C];Cell 1[V];Cell 2[V]\n$I$;1000\n"
                   b"$8.0;2.0;25;4.0;4.0\n$8.2;2.0;25.5;4.1;4.1\n$8.1;-1.0;26;4.05;4.05\n")
    out = io.StringIO()
    assert write_csv(raw, out) == 3
    lines = out.getvalue().splitlines()
    assert lines[0] == "t_s,voltage_v,current_a,temp_c,charge_in_mah,charge_out_mah,state,cell1_v,cell2_v"
    assert lines[1] == "0.000,8.0000,2.0000,25.00,0.0,0.0,charge,4.0000,4.0000"
    back = read_log(out.getvalue().encode())
    assert back.format == "export-csv" and back.cells == 2
    assert [s.voltage_v for s in back.samples] == [8.0, 8.2, 8.1]
    assert back.samples[1].temp_c == raw.samples[1].temp_c
    assert [s.mah_in for s in back.samples] == pytest.approx([s.mah_in for s in raw.samples], abs=0.05)


def test_open_format_empty_field_makes_the_line_bad():
    # The open format has no "not measured" value: an empty field is not a number, the line is bad.
    log = read_log(b"$N$;x\n$C$;U[V];T[\xc2\xb0C]\n$8.0;25\n$8.0;\n")
    assert len(log.samples) == 1 and log.bad_records == 1


def test_integrate_current_splits_at_zero_crossings_and_skips_gaps():
    ins, outs = integrate_current([60.0 * k for k in range(61)], [1.0] * 61)
    assert ins[-1] == pytest.approx(1000.0) and outs[-1] == 0.0       # 1 A for an hour
    ins, outs = integrate_current([0, 10, 20], [1.0, -1.0, -1.0])
    assert ins[-1] == pytest.approx(5 * 0.5 / 3.6) and outs[-1] == pytest.approx((5 * 0.5 + 10) / 3.6)
    ins, _ = integrate_current([0, 1000], [1.0, 1.0])
    assert ins[-1] == 0.0                              # a gap longer than a minute adds nothing


def test_charge_from_counter_banks_each_phase():
    ins, outs = charge_from_counter([0, 50, 95, 95, 0, -10, -149, -149, 0, 20])
    assert ins[-1] == 115.0 and outs[-1] == 149.0
    assert charge_from_counter([10, 9, 10])[0] == [0, -1, 0]      # rounding jitter is not a new count


def test_a_counter_that_does_not_start_at_zero_counts_from_its_first_value():
    # Akkumatik: a discharge whose counter starts at 1 867 mAh has moved nothing yet.
    ins, outs = charge_from_counter([-1867, -2000, -3317])
    assert (ins[-1], outs[-1]) == (0.0, 1450.0)


def test_summary_fields():
    log = read_log(b"$N$;x\n$C$;U[V];I[A]\n$I$;1000\n$8.0;2.0\n$8.2;2.0\n$8.1;-3.0\n")
    info = summarize(log)
    for key in ("format", "device", "samples", "bad_records", "duration_s", "v_min", "v_max", "i_max_a",
                "charge_in_mah", "charge_out_mah", "cells", "phases"):
        assert key in info
    assert (info["samples"], info["duration_s"], info["v_min"], info["v_max"], info["i_max_a"]) == \
        (3, 2.0, 8.0, 8.2, 3.0)
    assert info["phases"] == [{"state": "charge", "start_s": 0.0, "end_s": 2.0},
                              {"state": "discharge", "start_s": 2.0, "end_s": 2.0}]


def test_unknown_bytes_name_what_was_tried():
    with pytest.raises(LogFormatError, match="tried: .*DataExplorer"):
        read_log(b"hello\n")
    with pytest.raises(LogFormatError, match="empty"):
        read_log(b"")
    with pytest.raises(LogFormatError, match="unknown log format"):
        read_log(b"x", fmt="nope")


def test_a_format_with_ready_samples_joins_through_from_samples():
    # How a live driver's decoder (device/drivers.decode_capture) becomes a log format.
    from zuml_studio.logs.model import from_samples
    samples = [tel(0.0, 4.0, 1.0), tel(1.0, 4.1, 1.0, q_in=0.3), tel(2.0, 4.0, 0.0, "", q_in=0.3)]
    samples[2] = samples[2].__class__(**{**samples[2].__dict__, "running": False})
    log = from_samples("raw-capture", "cheali-charger", samples, 2)
    info = summarize(log)
    assert (info["format"], info["device"], info["samples"], info["bad_records"]) == \
        ("raw-capture", "cheali-charger", 3, 2)
    assert info["phases"] == [{"state": "charge", "start_s": 0.0, "end_s": 2.0},
                              {"state": "idle", "start_s": 2.0, "end_s": 2.0}]
