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
    assert ("⚠ phase 1 (charge) ended by default: capacity 1.5x, not by a condition of the macro: no condition of "
            "the macro ended this charge before the charger's guard") in out


def test_csv_has_every_sample_with_the_header(tmp_path):
    target = tmp_path / "run.csv"
    rc, out, err = run_zuml("simulate", str(MACROS / "LiPo.zuml"), "--capacity", "1000", "--series", "2",
                            "--current", "1", "--task", "train", "--cycles", "2", "--csv", str(target))
    assert rc == 0, err
    rows = list(csv.reader(target.open()))
    assert rows[0] == ["time_s", "section", "phase", "voltage_v", "current_a", "temp_c", "heatsink_c", "mah_in",
                       "mah_out", "cell1_v", "cell2_v", "balance_mask"]     # two cells: each one's share
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


def test_json_and_table_show_heat_sink_pauses_and_the_charger_clipping_the_current():
    args = ["simulate", str(MACROS / "LiPo.zuml"), "--task", "discharge", "--capacity", "2000", "--series", "3",
            "--ambient", "40"]
    rc, out, err = run_zuml(*args, "--json")
    assert rc == 0, err
    (phase,) = json.loads(out)["phases"]
    assert len(phase["pauses"]) > 5 and phase["paused_s"] > 600
    assert phase["clip"]["limit"] == "5 W discharge limit" and phase["clip"]["asked_a"] == -2.0
    rc, out, err = run_zuml(*args)
    assert f"heat-sink pause {len(phase['pauses'])}x" in out
    assert "asked 2.00 A, charger gave 0.40 A: 5 W discharge limit" in out


def test_a_charge_cut_by_its_timer_is_marked_not_reported_as_a_normal_end():
    args = ["simulate", str(MACROS / "NiMh-dV.zuml"), "--capacity", "2000", "--series", "4", "--current", "0.4",
            "--no-sensor"]
    rc, out, err = run_zuml(*args)
    assert rc == 0, err
    assert out.startswith("warning: charge phase 1: 0.40 A is 0.20C of 2000 mAh; NiMh shows no reliable -dV")
    assert "⚠ timer before full: 1600 mAh put in" in out
    assert "⚠ phase 1 (charge): timer before full: IF(tf>4h) STOP_FAZE ended it with 1600 mAh put in" in out
    rc, out, err = run_zuml(*args, "--json")
    assert json.loads(out)["phases"][0]["timer_before_full"] is True
    assert json.loads(out)["warnings"][0].startswith("charge phase 1: 0.40 A is 0.20C")


def test_template_option_takes_the_start_values_from_the_charger_table():
    rc, out, err = run_zuml("simulate", str(MACROS / "NiMh-dV.zuml"), "--template", "1", "--no-sensor", "--json")
    assert rc == 0, err
    assert json.loads(out)["battery"] == {"chemistry": "NiMh", "capacity_mah": 2000.0, "series": 4}
    rc, out, err = run_zuml("simulate", str(MACROS / "NiMh-dV.zuml"), "--template", "9")
    assert rc == 1 and "start template 9 (chosen at start) does not exist on this charger" in err


def test_the_table_stays_in_columns_when_a_value_is_wider_than_its_title(zuml):
    """A run to the simulator's 1000 h guard: its end (1000:00:00) and charge are wider than the
    columns' titles; the numbers still end under their titles, the reason starts under its own."""
    rc, out, err = zuml("simulate", str(MACROS / "NiMh.zuml"), "--capacity", "2000", "--series", "4", "--current", "1",
                        "--tick", "60")
    assert rc == 0, err
    title, row = out.splitlines()[1:3]

    def end_of(text, word):
        return text.index(word) + len(word)
    assert end_of(title, " end") == end_of(row, "1000:00:00")
    assert title.index("reason") == row.index("limit:")
    assert end_of(title, "in mAh") == end_of(row, "1000000.0")
    assert end_of(title, "T end") == len(row)               # no notes: the row ends with the temperature


def test_hostile_measurement_and_ambient_values_are_one_line(zuml):
    # found by benchmarks/fuzz_cli.py: --ambient nan ended in an UnboundLocalError traceback; inf,
    # -300 °C and a noise of 1e300 mV simulated nonsense; an ADC step of 4e-320 mV overflowed (OverflowError)
    for option, value, said in (("--ambient", "nan", "--ambient must be -20 to 60 °C"),
                                ("--ambient", "-300", "--ambient must be -20 to 60 °C"),
                                ("--ambient", "inf", "--ambient must be -20 to 60 °C"),
                                ("--noise", "nan", "--noise must be 0 to 1000 mV"),
                                ("--noise", "1e300", "--noise must be 0 to 1000 mV"),
                                ("--adc-lsb", "-5", "--adc-lsb must be 0 to 1000 mV"),
                                ("--adc-lsb", "4e-320", "--adc-lsb must be 0 (none) or at least 0.001 mV")):
        rc, out, err = zuml(*NIMH, option, value)
        assert (rc, err) == (2, f"zuml: error: {said}\n"), (option, value)


def test_a_weak_cell_shows_in_the_table_the_json_and_the_csv(tmp_path):
    lipo = ["simulate", str(MACROS / "LiPo.zuml"), "--capacity", "2000", "--series", "4", "--current", "2",
            "--weak-cell", "15"]
    rc, out, err = run_zuml(*lipo)
    assert rc == 0, err
    # the B6's windows: the CV's own current ends it as a window closes, the others 24 mV under the weak cell
    assert "phase 2 (charge): cells at the end 4.176 V (cell 1) to 4.200 V (cell 4)" in out
    rc, out, err = run_zuml(*lipo, "--json", "--csv", str(tmp_path / "w.csv"))
    data = json.loads(out)
    cells = data["phases"][-1]["cells"]
    assert (cells["min_cell"], cells["max_cell"]) == (1, 4)
    assert 4.1995 <= cells["max_v"] <= 4.2005 and cells["min_v"] > 4.17
    assert data["battery"]["cells"][3] == {"capacity_mah": 1700.0, "r_scale": 1.0, "soc": None}
    rows = list(csv.reader((tmp_path / "w.csv").open()))
    masks = {int(r[-1]) for r in rows[1:]}
    assert rows[0][-5:] == ["cell1_v", "cell2_v", "cell3_v", "cell4_v", "balance_mask"] and 8 in masks


def test_bad_cell_options_are_one_line():
    for args, said in ((["--cell-spread", "3,10"], "--cell-spread takes CAP,R,SOC"),
                       (["--cell-spread", "3,x,1"], "--cell-spread takes CAP,R,SOC"),
                       (["--cell-spread", "60,1,1"], "--cell-spread takes CAP,R,SOC"),
                       (["--weak-cell", "0"], "--weak-cell takes PCT or PCT@K"),
                       (["--weak-cell", "10@0"], "--weak-cell takes PCT or PCT@K"),
                       (["--weak-cell", "nan"], "--weak-cell takes PCT or PCT@K")):
        rc, out, err = run_zuml(*NIMH, *args)
        assert rc == 2 and said in err and len(err.strip().splitlines()) == 1, (args, err)
