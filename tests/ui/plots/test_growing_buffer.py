"""The live plot's table, without Qt: a growing buffer that keeps a whole session in fixed-size
chunks, safe for one writer thread and readers."""
import subprocess
import sys
import threading

import numpy as np
import pytest

from zuml_studio.ui.plots.growing_buffer import GrowingBuffer


def test_no_qt_is_imported():
    code = ("import sys; import zuml_studio.ui.plots.growing_buffer, zuml_studio.ui.plots.envelope, "
            "zuml_studio.device.session_log; "
            "print(any(m.startswith(('PySide6', 'pyqtgraph')) for m in sys.modules))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.strip() == "False"


def test_growing_buffer_appends_rows_in_chunks():
    buf = GrowingBuffer(("t", "v"), chunk_rows=4)
    for i in range(10):
        buf.append((i, 10 * i))
    assert len(buf) == 10 and buf.nbytes() == 3 * 4 * 8 * 2      # three chunks of four rows, two columns
    n, cols = buf.snapshot()
    assert n == 10
    assert cols["t"].tolist() == list(range(10)) and cols["v"].tolist() == [10 * i for i in range(10)]
    assert cols["t"][7:].tolist() == [7, 8, 9] and cols["t"][3:6].tolist() == [3, 4, 5]
    assert cols["t"][1:9:3].tolist() == [1, 4, 7] and cols["t"][::-4].tolist() == [9, 5, 1]
    assert cols["t"][-1] == 9 and cols["t"][4] == 4
    with pytest.raises(IndexError):
        cols["t"][10]
    assert buf.last() == {"t": 9.0, "v": 90.0}
    buf.append({"t": 10})                              # a missing column is NaN
    assert np.isnan(buf.column("v")[-1])
    with pytest.raises(ValueError):
        buf.append((1, 2, 3))


def test_growing_buffer_extend_and_dtypes():
    buf = GrowingBuffer(("t", "v"), chunk_rows=64, dtype={"v": np.float32})
    buf.extend({"t": np.arange(1000.0), "v": np.ones(1000)})
    assert len(buf) == 1000 and buf.nbytes() == 16 * 64 * (8 + 4)
    assert buf.column("t").tolist() == list(range(1000))
    assert buf.column("t").dtype == np.float64 and buf.column("v").dtype == np.float32
    buf.extend({"t": [], "v": []})
    assert len(buf) == 1000
    with pytest.raises(ValueError):
        buf.extend({"t": [1, 2], "v": [1]})
    with pytest.raises(ValueError):
        GrowingBuffer(("t", "t"))
    with pytest.raises(ValueError):
        GrowingBuffer(("t",), dtype={"x": np.float32})


def test_views_handed_out_stay_valid_while_the_buffer_grows():
    buf = GrowingBuffer(("t",), chunk_rows=8)
    buf.extend({"t": np.arange(5.0)})
    n, cols = buf.snapshot()
    view = cols["t"]
    buf.extend({"t": np.arange(5.0, 100.0)})           # fills the chunk the view is in, and more
    assert view.tolist() == list(range(5)) and len(view) == 5
    assert buf.column("t")[:8].tolist() == list(range(8))
    version = buf.version
    buf.append((100.0,))
    assert buf.version == version + 1


def test_searchsorted_across_chunks_is_numpys():
    t = np.repeat(np.arange(50.0), 3)                     # runs of equal values across chunk edges
    buf = GrowingBuffer(("t",), chunk_rows=7)
    buf.extend({"t": t})
    col = buf.column("t")
    for value in (-1.0, 0.0, 0.5, 2.0, 13.0, 33.0, 49.0, 49.5, 60.0):
        for side in ("left", "right"):
            assert col.searchsorted(value, side) == np.searchsorted(t, value, side), (value, side)
    assert np.searchsorted(col, 13.0) == np.searchsorted(t, 13.0)
    assert GrowingBuffer(("t",)).column("t").searchsorted(1.0) == 0


def test_a_million_rows():
    buf = GrowingBuffer(("t", "v", "i", "T", "Tc"), chunk_rows=1024)
    chunk = np.arange(10_000.0)
    for k in range(100):
        buf.extend({name: chunk + k * 10_000 for name in buf.names})
    assert len(buf) == 1_000_000
    t = buf.column("t")
    assert t[0] == 0 and t[-1] == 999_999 and (np.diff(np.asarray(t)) == 1).all()
    assert buf.nbytes() == 5 * 8 * 1024 * -(-1_000_000 // 1024)     # no more than one chunk beyond the rows


def test_one_writer_thread_and_a_reader():
    buf = GrowingBuffer(("t", "v"), chunk_rows=16)
    done = threading.Event()

    def write():
        for i in range(20_000):
            buf.append((i, 2 * i))
        done.set()

    writer = threading.Thread(target=write)
    writer.start()
    checks = 0
    while not done.is_set() or checks == 0:
        n, cols = buf.snapshot()
        if n:
            assert len(cols["t"]) == n == len(cols["v"])
            assert cols["t"][-1] == n - 1 and cols["v"][-1] == 2 * (n - 1)
        checks += 1
    writer.join()
    assert len(buf) == 20_000


def test_clear_keeps_views_already_handed_out():
    buf = GrowingBuffer(("t",))
    buf.extend({"t": [1.0, 2.0]})
    view = buf.column("t")
    buf.clear()
    assert len(buf) == 0 and buf.last() is None
    assert view.tolist() == [1.0, 2.0]

