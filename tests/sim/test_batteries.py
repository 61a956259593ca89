"""Named battery files as a hand edit or a damaged disk leaves them (findings of benchmarks/fuzz_files.py)."""
import json

import pytest

from zuml_studio.sim.batteries import BatteryFileError, load_battery, save_battery
from zuml_studio.sim.chemistry import load_chemistry
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
