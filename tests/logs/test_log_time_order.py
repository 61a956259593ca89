"""Time that goes back in a log (issue 27: 161 mutated real logs were summarised with a negative
duration): the samples out of order are left out, the longest part whose time never falls is read,
and the summary says where."""
import pytest

from helpers import ROOT
from zuml_studio.cli.main import main
from zuml_studio.logs import read_log
from zuml_studio.logs.model import in_time_order, time_order_text
from zuml_studio.logs.summary import summarize

AKKUMASTER = ROOT / "tests" / "data" / "logs" / "AkkuMasterC4_2007-12-28-EmpfaengerAA4-Laden.csv"


def _with_times(times: dict[int, str]) -> bytes:
    """The AkkuMaster charge (a DataExplorer CSV: "seconds; V; A; mAh", sample k on line k + 3) with
    some samples' times replaced."""
    lines = AKKUMASTER.read_bytes().split(b"\n")
    for k, text in times.items():
        fields = lines[k + 1].split(b";")
        fields[0] = text.encode()
        lines[k + 1] = b";".join(fields)
    return b"\n".join(lines)


def test_time_that_never_falls_is_kept_whole():
    assert in_time_order([0.0, 1.0, 1.0, 2.0]) == (None, None)     # a repeat: a session's next run


@pytest.mark.parametrize("times, kept, first", [
    ([0, 1, 2, 9e9, 4, 5, 6], [0, 1, 2, 4, 5, 6], 5),                # one garbled time drops one sample
    ([0, 1, 2, -50, 4, 5], [0, 1, 2, 4, 5], 4),
    ([0, 1, 2, 3, 4, 0.5, 1.5, 2.5], [0, 1, 2, 3, 4], 6),             # a clock reset: the longer part
    ([10, 11, 0, 1, 2, 3, 4], [2, 3, 4, 5, 6], 3),
])
def test_the_longest_part_in_time_order_is_kept_and_the_first_fault_named(times, kept, first):
    keep, note = in_time_order(times)
    assert keep == kept
    assert note["first_sample"] == first and note["left_out"] == len(times) - len(kept)
    assert note["time_s"] < note["previous_s"]


def test_a_real_log_with_one_time_sent_back_reads_the_rest_and_says_so():
    whole = summarize(read_log(AKKUMASTER.read_bytes(), AKKUMASTER.name))
    info = summarize(read_log(_with_times({101: "5.00"}), AKKUMASTER.name))
    assert info["samples"] == whole["samples"] - 1 and info["duration_s"] == whole["duration_s"] > 0
    assert info["time_order"] == {"first_sample": 101, "time_s": 5.0, "previous_s": 990.0, "left_out": 1}
    assert time_order_text(info["time_order"]) == \
        "time goes back at sample 101 (5 s after 990 s): 1 sample out of time order left out"


def test_log_info_prints_the_time_fault_on_its_own_line(capsys, tmp_path):
    path = tmp_path / AKKUMASTER.name
    path.write_bytes(_with_times({k: "0.00" for k in range(51, 61)}))
    assert main(["log", "info", str(path)]) == 0
    out = capsys.readouterr().out
    assert "  time goes back at sample 51 (0 s after 490 s): 10 samples out of time order left out\n" in out
