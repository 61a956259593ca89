"""`zuml log info/export` on a CSV: the guess is used and printed, `--columns` replaces it, a wrong
`--columns` is one line with the reason (the SkyRC logger's real CSVs, tests/data/realdata)."""
import csv
import json
from pathlib import Path

import pytest

from tests_cli_util import run_zuml

REAL = Path(__file__).resolve().parents[1] / "data" / "realdata"
DISCHARGE = REAL / "skyrc_B6ACv2_Discharging_head100.csv"


def test_info_prints_the_guess_and_columns_override_it():
    rc, out, err = run_zuml("log", "info", str(DISCHARGE))
    assert rc == 0 and "columns      time:s,voltage:V,current:mA,charge:mAh" in out
    rc, out, err = run_zuml("log", "info", str(DISCHARGE), "--json", "--columns", "time:s,voltage:V,current:-mA,charge")
    assert rc == 0, err
    info = json.loads(out)
    with DISCHARGE.open() as fh:
        body = list(csv.reader(fh))[1:]
    assert info["format"] == "csv" and info["samples"] == len(body)
    assert info["csv_columns"] == "time:s,voltage:V,current:-mA,charge:mAh"
    moved = float(body[-1][3]) - float(body[0][3])          # integrated; the counter agrees within 3 %
    assert info["charge_out_mah"] == pytest.approx(moved, rel=0.03, abs=0.2) and info["charge_in_mah"] == 0
    assert info["i_max_a"] == max(float(r[2]) for r in body) / 1000


def test_export_with_columns(tmp_path):
    out_csv = tmp_path / "out.csv"
    rc, out, err = run_zuml("log", "export", str(DISCHARGE), "-o", str(out_csv), "--columns", "time:min,voltage:V")
    assert rc == 0, err
    with out_csv.open() as fh:
        rows = list(csv.DictReader(fh))
    with DISCHARGE.open() as fh:
        body = list(csv.reader(fh))[1:]
    assert float(rows[-1]["t_s"]) == (float(body[-1][0]) - float(body[0][0])) * 60
    assert rows[-1]["current_a"] == ""                     # no current column: not measured


def test_a_wrong_columns_spec_is_one_line():
    rc, out, err = run_zuml("log", "info", str(DISCHARGE), "--columns", "time:s,volts")
    assert rc == 1 and err.count("\n") <= 1 and "--columns: column 2: 'volts' is not a role" in err
    assert "Traceback" not in err
