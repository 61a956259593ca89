"""`zuml log info/export` on raw captures: the drivers' recordings (tests/data/realdata) read
through the raw-capture log format give the counts the driver tests assert
(tests/streams/test_drivers_realdata.py)."""
import csv
import json
from pathlib import Path

import pytest

from tests_cli_util import run_zuml

REAL = Path(__file__).resolve().parents[1] / "data" / "realdata"
ICHARGER = "Junsi iCharger (106B/206B/208B/306B/3010B)"


def info(path) -> dict:
    rc, out, err = run_zuml("log", "info", str(path), "--json")
    assert rc == 0, err
    return json.loads(out)


@pytest.mark.parametrize("name, device, samples, bad, cells", [
    # lines quoted from several issues: one goes back in time and starts a new record set (issue 33)
    ("cheali_captured_lines_from_issues.txt", "cheali-charger (iMAX B6 clone, open firmware)", 13, 0, 6),
    ("icharger208B_Storage_lines.txt", ICHARGER, 68, 0, 3),
    ("icharger306B_RB_1000_lines_head300.txt", ICHARGER, 300, 0, 3),
    ("icharger106Bplus_Laden_lines_head300.txt", ICHARGER, 300, 0, 3),
    ("icharger3010B_2500NiMh_lines.txt", ICHARGER, 4606, 0, 0),     # NiMH: 5.2 V in slot 1 is no cell
    ("imaxb6_Ladung3S450mAh_frames_head300.txt", "iMAX B6 / e-Station (original firmware)", 300, 0, 3),
    # UltraDuoPlus45 (157) + Ultramat12 (50) + Ultramat16 (69) + Ultramat18 (38)
    ("ultramat_frames_extracted.txt", "Graupner Ultramat / Ultra Duo Plus", 157 + 50 + 69 + 38, 0, 0),
    # the decoder follows the first channel (Q8 channel 4); one frame is quoted without its 02 len AA head
    ("isdt_real_frames.txt", "ISDT (C4, A4, Q8) USB", 1, 1, 0),
])
def test_raw_captures_read_as_their_driver_reads_them(name, device, samples, bad, cells):
    got = info(REAL / name)
    assert (got["format"], got["device"], got["samples"], got["bad_records"], got["cells"]) == \
        ("raw-capture", device, samples, bad, cells)


def test_3010b_nimh_charge_totals_and_phases():
    got = info(REAL / "icharger3010B_2500NiMh_lines.txt")
    # In: the current integrated (660 mAh); the charger's counter says 684: 3.5 % apart, said.
    assert (got["duration_s"], got["charge_in_mah"], got["v_max"]) == (9210.0, 660.1, 6.113)
    assert got["charge_check"] == {"in_integrated_mah": 660.1, "out_integrated_mah": 0.0, "in_counter_mah": 684.0,
                                   "out_counter_mah": 0.0, "difference": 0.035}
    assert got["phases"] == [{"state": "charge", "start_s": 0.0, "end_s": 9210.0}]


def test_306b_discharge_is_a_discharge_phase():
    got = info(REAL / "icharger306B_RB_1000_lines_head300.txt")
    # state 1, 11 (info), 1, 2 (discharging, its current sent unsigned), 1
    assert [p["state"] for p in got["phases"]] == ["charge", "idle", "charge", "discharge", "charge"]
    assert (got["charge_out_mah"], got["i_max_a"]) == (542.0, 5.07)     # the counter: 544


@pytest.mark.parametrize("name, samples", [
    ("308DUO_LiFe_2.3Ah_Laden_0_CH1_head120.txt", 120), ("406DUO_Turnigy_4S_1500_A_Charge_0_CH1_head120.txt", 117),
    ("X6_LiFe_10-3A_Cycle_2_head120.txt", 116), ("X8_LiPo_5S_2200mA_Charge_4_head120.txt", 116),
])
def test_duo_x_lines_stay_with_the_duo_x_log_reader(name, samples):
    """The raw-capture reader is last: a DUO/X log is read as one, with the driver's count."""
    got = info(REAL / name)
    assert (got["format"], got["samples"], got["bad_records"]) == ("icharger-duo-txt", samples, 0)


def test_hid_report_dump(tmp_path):
    # the DUO/X USB-HID log report quoted in the notes (section C), as a dump of 64-byte reports
    report = ("2C 10 01 F8 7D 07 00 02 01 00 E5 FF 04 87 2B 3C CF FF FF FF 64 01 00 00 02 0F 0B 0F 0E 0F 00 0F"
              + " 00" * 32)
    dump = tmp_path / "duo.hid.txt"
    dump.write_text(f"# USB capture\nIN {report}\nIN {report}\n")
    got = info(dump)
    assert (got["format"], got["device"], got["samples"], got["bad_records"]) == \
        ("raw-capture", "Junsi iCharger DUO/X (USB)", 2, 0)
    assert got["charge_out_mah"] == 0.0 and got["cells"] == 4    # two equal reports: the counter moved 0


def test_export_of_a_raw_capture(tmp_path):
    target = tmp_path / "208b.csv"
    rc, out, err = run_zuml("log", "export", str(REAL / "icharger208B_Storage_lines.txt"), "-o", str(target))
    assert rc == 0, err
    rows = list(csv.DictReader(target.open(encoding="utf-8")))
    assert len(rows) == 68
    assert rows[0] == {"t_s": "0.000", "voltage_v": "11.4740", "current_a": "0.4500", "temp_c": "",
                       "charge_in_mah": "0.0", "charge_out_mah": "0.0", "state": "charge",
                       "cell1_v": "3.8330", "cell2_v": "3.8380", "cell3_v": "3.8370"}


def test_garbage_is_refused_naming_the_raw_capture_too(tmp_path):
    junk = tmp_path / "junk.bin"
    junk.write_bytes(bytes(range(256)) * 4)
    rc, out, err = run_zuml("log", "info", str(junk))
    assert rc != 0 and "raw capture" in err and "Traceback" not in err
