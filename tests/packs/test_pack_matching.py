"""Foreign logs and dates (issue 33 §2): a log whose chemistry or cell count contradicts the pack is not
filed (its reason said), and every session is dated by its log where the log holds a date."""
import pytest

from zuml_studio.logs import read_log_file
from zuml_studio.packs.db import Logbook
from zuml_studio.packs.matching import mismatch
from zuml_studio.packs.register import add_pack
from zuml_studio.packs.sessions import import_files, pack_sessions

DATA = __import__("pathlib").Path(__file__).resolve().parents[1] / "data" / "logs"


@pytest.fixture
def book(tmp_path):
    return Logbook(tmp_path / "p.sqlite3")


@pytest.mark.parametrize("name, reason", [
    ("UltramatACDCEQ_2014-09-16_4S_NiMH_cycle.osd", None),
    ("eStationBC6_2008-07-05_EmpfaengerAA.osd", None),
    ("PolaronPro_2014-08-23_5S_NiMh_cycle.osd",
     "its charge's median voltage, 7.08 V, is 1.77 V per cell for 4 cells; a NiMh cell reads about 1.46 V"),
    ("X8_LiPo_5S_2200mA_Charge_4.txt", "the log is of a LiPo pack, this one is NiMh"),
    ("4010DUO_LiFe_2S_3A_Charge_1_CH1.txt", "the log is of a LiFe pack, this one is NiMh"),
    ("iCharger208B_Storage.lov", "the log's balance taps show 3 cells, the pack has 4"),
])
def test_a_nimh_4s_pack_takes_its_own_logs_only(book, name, reason):
    pack = add_pack(book, "Rx", "NiMh", 4, 1200)
    assert mismatch(read_log_file(DATA / name), pack, name) == reason


def test_foreign_logs_are_skipped_with_their_reason_and_force_files_them_marked(book):
    pack = add_pack(book, "Rx", "NiMh", 4, 1200)
    names = ["UltramatACDCEQ_2014-09-16_4S_NiMH_cycle.osd", "X8_LiPo_5S_2200mA_Charge_4.txt"]
    results = import_files(book, pack, [DATA / n for n in names])
    assert [r.status for r in results] == ["added", "foreign"]
    assert results[1].message.startswith("not this pack's: the log is of a LiPo pack")
    assert len(pack_sessions(book, pack)) == 1
    (forced,) = import_files(book, pack, [DATA / names[1]], force=True)
    assert forced.status == "added" and "marked" in forced.message
    marked = [s.foreign_reason for s in pack_sessions(book, pack)]
    assert marked.count(None) == 1 and "LiPo" in [m for m in marked if m][0]


@pytest.mark.parametrize("name, when", [
    ("iCharger208B_Storage.lov", "2012-03-03T16:56:49"),           # the .lov header's "03.03.2012, 16:56:49"
    ("Ultramat16_2011-04-21_Test_Ultramat16.lov", "2011-04-21T21:45:32"),
    ("Akkumatik_2015-03-27_NiCd_E-L_Cycle.osd", "2015-03-27T15:27:57+00:00"),    # 16:27:57 CET
])
def test_a_session_is_dated_by_its_log(book, name, when):
    log = read_log_file(DATA / name)
    pack = add_pack(book, "P", "NiCd" if "NiCd" in name else "NiMh" if "Ultramat" in name else "LiPo",
                    log.cells or 4, 1000)
    (result,) = import_files(book, pack, [DATA / name], force=True)
    assert result.status == "added"
    (session,) = pack_sessions(book, pack)
    assert (session.recorded, session.recorded_from) == (when, "log")


def test_the_same_charge_in_two_formats_is_kept_once_with_both_files(book, tmp_path):
    # A .lov and the raw capture of the same charge (the iCharger 208B's lines, extracted from the .lov)
    pack = add_pack(book, "3S", "LiPo", 3, 1000)
    lov = DATA / "iCharger208B_Storage.lov"
    raw = DATA.parent / "realdata" / "icharger208B_Storage_lines.txt"
    first, second = import_files(book, pack, [lov, raw])
    assert first.status == "added"
    assert second.status == "known" and second.message.startswith(f"the same charge as {lov}")
    (session,) = pack_sessions(book, pack)
    assert session.as_dict()["same_files"] == [str(raw)]


def test_different_charges_of_one_pack_are_kept_apart(book):
    pack = add_pack(book, "Rx", "NiMh", 4, 2000)
    results = import_files(book, pack, [DATA / "AkkuMasterC4_2007-12-28-EmpfaengerAA4-Laden.csv",
                                        DATA / "AkkuMasterC4_2007-12-28-EmpfaengerAA4-Entladen.csv"])
    assert [r.status for r in results] == ["added", "added"]
