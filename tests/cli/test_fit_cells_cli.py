"""zuml fit on a log with balance taps: each cell, printed, in --json and kept by --save (issue #26)."""
import json

import pytest

from helpers import MACROS, ROOT
from zuml_studio.sim.batteries import batteries_dir

LOGS = ROOT / "tests" / "data" / "logs"
DUO_4S = str(LOGS / "406DUO_Turnigy_4S_1500_A_Charge_0_CH1.txt")


def test_fit_json_carries_each_cell_and_the_spread(zuml):
    rc, out, err = zuml("fit", DUO_4S, "--json")
    assert rc == 0, err
    data = json.loads(out)
    assert data["cells"] == 4                                  # the count, as before
    cell_fit = data["cell_fit"]
    assert [c["cell"] for c in cell_fit["cells"]] == [1, 2, 3, 4]
    assert set(cell_fit["cells"][0]) == {"cell", "capacity_mah", "start_soc", "r_scale", "r_mohm", "rmse_v_mv",
                                         "top_v", "held_pct", "held", "at_bound", "coverage", "capacity_measured"}
    assert cell_fit["implausible"] == []                      # four cells of one pack
    for key in ("capacity_mah", "r_mohm"):
        spread = cell_fit[key]
        assert spread["min"] <= spread["mean"] <= spread["max"] and spread["spread_pct"] >= 0
    assert 1 <= cell_fit["weakest"] <= 4 and 1 <= cell_fit["highest_resistance"] <= 4


def test_fit_of_a_curve_without_taps_has_no_cell_fit(zuml):
    rc, out, err = zuml("fit", str(ROOT / "tests" / "data" / "curves" / "lipo_4s_406duo_3c.csv"), "--chemistry",
                        "LiPo", "--json")
    assert rc == 0, err
    assert json.loads(out)["cell_fit"] is None


def test_fit_prints_the_cells_and_save_keeps_them(zuml):
    rc, out, err = zuml("fit", DUO_4S, "--save", "Turnigy 4S cells")
    assert rc == 0, err
    assert "cells from the balance taps" in out and "  cell 4: " in out and "weakest: cell " in out
    doc = json.loads((batteries_dir() / "Turnigy_4S_cells.json").read_text())
    assert doc["series"] == 4 and len(doc["cells"]) == 4
    assert sum(c["capacity_mah"] for c in doc["cells"]) / 4 == pytest.approx(doc["capacity_mah"], rel=1e-3)
    rc, out, err = zuml("simulate", str(MACROS / "LiPo.zuml"), "--battery", "Turnigy 4S cells",
                        "--current", "1.5", "--json")
    assert rc == 0, err          # a battery file with cells still loads where the cells are not used
