"""Gaps in real recordings (logs/gaps.py): where they are, and that the per-pixel envelope a plot
draws keeps every column's min and max and never joins two samples across a gap. Expected values
are computed here from the samples by plain loops."""
import math

import numpy as np
import pytest
from logdata import GAP_AFTER_LINE, GAP_S, data, gapped_3010b_lov

from zuml_studio.logs import gaps, read_log


def segments_across(x, y, a, b):
    """Drawn segments (both ends finite) that start at or before a and end at or after b."""
    return [(x[k], x[k + 1]) for k in range(len(x) - 1)
            if math.isfinite(y[k]) and math.isfinite(y[k + 1]) and x[k] <= a and x[k + 1] >= b]


def test_the_3010b_hole_is_the_one_gap():
    log = read_log(gapped_3010b_lov())
    t = log.arrays()["t"]
    assert gaps.sample_period(t) == 2.0 and gaps.gap_threshold(t) == 10.0
    assert list(gaps.gap_after(t)) == [GAP_AFTER_LINE]
    assert gaps.covered_spans(t) == [(0.0, 2.0 * GAP_AFTER_LINE), (2.0 * (GAP_AFTER_LINE + 1) + int(GAP_S), t[-1])]
    assert gaps.in_gap(t, 2.0 * GAP_AFTER_LINE + 100) and not gaps.in_gap(t, 101.0)


@pytest.mark.parametrize("pixels", [50, 700, 1366, 100_000])
def test_envelope_at_every_zoom_keeps_min_and_max_and_never_bridges_the_hole(pixels):
    d = read_log(gapped_3010b_lov()).arrays()
    t, v = d["t"], d["voltage"]
    x, y = gaps.envelope(t, v, t[0], t[-1], pixels)
    before, after = t[GAP_AFTER_LINE], t[GAP_AFTER_LINE + 1]
    assert segments_across(x, y, before + 1, after - 1) == []
    assert not any(before < xi < after for xi, yi in zip(x, y) if math.isfinite(yi))
    # per pixel column and side of the hole, the drawn min and max are the samples' own
    width = (t[-1] - t[0]) / pixels
    expected: dict = {}
    for ti, vi in zip(t, v):
        key = (math.floor((ti - t[0]) / width), ti > before)
        lo, hi = expected.get(key, (vi, vi))
        expected[key] = (min(lo, vi), max(hi, vi))
    drawn: dict = {}
    for xi, yi in zip(x, y):
        if math.isfinite(yi):
            key = (math.floor((xi - t[0]) / width), xi > before)
            lo, hi = drawn.get(key, (yi, yi))
            drawn[key] = (min(lo, yi), max(hi, yi))
    assert drawn == expected
    assert len(x) <= 2 * pixels + 8


def test_a_missing_value_breaks_the_curve_too():
    t = np.arange(10.0)
    y = np.array([1, 2, np.nan, 4, 5, 6, np.nan, np.nan, 9, 10], dtype=float)
    x, e = gaps.envelope(t, y, 0, 9, 1000)
    assert segments_across(x, e, 1.5, 2.5) == [] and segments_across(x, e, 6.5, 7.5) == []
    assert [v for v in e if math.isfinite(v)] == [1, 2, 4, 5, 6, 9, 10]


def test_broken_inserts_a_nan_row_in_each_gap_of_a_dataexplorer_log():
    # The Ultramat ACDC EQ .osd: 10 record sets, each after a pause of 33-39 s the file leaves out
    log = read_log(data("UltramatACDCEQ_2014-09-16_4S_NiMH_cycle.osd"))
    d = log.arrays()
    t = d["t"]
    steps = np.diff(t)
    expected = [k for k in range(len(steps)) if steps[k] > 5 * 1.0]
    assert list(gaps.gap_after(t)) == expected and len(expected) == 10
    bt, bv = gaps.broken(t, d["voltage"])
    assert len(bt) == len(t) + 10 and int(np.isnan(bv).sum()) == 10
    for k in expected:
        at = int(np.searchsorted(bt, t[k])) + 1
        assert math.isnan(bv[at]) and bt[at - 1] == t[k] and bt[at + 1] == t[k + 1]


def test_a_recording_without_gaps_is_drawn_whole():
    d = read_log(data("X8_LiPo_5S_2200mA_Charge_4.txt")).arrays()
    x, y = gaps.envelope(d["t"], d["voltage"], d["t"][0], d["t"][-1], 5000)
    assert np.array_equal(x, d["t"]) and np.array_equal(y, d["voltage"])
