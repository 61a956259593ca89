"""Time that goes back in a log (issue 27: 161 mutated real logs were summarised with a negative
duration; issue 33: never drop a row for its time): where time goes back a new record set starts,
following the last, and the summary says where."""
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


@pytest.mark.parametrize("times, placed, first, sets", [
    ([0, 1, 2, 9e9, 4, 5, 6], [0, 1, 2, 9e9, 9e9 + 1, 9e9 + 2, 9e9 + 3], 5, 2),    # nothing dropped
    ([0, 1, 2, -50, 4, 5], [0, 1, 2, 3, 57, 58], 4, 2),
    ([0, 1, 2, 3, 4, 0.5, 1.5, 2.5], [0, 1, 2, 3, 4, 5, 6, 7], 6, 2),            # a clock reset: a new set
    ([10, 11, 0, 1, 2, 3, 4], [10, 11, 12, 13, 14, 15, 16], 3, 2),
    ([0, 1, 0, 1, 0, 1], [0, 1, 2, 3, 4, 5], 3, 3),
])
def test_time_that_goes_back_starts_a_new_record_set_and_no_sample_is_left_out(times, placed, first, sets):
    moved, note = in_time_order(times)
    assert moved == pytest.approx(placed)
    assert note["first_sample"] == first and note["record_sets"] == sets and note["left_out"] == 0
    assert note["time_s"] < note["previous_s"]


def test_a_csv_whose_time_restarts_at_row_120_reads_all_200_rows_as_two_record_sets():
    # The hostile-3 reproducer (csv_hostile.py time_backwards): 200 rows 10 s apart, time back to 0 at row 120.
    rows = [f"{(i if i < 120 else i - 120) * 10:.1f};{7.4 + i * 0.004:.3f};2,000".replace(".", ",")
            for i in range(200)]
    log = read_log(("Zeit [s];Spannung [V];Strom [A]\n" + "\n".join(rows) + "\n").encode(), "back.csv")
    assert (len(log.samples), log.bad_records) == (200, 0)
    assert [s.time_s for s in log.samples] == [10.0 * i for i in range(200)]
    assert log.meta["time_order"]["record_sets"] == 2
    assert min(p.start_s for p in log.phases()) >= 0


def test_a_real_log_with_one_time_sent_back_reads_every_sample_and_says_so():
    whole = summarize(read_log(AKKUMASTER.read_bytes(), AKKUMASTER.name))
    info = summarize(read_log(_with_times({101: "5.00"}), AKKUMASTER.name))
    assert info["samples"] == whole["samples"]
    assert info["time_order"] == {"first_sample": 101, "time_s": 5.0, "previous_s": 990.0, "left_out": 0,
                                  "record_sets": 2}
    assert time_order_text(info["time_order"]) == \
        "time goes back at sample 101 (5 s after 990 s): read as 2 record sets, each following the last; " \
        "no sample left out"


def test_log_info_prints_the_time_fault_on_its_own_line(capsys, tmp_path):
    path = tmp_path / AKKUMASTER.name
    path.write_bytes(_with_times({k: "0.00" for k in range(51, 61)}))
    assert main(["log", "info", str(path)]) == 0
    out = capsys.readouterr().out
    assert "  time goes back at sample 51 (0 s after 490 s): read as 2 record sets, each following the last; " \
           "no sample left out\n" in out
