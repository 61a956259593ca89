"""Every log family README.md names opens: each against a real recording of it (tests/data), read
by recognising its bytes, as `zuml log info` and File ▸ Open Log… do."""
from pathlib import Path

import pytest

from zuml_studio.logs import read_log_file

ROOT = Path(__file__).resolve().parents[2]
LOGS = ROOT / "tests" / "data" / "logs"
REAL = ROOT / "tests" / "data" / "realdata"

# README's words for the family -> (a real recording, the format it is read as)
FAMILIES = {
    "cheali": (REAL / "cheali_captured_lines_from_issues.txt", "raw-capture"),
    "iCharger": (REAL / "icharger3010B_2500NiMh_lines.txt", "raw-capture"),
    "iMAX B6": (REAL / "imaxb6_Ladung3S450mAh_frames_head300.txt", "raw-capture"),
    "Ultramat": (REAL / "ultramat_frames_extracted.txt", "raw-capture"),
    "ISDT": (REAL / "isdt_real_frames.txt", "raw-capture"),
    "`.lov` files of iCharger": (LOGS / "iCharger106Bplus_Laden.lov", "logview-lov"),
    "iMAX B6 and Ultramat chargers": (LOGS / "iMaxB6_Ladung3S450mAh.lov", "logview-lov"),
    "Ultramat 12/16": (LOGS / "Ultramat16_2011-04-21_Test_Ultramat16.lov", "logview-lov"),
    "iCharger DUO/X text logs": (LOGS / "X6_LiFe_10-3A_Cycle_2.txt", "icharger-duo-txt"),
    "DataExplorer `.osd` files": (LOGS / "PolaronPro_2014-08-23_5S_NiMh_cycle.osd", "dataexplorer-osd"),
    "CSV exports": (LOGS / "AkkuMasterC4_2007-12-28-EmpfaengerAA4-Laden.csv", "dataexplorer-csv"),
    "open-format text": (LOGS / "LogViewOpenFormat_TimeInc_Ch1_1Log.txt", "logview-open"),
    "SkyRC logger's": (REAL / "skyrc_B6ACv2_Charging_head100.csv", "csv"),
}


def readme_text() -> str:
    return " ".join((ROOT / "README.md").read_text(encoding="utf-8").split())


@pytest.mark.parametrize("family", sorted(FAMILIES))
def test_each_family_the_readme_names_opens(family):
    assert family in readme_text()
    path, fmt = FAMILIES[family]
    log = read_log_file(path)
    assert log.format == fmt and len(log.samples) > 0


def test_the_readme_names_no_lov_family_without_a_real_file():
    # cheali .lov files have no public recording: the README does not claim them.
    assert "`.lov` files of the serial ones" not in readme_text()
    assert "`.lov` files of iCharger, iMAX B6 and Ultramat chargers" in readme_text()
