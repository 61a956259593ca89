"""Named battery files as a hand edit or a damaged disk leaves them (findings of benchmarks/fuzz_files.py)."""
import json

import pytest

from zuml_studio.sim.batteries import BatteryFileError, load_battery, save_battery
from zuml_studio.domain.chemistry import load_chemistry
from zuml_studio.sim.fit import Battery


@pytest.fixture
def pack(tmp_path):
    save_battery("pack", Battery(load_chemistry("NiMh"), 2000.0, 4), root=tmp_path)
    path = tmp_path / "batteries" / "pack.json"

    def write(**changes):
        doc = json.loads(path.read_text())
        params = changes.pop("parameters", None)
        doc.update(changes)
        if params is not None:
            doc["parameters"] = params
        path.write_text(json.dumps(doc))
    return write


@pytest.mark.parametrize("changes, said", [
    ({"capacity_mah": float("inf")}, "capacity_mah must be a finite number, not inf"),
    ({"capacity_mah": float("nan")}, "capacity_mah must be a finite number, not nan"),
    ({"capacity_mah": "2000"}, "capacity_mah must be a number, not '2000'"),
    ({"series": 1e999}, "series must be a finite number, not inf"),          # was OverflowError
    ({"series": True}, "series must be a number, not True"),                  # was read as 1 cell
    ({"series": 4.5}, "series a whole number 1..255"),                        # was read as 4 cells
    ({"parameters": {"r0_ohm": 10 ** 400}}, "r0_ohm must be a finite number"),  # was OverflowError
    ({"parameters": {"ocv_v": [1.1, float("nan")]}}, "ocv_v must be a finite number, not nan"),
])
def test_a_number_that_is_no_finite_number_is_said(pack, tmp_path, changes, said):
    pack(**changes)
    with pytest.raises(BatteryFileError, match="bad battery file: .*" + said.replace("(", r"\(").replace(")", r"\)")):
        load_battery("pack", tmp_path)


def test_a_file_that_is_a_json_list(tmp_path, pack):
    (tmp_path / "batteries" / "pack.json").write_text("[1, 2]")
    with pytest.raises(BatteryFileError, match="a JSON object expected, not list"):
        load_battery("pack", tmp_path)


def test_the_saved_battery_still_loads(pack, tmp_path):
    pack()
    battery = load_battery("pack", tmp_path)
    assert (battery.capacity_mah, battery.series) == (2000.0, 4)


def test_a_battery_files_cells_round_trip_and_reach_the_pack(tmp_path, monkeypatch):
    from zuml_studio.sim import batteries
    from zuml_studio.sim.batteries import load_battery_cells
    from zuml_studio.sim.cell_pack import CellPack, CellSpec
    from zuml_studio.sim.interpreter import StartParams
    from zuml_studio.sim.simulate import BatterySetup, models
    from simhelp import record_of
    cells = [CellSpec(2000.0), CellSpec(1950.0, 1.2, None), CellSpec(2010.0, 0.9, 0.1), CellSpec(1700.0, 1.5, None)]
    save_battery("four", Battery(load_chemistry("LiPo"), 2000.0, 4), root=tmp_path, cells=cells)
    assert load_battery_cells("four", root=tmp_path)[1] == cells
    monkeypatch.setattr(batteries, "config_dir", lambda: tmp_path)
    _, _, pack, _ = models(record_of("LiPo"), StartParams("charge", 1, None, 2.0), BatterySetup(battery="four"))
    assert isinstance(pack, CellPack) and [round(c.capacity_mah) for c in pack.cells] == [2000, 1950, 2010, 1700]
    assert pack.cells[2].soc == 0.1 and pack.cells[1].soc == 0.0


@pytest.mark.parametrize("cells, said", [
    ([{"capacity_mah": 2000}] * 3, "cells must be a list of 4 cells"),
    ([{"capacity_mah": 2000}] * 3 + [{"capacity_mah": -1}], "cell 4: capacity_mah must be > 0"),
    ([{"capacity_mah": 2000, "r_scale": 1, "soc": 2}] * 4, "cell 1: soc must be 0..1 or null"),
    ([{"capacity_mah": 2000, "volts": 1}] * 4, "cell 1: an object with capacity_mah, r_scale and soc"),
])
def test_bad_cells_in_a_battery_file_are_named(pack, tmp_path, cells, said):
    pack(cells=cells)
    with pytest.raises(BatteryFileError, match=said):
        load_battery("pack", root=tmp_path)
