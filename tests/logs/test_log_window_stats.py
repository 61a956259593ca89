"""What a log says between two cursors (logs/window_stats.py), on real recordings, against numbers
computed here sample by sample with plain loops."""
import math

import pytest
from logdata import GAP_AFTER_LINE, data, gapped_3010b_lov

from zuml_studio.logs import read_log
from zuml_studio.logs.window_stats import between, deviation_mv

X8 = "X8_LiPo_5S_2200mA_Charge_4.txt"


def test_cursors_and_span_of_the_x8_charge():
    log = read_log(data(X8), X8)
    a, b = 300.2, 899.9
    got = between(log, a, b)
    assert between(log, b, a).curves == got.curves        # the span is the same either way
    at = {s.time_s: s for s in log.samples}
    sa, sb = at[300.0], at[900.0]                 # the nearest samples (1 s records)
    assert (got.a.t, got.b.t) == (300.0, 900.0)
    assert got.delta("voltage") == pytest.approx(sb.voltage_v - sa.voltage_v)
    assert got.delta("current") == pytest.approx(sb.current_a - sa.current_a)
    assert got.delta("net_mah") == (sb.mah_in - sb.mah_out) - (sa.mah_in - sa.mah_out)
    inside = [s for s in log.samples if a <= s.time_s <= b]
    assert got.samples == len(inside) == 599 and got.time_s == pytest.approx(b - a)
    v = [s.voltage_v for s in inside]
    assert (got.curves["voltage"].min, got.curves["voltage"].max) == (min(v), max(v))
    assert got.curves["voltage"].mean == pytest.approx(sum(v) / len(v))
    for k in range(5):
        cell = [s.cells_v[k] for s in inside]
        assert got.curves[f"cell {k + 1}"].mean == pytest.approx(sum(cell) / len(cell))
    spread = [(max(s.cells_v) - min(s.cells_v)) * 1000 for s in inside]
    assert got.curves["deviation"].max == pytest.approx(max(spread))
    assert got.charge_in_mah == inside[-1].mah_in - inside[0].mah_in and got.charge_out_mah == 0
    energy = sum((p.voltage_v * p.current_a + q.voltage_v * q.current_a) / 2 * (q.time_s - p.time_s)
                 for p, q in zip(inside, inside[1:])) / 3600
    assert got.energy_in_wh == pytest.approx(energy) and got.energy_out_wh == 0


def test_a_cursor_in_a_gap_has_no_reading_and_no_energy_crosses_the_gap():
    log = read_log(gapped_3010b_lov())
    before = log.samples[GAP_AFTER_LINE]
    after = log.samples[GAP_AFTER_LINE + 1]
    got = between(log, before.time_s - 100, (before.time_s + after.time_s) / 2)
    assert got.a is not None and got.b is None and got.delta("voltage") is None
    across = between(log, before.time_s - 20, after.time_s + 20)
    inside = [s for s in log.samples if before.time_s - 20 <= s.time_s <= after.time_s + 20]
    pairs = [(p, q) for p, q in zip(inside, inside[1:]) if q.time_s - p.time_s <= 10]     # 5 periods of 2 s
    energy = sum((p.voltage_v * p.current_a + q.voltage_v * q.current_a) / 2 * (q.time_s - p.time_s)
                 for p, q in pairs) / 3600
    assert len(pairs) == len(inside) - 2 and across.energy_in_wh == pytest.approx(energy)


def test_deviation_needs_two_cells():
    assert math.isnan(deviation_mv([[3.9]])[0])
    assert deviation_mv([[3.9, 3.95, float("nan")], [3.9, float("nan"), float("nan")]])[0] == pytest.approx(50)
    assert math.isnan(deviation_mv([[3.9, 3.95, float("nan")], [3.9, float("nan"), float("nan")]])[1])
