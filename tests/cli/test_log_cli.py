"""zuml log info / export as a user runs them, on real recordings."""
import csv
import json
from pathlib import Path

from tests_cli_util import run_zuml

LOGS = Path(__file__).resolve().parents[1] / "data" / "logs"
X8 = str(LOGS / "X8_LiPo_5S_2200mA_Charge_4.txt")


def test_info_json_has_the_documented_fields():
    rc, out, err = run_zuml("log", "info", X8, "--json")
    assert rc == 0, err
    info = json.loads(out)
    assert {"format", "device", "samples", "bad_records", "duration_s", "v_min", "v_max", "i_max_a",
            "charge_in_mah", "charge_out_mah", "cells", "phases"} <= set(info)
    assert (info["format"], info["device"], info["samples"], info["cells"]) == \
        ("icharger-duo-txt", "Junsi iCharger X8", 1375, 5)
    assert (info["charge_in_mah"], info["charge_out_mah"], info["i_max_a"]) == (2015.9, 0.0, 6.02)   # integrated
    assert info["phases"] == [{"state": "charge", "start_s": 0.0, "end_s": 1374.0}]
    assert info["resistance"]["readings"] == 23


def test_info_table_names_charger_and_phases():
    rc, out, _ = run_zuml("log", "info", str(LOGS / "PolaronPro_2014-08-23_5S_NiMh_cycle.osd"))
    assert rc == 0
    assert "dataexplorer-osd, PolaronPro" in out
    assert "charge       in 1916 mAh, out 1437 mAh" in out     # integrated; the counter: 1917, 1440
    assert "discharge" in out and "pause" in out


def test_export_writes_one_row_per_sample(tmp_path):
    target = tmp_path / "x6.csv"
    rc, out, err = run_zuml("log", "export", str(LOGS / "X6_LiFe_10-3A_Cycle_2.txt"), "-o", str(target))
    assert rc == 0, err
    rows = list(csv.DictReader(target.open(encoding="utf-8")))
    assert len(rows) == 794 and out.strip() == f"wrote 794 rows to {target}"
    assert list(rows[0]) == ["t_s", "voltage_v", "current_a", "temp_c", "charge_in_mah", "charge_out_mah", "state"] + \
        [f"cell{k}_v" for k in range(1, 7)]
    assert rows[-1]["current_a"] == "-1.5000" and rows[-1]["state"] == "discharge"
    assert rows[-1]["temp_c"] == ""                 # no probe: empty, not 0
    assert (rows[-1]["charge_in_mah"], rows[-1]["charge_out_mah"]) == ("96.5", "149.4")    # the counter: 95, 149


def test_errors_are_one_line(tmp_path):
    junk = tmp_path / "junk.bin"
    junk.write_bytes(b"\x00\x01garbage")
    rc, _, err = run_zuml("log", "info", str(junk))
    assert rc == 1 and err.startswith(f"zuml: error: {junk}: not a log file") and err.count("\n") == 1
    rc, _, err = run_zuml("log", "info", str(tmp_path / "missing.txt"))
    assert rc == 2 and "no such file" in err
    rc, _, err = run_zuml("log", "export", X8, "-o", str(tmp_path / "no" / "such" / "dir.csv"))
    assert rc == 2 and "cannot write" in err


def test_a_forced_format_that_does_not_fit_says_it_was_forced(zuml):
    rc, _, err = zuml("log", "info", str(LOGS / "iMaxB6_Ladung3S450mAh.lov"), "--format", "session-csv")
    assert rc == 1 and err.count("\n") == 1
    assert "read as session-csv (--format): not UTF-8 text" in err and "without --format" in err
