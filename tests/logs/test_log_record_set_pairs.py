"""Issue 33 §4: every real log and every DataExplorer-style CSV export of it read to the same sessions.

Two kinds of pair: (1) each real ``.osd`` and the ``### RECORDSET`` CSV the shared notes converted from it
(tests/data/realdata/*.csv.xz, provenance in its README); (2) every real log the tests hold
(tests/data/logs, tests/data/realdata) and ``zuml log export --dataexplorer`` of it, read back by the CSV
reader. "The same sessions": the same samples in the same order, with the same times (from the first),
voltages, currents, states, temperatures, cells and charge in/out."""
import io
import lzma

import numpy as np
import pytest

from helpers import ROOT
from zuml_studio.cli.main import main
from zuml_studio.logs import LogFormatError, read_log
from zuml_studio.logs.export import write_record_sets
from zuml_studio.logs.model import Log, state_of
from zuml_studio.logs.summary import summarize

LOGS = ROOT / "tests" / "data" / "logs"
REAL = ROOT / "tests" / "data" / "realdata"
CONVERTED = {
    "LiIon_2S_4000_PolaronACDC_charge.csv.xz": "PolaronACDC_2014-08-15_LiIo_2_4000.osd",
    "NiMH_AA_Rx_eStationBC6_cycle.csv.xz": "eStationBC6_2008-07-05_EmpfaengerAA.osd",
    "NiCd_Akkumatik_discharge_charge_cycle_with_temp.csv.xz": "Akkumatik_2015-03-27_NiCd_E-L_Cycle.osd",
    "NiMH_5S_PolaronPro_cycle_with_temp.csv.xz": "PolaronPro_2014-08-23_5S_NiMh_cycle.osd",
    "NiMH_4S_Ultramat_ACDC_EQ_cycle.csv.xz": "UltramatACDCEQ_2014-09-16_4S_NiMH_cycle.osd",
}


def _bytes(path):
    """A file's bytes, an ``.xz`` one decompressed (the large real CSVs are stored so)."""
    return lzma.decompress(path.read_bytes()) if path.suffix == ".xz" else path.read_bytes()


def _name(path):
    return path.name.removesuffix(".xz")


def _readable(folder):
    out = []
    for path in sorted(folder.iterdir()):
        if path.suffix == ".md":
            continue
        try:
            read_log(_bytes(path), _name(path))
        except LogFormatError:
            continue                         # not a log (an HID dump of no driver's layout)
        out.append(path)
    return out


ORIGINALS = _readable(LOGS) + _readable(REAL)


def _columns(log: Log) -> dict[str, np.ndarray]:
    made = log.arrays()
    made["t"] = made["t"] - made["t"][0]
    made["in"] = np.array([s.mah_in for s in log.samples])
    made["out"] = np.array([s.mah_out for s in log.samples])
    return made


def same_sessions(a: Log, b: Log, volts: float = 1e-6, charge_mah: float = 0.5) -> None:
    assert len(a.samples) == len(b.samples)
    assert a.cells == b.cells
    assert [state_of(x) for x in a.samples] == [state_of(y) for y in b.samples]
    x, y = _columns(a), _columns(b)
    for name, tolerance in (("t", 1e-3), ("voltage", volts), ("current", volts), ("temp", volts),
                            ("cells", volts), ("in", charge_mah), ("out", charge_mah)):
        np.testing.assert_allclose(x[name], y[name], rtol=0, atol=tolerance, err_msg=name)   # NaN == NaN
    assert [p.state for p in a.phases()] == [p.state for p in b.phases()]


@pytest.mark.parametrize("converted", sorted(CONVERTED))
def test_an_osd_and_its_record_set_csv_read_to_the_same_sessions(converted):
    osd = read_log((LOGS / CONVERTED[converted]).read_bytes(), CONVERTED[converted])
    csv = read_log(lzma.decompress((REAL / converted).read_bytes()), converted[:-3])
    assert csv.format == "csv" and csv.bad_records == 0
    assert csv.meta["record_sets"] == osd.meta["record_sets"]      # every block a record set, named
    # The conversion rounds values to the 3rd decimal and gives times in ms.
    same_sessions(osd, csv, volts=1e-3, charge_mah=1.0)
    a, b = summarize(osd), summarize(csv)
    assert (a["charge_in_mah"], a["charge_out_mah"], a["phases"]) == \
        (pytest.approx(b["charge_in_mah"], abs=1), pytest.approx(b["charge_out_mah"], abs=1), b["phases"])


@pytest.mark.parametrize("path", ORIGINALS, ids=[p.name for p in ORIGINALS])
def test_a_log_and_its_dataexplorer_style_export_read_to_the_same_sessions(path):
    log = read_log(_bytes(path), _name(path))
    text = io.StringIO()
    assert write_record_sets(log, text, _name(path)) == len(log.samples)
    assert text.getvalue().count("### RECORDSET\n") == len(log.phases())
    back = read_log(text.getvalue().encode(), _name(path) + ".export.csv")
    assert back.format == "csv" and back.bad_records == 0
    same_sessions(log, back)
    if log.meta.get("started"):                      # dated as the log is (a time without a zone: UTC)
        assert back.meta["started"][:19] == log.meta["started"][:19]


def test_log_export_dataexplorer_writes_the_record_sets(tmp_path, capsys):
    source = LOGS / "eStationBC6_2008-07-05_EmpfaengerAA.osd"
    out = tmp_path / "e.csv"
    assert main(["log", "export", str(source), "--dataexplorer", "-o", str(out)]) == 0
    text = out.read_text()
    assert text.startswith("### RECORDSET\n# source=eStationBC6_2008-07-05_EmpfaengerAA.osd ")
    assert [line.split("recordset='")[1].split("'")[0] for line in text.splitlines() if "recordset=" in line] == \
        ["1) Entladen", "2) Laden", "3) Entladen", "4) Laden"]
    capsys.readouterr()
    assert main(["log", "info", str(out)]) == 0
    assert "  record sets  4: 1) Entladen; 2) Laden; 3) Entladen; 4) Laden\n" in capsys.readouterr().out
