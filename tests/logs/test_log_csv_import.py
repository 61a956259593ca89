"""CSV import (logs/csv_import.py) on real CSVs: the SkyRC B6AC v2 logger's ``SN,Volatge,Current,mAH``
(tests/data/realdata), DataExplorer's German export (tests/data/logs), and the SkyRC file as a
German spreadsheet writes it (``;``, decimal comma, ``Zeit [s];Spannung [V];…``). Expected values
are read here with the csv module."""
import csv
import io
from pathlib import Path

import numpy as np
import pytest
from logdata import data

from zuml_studio.logs import LogFormatError, csv_import, read_log

REAL = Path(__file__).resolve().parents[1] / "data" / "realdata"
SKYRC = REAL / "skyrc_B6ACv2_Charging_head100.csv"


def rows(raw: bytes, sep: str = ",") -> list[list[str]]:
    return list(csv.reader(io.StringIO(raw.decode()), delimiter=sep))


def test_skyrc_logger_csv_is_guessed_and_read():
    raw = SKYRC.read_bytes()
    g = csv_import.guess(raw)
    assert (g.separator, g.decimal_comma, g.header_line) == (",", False, 0)
    assert g.spec() == "time:s,voltage:V,current:mA,charge:mAh"        # Current 310 -> mA by its size
    log = read_log(raw, "skyrc.csv")
    table = rows(raw)
    assert table[0] == ["SN", "Volatge", "Current", "mAH"]
    body = table[1:]
    assert (log.format, len(log.samples), log.bad_records) == ("csv", len(body), 0)
    for s, row in zip(log.samples, body):
        assert s.time_s == pytest.approx(float(row[0]) - float(body[0][0]))
        assert s.voltage_v == float(row[1]) and s.current_a == pytest.approx(float(row[2]) / 1000)
    # In: the current integrated; the logger's counter agrees within 3 %.
    assert log.samples[-1].mah_in == pytest.approx(max(float(row[3]) for row in body) - float(body[0][3]), rel=0.03)


def test_german_spreadsheet_with_decimal_comma():
    table = rows(SKYRC.read_bytes())[1:]
    text = "Zeit [s];Spannung [V];Strom [mA];Ladung [mAh];Temperatur [°C]\n" + "".join(
        ";".join(x.replace(".", ",") for x in row) + ";21,5\n" for row in table)
    raw = text.encode("cp1252")                       # as Excel on a German Windows saves it
    g = csv_import.guess(raw)
    assert (g.separator, g.decimal_comma) == (";", True)
    assert g.spec() == "time:s,voltage:V,current:mA,charge:mAh,temp:°C"
    log = csv_import.read(raw, g)
    assert [s.voltage_v for s in log.samples] == [float(row[1]) for row in table]
    assert all(s.temp_c == 21.5 for s in log.samples)


def test_dataexplorer_export_read_as_csv_agrees_with_its_own_reader():
    raw = data("AkkuMasterC4_2007-12-28-EmpfaengerAA4-Laden.csv")
    own, generic = read_log(raw), read_log(raw, fmt="csv")
    assert own.format == "dataexplorer-csv" and csv_import.guess(raw).header_line == 1
    assert [(s.time_s, s.voltage_v, s.current_a, s.mah_in) for s in generic.samples] == \
        [(s.time_s, s.voltage_v, s.current_a, s.mah_in) for s in own.samples]


def test_columns_override_the_guess():
    raw = (REAL / "skyrc_B6ACv2_Discharging_head100.csv").read_bytes()
    body = rows(raw)[1:]
    g = csv_import.guess(raw)
    fixed = g.with_columns(csv_import.parse_columns("time:s,voltage:V,current:-mA,charge:mAh",
                                                    tuple(c.name for c in g.columns)))
    log = csv_import.read(raw, fixed)
    assert log.samples[-1].current_a == pytest.approx(-float(body[-1][2]) / 1000)
    moved = float(body[-1][3]) - float(body[0][3])
    assert log.samples[-1].mah_out == pytest.approx(moved, rel=0.03, abs=0.2) and log.samples[-1].mah_in == 0
    assert {p.state for p in log.phases()} <= {"idle", "discharge"}
    minutes = g.with_columns(csv_import.parse_columns("time:min,voltage", tuple(c.name for c in g.columns)))
    assert csv_import.read(raw, minutes).samples[-1].time_s == pytest.approx(
        (float(body[-1][0]) - float(body[0][0])) * 60)


@pytest.mark.parametrize("spec, message", [
    ("time:s,volts", "'volts' is not a role"), ("time:s,voltage:kV", "'kV' is not a unit of voltage"),
    ("time,voltage,current,charge,temp", "5 columns given, the file has 4")])
def test_a_wrong_columns_spec_says_why(spec, message):
    names = ("SN", "Volatge", "Current", "mAH")
    with pytest.raises(ValueError, match=message):
        csv_import.parse_columns(spec, names)


def test_a_csv_without_time_or_voltage_is_refused_with_the_reason():
    g = csv_import.guess(b"a,b\nx1,2\n3,4\n")
    with pytest.raises(LogFormatError, match="no time column|no voltage column"):
        csv_import.read(b"a,b\nx1,2\n3,4\n", g.with_columns(csv_import.parse_columns("-,-", ("a", "b"))))


def test_the_fit_s_curve_csv_is_left_to_the_fit():
    assert not csv_import.sniff(b"time_s,voltage_v,current_a\n0,4.0,1.0\n1,4.1,1.0\n", "c.csv")


def test_a_csv_is_read_into_columns_a_block_at_a_time_with_progress(monkeypatch):
    # Issue 33 §1 (cost): the rows go into numpy columns, never a Telemetry per row; the reader says how far
    # it is after each block of lines (the log window's progress bar).
    from zuml_studio.logs import csv_import as reader
    monkeypatch.setattr(reader, "TEXT_BLOCK", 64)
    rows = "".join(f"{k};{7.4 + k * 0.01:.2f};2,0\n".replace(".", ",") for k in range(50))
    data = ("Zeit [s];Spannung [V];Strom [A]\n" + rows).encode()
    told = []
    log = read_log(data, "x.csv", progress=lambda done, total: told.append((done, total)))
    assert len(told) > 5 and told[-1] == (len(data), len(data))
    assert all(a[0] <= b[0] for a, b in zip(told, told[1:]))
    assert isinstance(log.columns.voltage, np.ndarray) and len(log.columns.voltage) == 50
    assert log.samples[-1].voltage_v == pytest.approx(7.89) and log.samples[-1].time_s == 49.0
    assert log.samples[3] == log.columns.sample(3)
