"""iCharger DUO/X text logs and LogView .lov files (iCharger serial models, iMAX B6,
Ultramat): every recording in tests/data/logs, with the values the notes give
(realdata/icharger_logview.md, dataexplorer.md, datasets.md)."""
import pytest
from logdata import data

from zuml_studio.logs import LogFormatError, read_log
from zuml_studio.streams.stream_decoder import xor8

# file: (samples, cells, IR readings, mAh in at the end, duration s, device)
DUO = {
    "308DUO_LiFe_2.3Ah_Laden_0_CH1.txt": (897, 2, 0, 409.0, 896.0, "Junsi iCharger (DUO/X log)"),
    "4010DUO_LiFe_2S_3A_Charge_1_CH1.txt": (421, 0, 0, 102.0, 420.0, "Junsi iCharger (DUO/X log)"),
    "406DUO_Turnigy_4S_1500_A_Charge_0_CH1.txt": (1079, 4, 9, 1117.0, 1078.0, "Junsi iCharger 406DUO"),
    "X6_LiFe_10-3A_Cycle_2.txt": (794, 6, 13, 95.0, 793.0, "Junsi iCharger X6"),
    "X6_LiPo_Cycle_1.first1200.txt": (1200, 5, 0, 223.0, 1199.0, "Junsi iCharger X6"),
    "X8_LiPo_5S_2200mA_Charge_4.txt": (1375, 5, 23, 2016.0, 1374.0, "Junsi iCharger X8"),
    "codelever_4010DUO_LiPo_Storage_952_CH1.txt": (447, 6, 0, 464.0, 446.0, "Junsi iCharger (DUO/X log)"),
}


@pytest.mark.parametrize("name", sorted(DUO))
def test_every_duo_log_reads_with_its_counts(name):
    samples, cells, ir, mah_in, duration, device = DUO[name]
    log = read_log(data(name), name)
    assert log.format == "icharger-duo-txt"
    assert log.device == device
    assert len(log.samples) == samples
    assert log.bad_records == 0          # every checksum in the real files is right
    assert log.cells == cells
    assert len(log.resistance) == ir
    assert log.samples[-1].mah_in == pytest.approx(mah_in, rel=0.03)    # integrated; the counter agrees
    assert "charge_check" not in log.meta
    assert log.samples[-1].time_s - log.samples[0].time_s == duration


def test_every_record_of_the_real_files_passes_its_checksum():
    for name in DUO:
        for line in data(name).split(b"\n"):
            if line.startswith(b"$"):
                body, _, ck = line.strip().rpartition(b";")
                assert xor8(body + b";") == int(ck), line


def test_x8_charge_matches_the_notes():
    # datasets.md: LiPo 5S 2200 mAh, 6.0 A -> 20.92 V, end 0.75 A, 2016 mAh, 23 min, ext. T 22 -> 26 °C
    log = read_log(data("X8_LiPo_5S_2200mA_Charge_4.txt"))
    s = log.samples
    assert max(x.current_a for x in s) == pytest.approx(6.02)
    assert max(x.voltage_v for x in s) == pytest.approx(20.923)
    assert s[-1].current_a == pytest.approx(0.75)
    assert 22 <= s[-1].time_s / 60 <= 23
    assert min(x.temp_c for x in s) == pytest.approx(22.2) and max(x.temp_c for x in s) == pytest.approx(26.0)
    assert log.meta["battery"] == "LiPo" and log.meta["header"]["Model"] == "X8"
    # `$1;128;2000;293;189;39;39;37;38;36;0;0;0;37`: pack 29.3 mΩ, then Σcells, then the 5 connected cells
    assert log.resistance[0] == (2.0, 29.3, (3.9, 3.9, 3.7, 3.8, 3.6))


def test_x6_ir_record_without_pack_value():
    # X6 FW 2.0.6: `$1;128;3000;738;122;121;128;122;125;120;29`, 738 = Σ of the six cells
    log = read_log(data("X6_LiFe_10-3A_Cycle_2.txt"))
    assert log.resistance[0] == (3.0, None, (12.2, 12.1, 12.8, 12.2, 12.5, 12.0))


def test_x6_cycle_has_charge_pause_discharge_and_signed_current():
    log = read_log(data("X6_LiFe_10-3A_Cycle_2.txt"))
    assert [(p.state, p.start_s) for p in log.phases()] == [("charge", 0.0), ("pause", 367.0),
                                                             ("discharge", 428.0)]
    last = log.samples[-1]
    assert last.current_a == -1.5 and last.section == "discharge"
    # the capacity counter restarts for the discharge and counts negative: 95 in, then 149 out
    assert (last.mah_in, last.mah_out) == (pytest.approx(95.0, rel=0.03), pytest.approx(149.0, rel=0.03))
    assert all(x.temp_c is None for x in log.samples)     # ext. temperature 0 throughout: no probe


def test_first_record_decoded_as_the_notes_show():
    # `$1;1;0;1;0;0;27175;14925;0;280;243;3725;3734;3729;3733;0;0;39` (406DUO, LiPo 4S)
    first = read_log(data("406DUO_Turnigy_4S_1500_A_Charge_0_CH1.txt")).samples[0]
    assert (first.time_s, first.voltage_v, first.current_a) == (0.0, 14.925, 0.0)
    assert (first.heatsink_c, first.temp_c) == (28.0, 24.3)
    assert first.cells_v == (3.725, 3.734, 3.729, 3.733)


def test_bad_checksum_torn_line_and_garbage_are_counted_not_read():
    good = data("308DUO_LiFe_2.3Ah_Laden_0_CH1.txt").split(b"\r\n")
    lines = [good[0], good[1][:-1] + b"9" if not good[1].endswith(b"9") else good[1][:-1] + b"8",
             good[2][:20], b"garbage \x00\xff", good[3]]
    log = read_log(b"\r\n".join(lines) + b"\r\n", fmt="icharger-duo-txt")
    assert len(log.samples) == 2
    assert log.bad_records == 3


def test_other_channel_records_are_kept_apart():
    line1 = b"$1;1;0;1;0;0;27175;14925;0;280;243;3725;3734;3729;3733;0;0;39"
    body = b"$2;1;0;1;0;0;27175;14925;0;280;243;3725;3734;3729;3733;0;0;"
    ck = 0
    for b in body:
        ck ^= b
    log = read_log(line1 + b"\n" + body + str(ck).encode() + b"\n")
    assert len(log.samples) == 1 and log.meta["other_channel_records"] == 1


# -- LogView .lov -------------------------------------------------------------------------------
def test_lov_106b_charge_matches_the_notes():
    # datasets.md: LiPo 3S, 0.43 A -> 12.37 V, 1201 mAh, 189 min, 2 s records
    log = read_log(data("iCharger106Bplus_Laden.lov"), "iCharger106Bplus_Laden.lov")
    assert log.format == "logview-lov" and log.device == "Junsi iCharger 106B+"
    assert len(log.samples) == 5679 and log.bad_records == 0
    assert log.cells == 3
    assert max(x.current_a for x in log.samples) == pytest.approx(0.43)
    assert max(x.voltage_v for x in log.samples) == pytest.approx(12.376)
    assert log.samples[-1].mah_in == pytest.approx(1201.0, rel=0.03) and "charge_check" not in log.meta
    assert log.samples[-1].time_s == 11356.0 and log.samples[1].time_s == 2.0


def test_lov_208b_first_record_as_the_notes_show():
    # `$1;1;;13889;11474;45;3833;3838;3837;0;0;0;0;0;165;0;0;20` (208B, 8 cell slots, 3 used)
    log = read_log(data("iCharger208B_Storage.lov"))
    assert len(log.samples) == 68
    first = log.samples[0]
    assert (first.voltage_v, first.current_a, first.heatsink_c, first.temp_c) == (11.474, 0.45, 16.5, None)
    assert first.cells_v == (3.833, 3.838, 3.837)


def test_lov_ultramat_frames_go_to_the_ultramat_driver():
    # 69 frames of an Ultramat 16 (52 bytes, the layout the notes give), 1 s apart
    log = read_log(data("Ultramat16_2011-04-21_Test_Ultramat16.lov"))
    assert (log.format, log.device, len(log.samples), log.bad_records) == ("logview-lov", "Ultramat 16", 69, 0)
    assert log.meta["driver"] == "ultramat" and log.samples[-1].time_s == 68.0


def test_lov_imaxb6_frames_match_the_decoded_csv_and_carry_their_time():
    """The 76-byte frames with their Delphi TDateTime: the values and times the notes' decoded
    CSV (shared imaxb6_serial/iMaxB6_Ladung3S450mAh_decoded.csv, its first 300 rows) gives."""
    import csv
    from pathlib import Path
    log = read_log(data("iMaxB6_Ladung3S450mAh.lov"))
    assert (log.device, len(log.samples), log.bad_records, log.cells) == ("IMAX B6", 1609, 0, 3)
    decoded = Path(__file__).resolve().parents[1] / "data" / "realdata" / "imaxb6_Ladung3S450mAh_decoded_head300.csv"
    with decoded.open() as fh:
        rows = list(csv.DictReader(fh))
    for s, row in zip(log.samples, rows):
        assert s.time_s == pytest.approx(float(row["t_s"]), abs=0.002)
        assert round(s.voltage_v * 1000) == int(row["V_mV"]) and round(s.current_a * 1000) == int(row["I_mA"])
        assert s.mah_in == pytest.approx(float(row["C_mAh"]), abs=2.0)     # integrated; the counter agrees
        assert [round(c * 1000) for c in s.cells_v] == [int(row[f"c{k}_mV"]) for k in range(1, 4)]


def test_lov_of_a_device_without_a_driver_is_refused_by_name():
    raw = data("Ultramat16_2011-04-21_Test_Ultramat16.lov").replace(b"Name=Ultramat 16", b"Name=Pichler P60")
    with pytest.raises(LogFormatError, match="'Pichler P60'.*iMAX B6"):
        read_log(raw)


def test_lov_record_with_bad_checksum_is_counted():
    raw = bytearray(data("iCharger208B_Storage.lov"))
    at = raw.find(b"$1;1;;13889;11474;45;")
    raw[at + 13] = ord("9")              # 11474 -> 11974: the checksum no longer fits
    log = read_log(bytes(raw))
    assert len(log.samples) == 67 and log.bad_records == 1


def test_a_torn_first_line_does_not_hide_the_format():
    raw = data("4010DUO_LiFe_2S_3A_Charge_1_CH1.txt")
    log = read_log(raw[7:])                 # starts in the middle of the first record
    assert log.format == "icharger-duo-txt" and len(log.samples) == 420 and log.bad_records == 1
