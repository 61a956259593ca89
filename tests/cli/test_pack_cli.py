"""zuml pack: the logbook from the command line (ZUML_STUDIO_DATA_DIR points at a temporary folder)."""
import json
import shutil

import pytest

DATA = __import__("pathlib").Path(__file__).resolve().parents[1] / "data" / "logs"


@pytest.fixture(autouse=True)
def data_dir(tmp_path, monkeypatch):
    monkeypatch.setenv("ZUML_STUDIO_DATA_DIR", str(tmp_path / "data"))
    return tmp_path / "data"


def test_add_import_show_json_export_remove(zuml, tmp_path):
    assert zuml("pack", "add", "Turnigy 4S #2", "--chemistry", "LiPo", "--cells", "4", "--capacity", "1500",
                "--bought", "2024-05-01")[0] == 0
    folder = tmp_path / "logs"
    folder.mkdir()
    for name in ("406DUO_Turnigy_4S_1500_A_Charge_0_CH1.txt", "X8_LiPo_5S_2200mA_Charge_4.txt"):
        shutil.copy(DATA / name, folder / name)
    code, out, _err = zuml("pack", "import", str(folder), "--pack", "Turnigy 4S #2")
    # The X8 log is a 5S pack's: skipped with its reason, then filed marked with --force.
    assert code == 0 and "1 added, 0 already known, 0 not read" in out
    assert "not this pack's: the log's balance taps show 5 cells, the pack has 4 (--force files it, marked)" in out
    assert "1 log skipped as another pack's (its reason above; --force files it)" in out
    code, out, _err = zuml("pack", "import", str(folder), str(folder / "X8_LiPo_5S_2200mA_Charge_4.txt"),
                           "--pack", "Turnigy 4S #2", "--force")
    assert code == 0 and "1 added, 2 already known, 0 not read" in out
    assert "filed as asked, marked: the log's balance taps show 5 cells, the pack has 4" in out
    code, out, _err = zuml("pack", "show", "Turnigy 4S #2", "--json")
    info = json.loads(out)
    assert info["bought"] == "2024-05-01" and len(info["sessions"]) == 2
    for s in info["sessions"]:
        assert {"file", "charge_in_mah", "charge_out_mah", "resistance_mohm_per_cell", "cell_deviation_mv",
                "t_max_c"} <= s.keys()
    assert [s["charge_in_mah"] for s in info["sessions"]] == [1113.2, 2015.9]     # integrated (counters: 1117, 2016)
    # the 5S log filed with --force is marked and kept out of the trend
    assert [s["foreign_reason"] for s in info["sessions"]].count(None) == 1
    assert len(info["trend"]) == 1 and set(info["health"]) == {"verdict", "reasons"}
    assert info["health"]["verdict"] in ("good", "poor", "unknown") and info["health"]["reasons"]
    code, out, _err = zuml("pack", "show", "Turnigy 4S #2")
    assert code == 0 and "2 sessions" in out and "health:" in out
    code, out, _err = zuml("pack", "list", "--json")
    assert json.loads(out)["packs"][0]["sessions"] == 2
    csv_path = tmp_path / "s.csv"
    assert zuml("pack", "export", "Turnigy 4S #2", "-o", str(csv_path))[0] == 0
    assert len(csv_path.read_text(encoding="utf-8").splitlines()) == 3
    code, out, _err = zuml("pack", "remove", "Turnigy 4S #2")
    assert code == 0 and "2 sessions" in out
    assert "no packs yet" in zuml("pack", "list")[1]


@pytest.mark.parametrize("args, words", [
    (("pack", "show", "Nope"), "no pack named 'Nope'"),
    (("pack", "remove", "Nope"), "no pack named 'Nope'"),
    (("pack", "import", "x.lov", "--pack", "Nope"), "no pack named 'Nope'"),
    (("pack", "add", "A", "--chemistry", "Kryptonite", "--cells", "4", "--capacity", "1"), "Kryptonite"),
    (("pack", "add", "A", "--chemistry", "LiPo", "--cells", "99", "--capacity", "1"), "cells must be 1 to 32"),
    (("pack", "add", "A", "--chemistry", "LiPo", "--cells", "3", "--capacity", "1", "--bought", "May"),
     "YYYY-MM-DD"),
])
def test_errors_are_one_line(zuml, args, words):
    code, out, err = zuml(*args)
    assert code == 1 and words in err and err.count("\n") == 1


def test_missing_path_and_unreadable_file(zuml, tmp_path):
    zuml("pack", "add", "A", "--chemistry", "LiPo", "--cells", "3", "--capacity", "1000")
    code, _out, err = zuml("pack", "import", str(tmp_path / "gone.lov"), "--pack", "A")
    assert code == 1 and "no such file or folder" in err
    junk = tmp_path / "junk.txt"
    junk.write_text("hello")
    code, out, err = zuml("pack", "import", str(junk), "--pack", "A")
    assert code == 1 and "0 added, 0 already known, 1 not read" in out
    assert err == "zuml: error: nothing imported: no file given is a log ZUML Studio reads (each one's reason above)\n"


def test_damaged_logbook_is_one_line_and_left_alone(zuml, data_dir):
    data_dir.mkdir(parents=True)
    (data_dir / "packs.sqlite3").write_bytes(b"\0garbage" * 1000)
    code, _out, err = zuml("pack", "list")
    assert code == 1 and "damaged" in err and err.count("\n") == 1
    assert (data_dir / "packs.sqlite3").read_bytes() == b"\0garbage" * 1000


def test_import_draws_a_progress_bar_on_a_terminal(zuml, tmp_path, monkeypatch):
    zuml("pack", "add", "A", "--chemistry", "LiFe", "--cells", "2", "--capacity", "2300")
    monkeypatch.setattr("sys.stderr.isatty", lambda: True)
    files = [str(DATA / n) for n in ("308DUO_LiFe_2.3Ah_Laden_0_CH1.txt", "4010DUO_LiFe_2S_3A_Charge_1_CH1.txt")]
    code, out, err = zuml("pack", "import", *files, "--pack", "A")
    assert code == 0 and "2 added" in out
    assert "[###############...............] 1/2" in err and "[" + "#" * 30 + "] 2/2" in err


def test_two_processes_importing_at_once_keep_the_logbook_whole(zuml, data_dir):
    """Two instances (here two `zuml pack import` processes) write the same logbook at once: WAL and one
    writer at a time, so every file lands once and the database stays sound."""
    import os
    import sqlite3
    import subprocess
    import sys

    zuml("pack", "add", "A", "--chemistry", "LiPo", "--cells", "4", "--capacity", "1500")
    zuml("pack", "add", "B", "--chemistry", "LiPo", "--cells", "5", "--capacity", "2200")
    shared = str(DATA / "X6_LiPo_Cycle_1.first1200.txt")                  # both import it: one wins
    jobs = {"A": [str(DATA / "406DUO_Turnigy_4S_1500_A_Charge_0_CH1.txt"), shared],
            "B": [str(DATA / "X8_LiPo_5S_2200mA_Charge_4.txt"), shared]}
    env = dict(os.environ, ZUML_STUDIO_DATA_DIR=str(data_dir))
    procs = [subprocess.Popen([sys.executable, "-m", "zuml_studio.cli.main", "pack", "import", *files, "--pack", name],
                              env=env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
             for name, files in jobs.items()]
    outs = [p.communicate(timeout=120) for p in procs]
    assert [p.returncode for p in procs] == [0, 0], outs
    added = sum(int(o.split(": ")[-1].split(" added")[0]) for o, _e in outs)
    assert added == 3
    shown = {name: len(__import__("json").loads(zuml("pack", "show", name, "--json")[1])["sessions"])
             for name in "AB"}
    assert sum(shown.values()) == 3 and min(shown.values()) >= 1
    with sqlite3.connect(data_dir / "packs.sqlite3") as conn:
        assert conn.execute("PRAGMA integrity_check").fetchone()[0] == "ok"


def test_a_discharge_not_from_full_shows_what_was_taken_out_in_parentheses_and_why(zuml, tmp_path):
    assert zuml("pack", "add", "Rx AA", "--chemistry", "NiMH", "--cells", "4", "--capacity", "2000")[0] == 0
    assert zuml("pack", "import", str(DATA / "AkkuMasterC4_2007-12-28-EmpfaengerAA4-Entladen.csv"),
                "--pack", "Rx AA")[0] == 0
    code, out, _err = zuml("pack", "show", "Rx AA")
    assert code == 0 and "(396)" in out and "health: unknown" in out
    assert "(capacity): taken out, not the pack's capacity: 2007-12-28: the discharge began at about " in out
