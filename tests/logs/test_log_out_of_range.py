"""A sample no charger could have measured (issue 27: a log with a voltage of 1e308 was summarised
with it): left out, and the summary says how many and where the first was."""
from helpers import ROOT
from zuml_studio.cli.main import main
from zuml_studio.logs import read_log
from zuml_studio.logs.summary import summarize

AKKUMASTER = ROOT / "tests" / "data" / "logs" / "AkkuMasterC4_2007-12-28-EmpfaengerAA4-Laden.csv"


def _with_voltages(values: dict[int, str]) -> bytes:
    """The AkkuMaster charge ("seconds; V; A; mAh", sample k on line k + 2) with some voltages replaced."""
    lines = AKKUMASTER.read_bytes().split(b"\n")
    for k, text in values.items():
        fields = lines[k + 1].split(b";")
        fields[1] = text.encode()
        lines[k + 1] = b";".join(fields)
    return b"\n".join(lines)


def test_absurd_voltages_are_left_out_and_counted():
    whole = summarize(read_log(AKKUMASTER.read_bytes(), AKKUMASTER.name))
    info = summarize(read_log(_with_voltages({8: "1e308", 30: "-5000"}), AKKUMASTER.name))
    assert info["samples"] == whole["samples"] - 2 and info["v_max"] == whole["v_max"]
    assert info["out_of_range"] == {"left_out": 2, "first_sample": 8}


def test_log_info_says_it_on_its_own_line(capsys, tmp_path):
    path = tmp_path / AKKUMASTER.name
    path.write_bytes(_with_voltages({8: "1e308"}))
    assert main(["log", "info", str(path)]) == 0
    assert ("  1 sample with a voltage or current past ±2000 (no charger measures that) left out, the first at "
            "sample 8\n") in capsys.readouterr().out
