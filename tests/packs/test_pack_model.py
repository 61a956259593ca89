"""The pack's own fitted model, saved as a named battery the simulator offers."""
import pytest

from zuml_studio.packs.db import Logbook
from zuml_studio.packs.model import fit_pack_model, has_model, model_name
from zuml_studio.packs.register import PackError, add_pack
from zuml_studio.packs.sessions import import_files
from zuml_studio.sim.batteries import load_battery

DATA = __import__("pathlib").Path(__file__).resolve().parents[1] / "data" / "logs"


def test_the_packs_model_is_fitted_to_its_charge_and_saved(tmp_path, monkeypatch):
    monkeypatch.setenv("ZUML_STUDIO_CONFIG_DIR", str(tmp_path / "config"))
    book = Logbook(tmp_path / "p.sqlite3")
    pack = add_pack(book, "Turnigy 4S #2", "LiPo", 4, 1500)
    assert model_name(pack) == "pack Turnigy 4S 2" and not has_model(pack)
    with pytest.raises(PackError, match="no session with a charge"):
        fit_pack_model(book, pack)
    import_files(book, pack, [DATA / "406DUO_Turnigy_4S_1500_A_Charge_0_CH1.txt"])
    name, result = fit_pack_model(book, pack)
    assert has_model(pack)
    battery = load_battery(name)
    assert battery.series == 4 and battery.chem.name == "LiPo"
    assert battery.capacity_mah == pytest.approx(result.params["capacity_mah"])


def test_a_fit_that_fails_is_said_in_one_line(tmp_path, monkeypatch):
    from zuml_studio.packs import model

    book = Logbook(tmp_path / "p.sqlite3")
    pack = add_pack(book, "P", "LiPo", 4, 1500)
    import_files(book, pack, [DATA / "406DUO_Turnigy_4S_1500_A_Charge_0_CH1.txt"])

    def broken(*args, **kwargs):
        raise ValueError("math domain error")        # what a hostile charge makes the fit raise today
    monkeypatch.setattr(model, "fit", broken)
    with pytest.raises(PackError, match="the fit failed: math domain error"):
        fit_pack_model(book, pack)
