"""The sample log's compact storage: numpy chunks give back what was appended (to float32
precision), sections once per phase, the staging chunk included."""
import io

import numpy as np
import pytest

from simhelp import run
from zuml_studio.domain import samples
from zuml_studio.domain.samples import COLUMNS, SampleLog


def _rows(n: int, tick: float = 1.0, per_phase: int = 7):
    rng = np.random.default_rng(3)
    for k in range(n):
        phase = 1 + k // per_phase
        yield ((k + 1) * tick, phase % 2, phase, 4.0 + rng.random(), rng.normal(), 25 + rng.random(),
               30 + rng.random(), k * 0.37, k * 0.11)


def _filled(n: int, **kw) -> tuple[SampleLog, list[tuple]]:
    log, rows = SampleLog(), list(_rows(n, **kw))
    for row in rows:
        log.append(*row)
        log.seal_if_full()
    return log, rows


def _assert_equal(log: SampleLog, rows: list[tuple]) -> None:
    got = log.arrays()
    for k, name in enumerate(COLUMNS):
        want = np.array([r[k] for r in rows], dtype=float)
        if name in ("section", "phase"):
            assert np.array_equal(got[name], want), name
        else:
            assert np.allclose(got[name], want, rtol=1e-6, atol=1e-4), name


def test_columns_across_chunks_and_the_staging_chunk_equal_what_was_appended(monkeypatch):
    monkeypatch.setattr(samples, "CHUNK", 64)
    log, rows = _filled(64 * 3 + 17, tick=0.1)
    assert len(log) == len(rows) and len(log._chunks) == 3
    _assert_equal(log, rows)
    assert log.arrays(100, 150)["time_s"][0] == pytest.approx(rows[100][0])
    assert len(log.arrays(100, 150)["time_s"]) == 50
    assert log.last() == pytest.approx(rows[-1])
    log.seal()
    assert log.last() == pytest.approx(rows[-1]) and len(log._chunks) == 4
    _assert_equal(log, rows)


def test_a_sealed_log_takes_30_bytes_a_tick():
    log, _ = _filled(samples.CHUNK * 2)
    assert log.nbytes() == 30 * len(log)


def test_the_simulators_log_equals_the_values_the_interpreter_appended(monkeypatch):
    seen = []
    real_init = SampleLog.__init__

    def recording_init(self, *args):
        real_init(self, *args)
        append = self.append

        def both(*row):
            seen.append(row)
            append(*row)

        self.append = both

    monkeypatch.setattr(SampleLog, "__init__", recording_init)
    monkeypatch.setattr(samples, "CHUNK", 1000)
    r = run("NiMh", "train", capacity=2000, current=2.0, series=4, engine="python")   # the interpreter's appends
    assert len(seen) == len(r.log) > 5000
    _assert_equal(r.log, seen)


def test_a_phase_in_two_sections_is_refused():
    log = SampleLog()
    log.append(1.0, 0, 1, 4.0, -1.0, 25.0, 30.0, 0.0, 0.1)
    log.append(2.0, 1, 1, 4.0, 1.0, 25.0, 30.0, 0.1, 0.1)
    with pytest.raises(ValueError, match="one section"):
        log.seal()


def test_keep_last_forgets_all_but_the_newest(monkeypatch):
    monkeypatch.setattr(samples, "CHUNK", 16)
    log, rows = _filled(40)
    log.keep_last()
    assert len(log) == 1 and log.last() == pytest.approx(rows[-1])


def test_csv_has_a_row_per_sample_in_the_old_format(monkeypatch):
    monkeypatch.setattr(samples, "CHUNK", 16)
    log, rows = _filled(40)
    out = io.StringIO()
    log.write_csv(out)
    lines = out.getvalue().splitlines()
    assert lines[0] == ",".join(COLUMNS) and len(lines) == 41
    t, s, p, v, i, tc, hs, qi, qo = rows[20]
    assert lines[21] == (f"{t:.1f},{samples.SECTION_NAMES[s]},{p},{v:.4f},{i:.4f},{tc:.2f},{hs:.2f},"
                         f"{qi:.1f},{qo:.1f}")


def test_unequal_cells_are_stored_with_their_balance_mask_across_chunks(monkeypatch):
    monkeypatch.setattr(samples, "CHUNK", 64)
    log = SampleLog(3, per_cell=True)
    assert log.columns == COLUMNS + ("cell1_v", "cell2_v", "cell3_v", "balance_mask")
    rows = list(_rows(64 * 2 + 5))
    for k, row in enumerate(rows):
        log.append(*row)
        log.append_cells((4.0 + k * 1e-3, 4.1, 4.2), k % 8)
        log.seal_if_full()
    got = log.arrays()
    assert np.allclose(got["cell1_v"], [4.0 + k * 1e-3 for k in range(len(rows))], atol=1e-6)
    assert got["balance_mask"].dtype == np.int64 and got["balance_mask"].tolist() == [k % 8 for k in range(len(rows))]
    out = io.StringIO()
    log.write_csv(out)
    lines = out.getvalue().splitlines()
    assert lines[0].endswith("mah_out,cell1_v,cell2_v,cell3_v,balance_mask")
    assert lines[2].endswith(",4.0010,4.1000,4.2000,1")
    log.keep_last()
    assert len(log) == 1 and log.arrays()["balance_mask"].tolist() == [(len(rows) - 1) % 8]


def test_identical_cells_read_as_the_pack_voltage_shared_and_nothing_bleeding():
    log = SampleLog(4)
    log.append(1.0, 1, 1, 16.8, 1.0, 25.0, 30.0, 0.3, 0.0)
    got = log.arrays()
    assert got["cell4_v"].tolist() == pytest.approx([4.2]) and got["balance_mask"].tolist() == [0]
    assert SampleLog(1).columns == COLUMNS
