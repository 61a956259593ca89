"""zuml simulate as a user runs it."""
import csv
import json

from helpers import MACROS
from tests_cli_util import run_zuml

NIMH = ["simulate", str(MACROS / "NiMh.zuml"), "--capacity", "2000", "--series", "4", "--current", "2"]


def test_json_has_the_documented_shape():
    rc, out, err = run_zuml(*NIMH, "--no-sensor", "--json")
    assert rc == 0, err
    data = json.loads(out)
    (phase,) = data["phases"]
    assert {"section", "index", "start_s", "end_s", "reason", "mah_in", "mah_out", "v_end", "temp_end"} <= set(phase)
    assert phase["reason"] == "default: capacity 1.5x" and phase["section"] == "charge" and phase["index"] == 1
    assert set(data["totals"]) == {"duration_s", "mah_in", "mah_out", "end"}


def test_table_makes_a_default_end_visible():
    rc, out, _ = run_zuml(*NIMH, "--no-sensor")
    assert rc == 0
    assert "default: capacity 1.5x" in out
    assert "note: phase 1 (charge) ended by default: capacity 1.5x, not by a condition of the macro" in out


def test_csv_has_every_sample_with_the_header(tmp_path):
    target = tmp_path / "run.csv"
    rc, out, err = run_zuml("simulate", str(MACROS / "LiPo.zuml"), "--capacity", "1000", "--series", "2",
                            "--current", "1", "--task", "train", "--cycles", "2", "--csv", str(target))
    assert rc == 0, err
    rows = list(csv.reader(target.open()))
    assert rows[0] == ["time_s", "section", "phase", "voltage_v", "current_a", "temp_c", "heatsink_c", "mah_in",
                       "mah_out"]
    sections = {r[1] for r in rows[1:]}
    assert sections == {"discharge", "charge"}
    assert "repetition 2: discharged" in out


def test_missing_start_values_are_one_clear_line():
    rc, out, err = run_zuml("simulate", str(MACROS / "NiMh.zuml"), "--capacity", "2000", "--series", "4")
    assert rc == 1 and "Traceback" not in err
    assert "INPUT" in err and err.count("\n") == 1
    rc, _, err = run_zuml("simulate", str(MACROS / "NiMh.zuml"), "--current", "2", "--series", "4")
    assert rc == 1 and "--capacity" in err
    rc, _, err = run_zuml(*NIMH, "--soc", "2")
    assert rc == 2 and "--soc" in err
