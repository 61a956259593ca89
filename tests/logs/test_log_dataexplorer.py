"""DataExplorer .osd files against the notes' own conversions (curves/*.csv, trimmed copies
here: per record set its full row count, its first 40 and last 3 rows), and the LogView
open-format samples DataExplorer ships."""
import csv
import io

import pytest
from logdata import data

from zuml_studio.logs import LogFormatError, read_log

OSD = {  # .osd: (its conversion, samples, mAh in, mAh out, device)
    "Akkumatik_2015-03-27_NiCd_E-L_Cycle.osd": ("NiCd_Akkumatik_discharge_charge_cycle_with_temp", 19223, 2328, 1973,
                                                "Akkumatik"),
    "PolaronACDC_2014-08-15_LiIo_2_4000.osd": ("LiIon_2S_4000_PolaronACDC_charge", 1613, 440, 0, "PolaronACDC"),
    "PolaronPro_2014-08-23_5S_NiMh_cycle.osd": ("NiMH_5S_PolaronPro_cycle_with_temp", 21963, 1917, 1440, "PolaronPro"),
    "UltramatACDCEQ_2014-09-16_4S_NiMH_cycle.osd": ("NiMH_4S_Ultramat_ACDC_EQ_cycle", 78483, 5562, 5083,
                                                    "Ultramat ACDC EQ"),
    "eStationBC6_2008-07-05_EmpfaengerAA.osd": ("NiMH_AA_Rx_eStationBC6_cycle", 8840, 1982, 1543, "eStationBC6"),
}


def conversion_sets(name: str):
    """[(full row count, header, rows kept)] per record set of a trimmed conversion."""
    sets = []
    for line in data(name + ".trimmed.csv").decode("utf-8").splitlines():
        if line.startswith("### RECORDSET"):
            sets.append([0, None, []])
        elif line.startswith("# rows="):
            sets[-1][0] = int(line[7:])
        elif line.startswith("time_s"):
            sets[-1][1] = next(csv.reader(io.StringIO(line)))
        elif line and not line.startswith("#"):
            sets[-1][2].append([float(x) for x in line.split(",")])
    return sets


def column(header, prefix):
    for k, name in enumerate(header):
        if name.startswith(prefix):
            return k
    return None


@pytest.mark.parametrize("name", sorted(OSD))
def test_osd_values_match_the_notes_conversion(name):
    conversion, samples, q_in, q_out, device = OSD[name]
    log = read_log(data(name), name)
    assert log.format == "dataexplorer-osd" and log.device == device
    assert len(log.samples) == samples and log.bad_records == 0
    # In/out: the current integrated; the device's counter agrees within 3 % (else it would be said).
    assert (log.samples[-1].mah_in, log.samples[-1].mah_out) == (pytest.approx(q_in, rel=0.03),
                                                              pytest.approx(q_out, rel=0.03))
    assert "charge_check" not in log.meta
    start = 0
    for count, header, rows in conversion_sets(conversion):
        chunk = log.samples[start:start + count]
        kept = chunk[:40] + chunk[-3:] if count > 43 else chunk
        v, i, t = column(header, "Spannung"), column(header, "Strom"), column(header, "BatterieTemperatur")
        for sample, row in zip(kept, rows, strict=True):
            assert sample.voltage_v == pytest.approx(row[v], abs=1e-9)
            assert abs(sample.current_a) == pytest.approx(abs(row[i]), abs=1e-9)
            if t is not None:
                assert sample.temp_c == pytest.approx(row[t], abs=1e-9)
            for k, cell in enumerate(sample.cells_v, 1):
                assert cell == pytest.approx(row[column(header, f"ZellenSpannung {k} ")], abs=1e-9)
        start += count
    assert start == samples


def test_osd_record_sets_give_states_and_signs():
    log = read_log(data("PolaronPro_2014-08-23_5S_NiMh_cycle.osd"))
    assert [p.state for p in log.phases()] == ["discharge", "pause", "charge", "pause"]
    discharge = [s for s in log.samples if s.section == "discharge"]
    assert all(s.current_a <= 0 for s in discharge)
    assert 19.6 <= min(s.temp_c for s in log.samples) and max(s.temp_c for s in log.samples) == pytest.approx(28.3)


def test_osd_polaron_acdc_has_two_cells_and_the_cv_end():
    # datasets.md: Li-ion 2S 4000 mAh, CV end at 8.2 V; cells 1 and 2 measured, 3..7 constant 0
    log = read_log(data("PolaronACDC_2014-08-15_LiIo_2_4000.osd"))
    assert log.cells == 2
    assert log.samples[-1].voltage_v == pytest.approx(8.22)


def test_osd_truncated_is_a_precise_error():
    import zipfile
    raw = zipfile.ZipFile(io.BytesIO(data("PolaronACDC_2014-08-15_LiIo_2_4000.osd")))
    inner = raw.read(raw.namelist()[0])
    with pytest.raises(LogFormatError, match="data bytes do not hold|past the end"):
        read_log(inner[:-1000], fmt="dataexplorer-osd")
    with pytest.raises(LogFormatError, match="ZIP"):
        read_log(data("PolaronACDC_2014-08-15_LiIo_2_4000.osd")[:3000], "x.osd")


# -- LogView open format ----------------------------------------------------------------------
def test_open_format_time_increment_and_battery_column():
    log = read_log(data("LogViewOpenFormat_TimeInc_Ch1_1Log.txt"))
    assert log.format == "logview-open" and len(log.samples) == 35
    assert log.samples[1].time_s == pytest.approx(0.1)           # $I$;100 ms
    assert log.samples[0].voltage_v == 11.63                      # U_Lipo[V], not U_Gate[V]
    assert log.samples[0].temp_c == 25.49                         # the first column in °C


def test_open_format_second_channel_counted_apart_and_sets_follow():
    log = read_log(data("LogViewOpenFormat_TimeInc_Ch1-2_2Logs.txt"))
    assert len(log.samples) == 35 and log.meta["other_channel_lines"] == 35
    times = [s.time_s for s in log.samples]
    assert times == sorted(times)


def test_open_format_time_given_hex():
    log = read_log(data("LogViewOpenFormat_TimeGiven_HEX.txt"))
    assert [s.time_s for s in log.samples] == [0.0, 1.0, 4.0, 6.0, 9.0]     # ddHHmmss
    assert [s.temp_c for s in log.samples][:2] == [10.0, 26.0]              # A, 1A
    assert log.samples[0].voltage_v == 0xCC
    assert log.meta["current_measured"] is False


def test_open_format_factors():
    log = read_log(data("LogViewOpenFormat_TimeGiven_Offsets_Factor.txt"))
    first = log.samples[0]
    assert first.temp_c == pytest.approx(5.1 * 2) and first.voltage_v == pytest.approx(2.3 * 1.5)
    assert [s.time_s for s in log.samples] == [0.0, 1.0, 2.0, 3.0, 4.0]


def test_open_format_bad_lines_counted():
    text = b"$N$;x\r\n$C$;U[V];I[A]\r\n$1.0;2.0\r\n$1.0\r\n$abc;1\r\n$2.0;-1.0\r\n"
    log = read_log(text)
    assert len(log.samples) == 2 and log.bad_records == 2
    assert [p.state for p in log.phases()] == ["charge", "discharge"]


def test_open_format_without_volts_is_refused():
    with pytest.raises(LogFormatError, match="volts"):
        read_log(b"$N$;x\n$C$;T[\xc2\xb0C]\n$1.0\n")


# -- DataExplorer CSV export ------------------------------------------------------------------
@pytest.mark.parametrize("name, rows, mah, last_v, direction", [
    ("AkkuMasterC4_2007-12-28-EmpfaengerAA4-Laden.csv", 2203, 917.0, 5.865, "charge"),
    ("AkkuMasterC4_2007-12-28-EmpfaengerAA4-Entladen.csv", 951, 397.0, None, "discharge"),
])
def test_dataexplorer_csv_export(name, rows, mah, last_v, direction):
    # datasets.md: H-Tronic AkkuMaster C4, NiMH AA 4 cells, 0.15 A, 10 s sampling
    log = read_log(data(name), name)
    assert (log.format, log.device, len(log.samples), log.bad_records) == ("dataexplorer-csv", "AkkuMasterC4",
                                                                           rows, 0)
    assert log.samples[1].time_s - log.samples[0].time_s == 10.0
    assert max(abs(s.current_a) for s in log.samples) == 0.15
    # The export says no direction and logs the discharge with positive current: the voltage falling
    # under load makes it a discharge. The current integrated agrees with the counter.
    moved = log.samples[-1].mah_in if direction == "charge" else log.samples[-1].mah_out
    assert moved == pytest.approx(mah, rel=0.03) and "charge_check" not in log.meta
    assert {s.section for s in log.samples if s.running} == {direction}
    if last_v is not None:
        assert log.samples[-1].voltage_v == last_v


def test_dataexplorer_csv_decimal_comma_clock_time_and_bad_rows():
    raw = ("Dev;Outlet 1\nTime [hh:mm:ss.SSS];Voltage [V];Current [A]\n"
           "00:00:00.000;4,10;1,00\n00:00:01.500;4,11;1,00\nbroken\n00:00:03.000;x;1\n").encode()
    log = read_log(raw)
    assert [s.time_s for s in log.samples] == [0.0, 1.5] and log.samples[1].voltage_v == 4.11
    assert log.bad_records == 2 and log.device == "Dev"
