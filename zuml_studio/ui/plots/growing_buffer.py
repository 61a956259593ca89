"""The numpy table live telemetry goes into: filled by a reader thread, read by the GUI.

No Qt here (unit-tested on its own).

``GrowingBuffer``: named columns that keep everything, in fixed-size chunks. A day of 50 Hz
telemetry is 4.3 million rows: growing one array by doubling would hold up to twice that,
and copy it all (old and new side by side) at every doubling; chunks never move, so the
table costs its rows and at most one partly filled chunk.

It is safe for one writer thread and any number of readers: writes happen under a lock,
and a reader gets ``Column`` views of rows that are never written again (a chunk is never
reallocated; ``clear`` starts new ones). ``version`` counts appends, so a reader can tell
cheaply whether anything is new.
"""
from __future__ import annotations

import threading
from typing import Iterable, Mapping, Sequence

import numpy as np

CHUNK_ROWS = 65_536


class Column:
    """The first ``n`` rows of one column, read-only. Indexing gives a value, slicing a numpy
    array (a view inside one chunk, a copy across chunks), ``searchsorted`` bisects a sorted
    column, and numpy functions see the whole column as one array (a copy: avoid on big ones)."""

    def __init__(self, chunks: Sequence[np.ndarray], n: int, chunk_rows: int, dtype: np.dtype):
        self._chunks = list(chunks)
        self._n = n
        self._rows = chunk_rows
        self.dtype = dtype

    def __len__(self) -> int:
        return self._n

    def __getitem__(self, key):
        if isinstance(key, slice):
            start, stop, step = key.indices(self._n)
            if step == 1:
                return self._range(start, stop)
            if step > 0:
                return self._range(start, max(start, stop))[::step]
            return np.asarray(self)[key]
        i = int(key)
        if i < 0:
            i += self._n
        if not 0 <= i < self._n:
            raise IndexError("row out of range")
        return self._chunks[i // self._rows][i % self._rows]

    def _range(self, a: int, b: int) -> np.ndarray:
        if a >= b:
            return np.empty(0, self.dtype)
        rows = self._rows
        first, last = a // rows, (b - 1) // rows
        if first == last:
            return self._chunks[first][a - first * rows:b - first * rows]
        parts = [self._chunks[first][a - first * rows:]]
        parts += self._chunks[first + 1:last]
        parts.append(self._chunks[last][:b - last * rows])
        return np.concatenate(parts)

    def searchsorted(self, value, side: str = "left", sorter=None) -> int:
        """Where ``value`` goes in a sorted column (numpy's rule), chunk by chunk."""
        if sorter is not None:
            raise ValueError("a chunked column is bisected as it is sorted")
        n, rows = self._n, self._rows
        if not n:
            return 0
        count = -(-n // rows)
        firsts = np.array([self._chunks[k][0] for k in range(count)])
        k = max(0, int(np.searchsorted(firsts, value, side)) - 1)
        return k * rows + int(np.searchsorted(self._chunks[k][:min(rows, n - k * rows)], value, side))

    def __array__(self, dtype=None, copy=None) -> np.ndarray:
        whole = self._range(0, self._n)
        return whole if dtype is None else whole.astype(dtype)

    def tolist(self) -> list:
        return self._range(0, self._n).tolist()


class GrowingBuffer:
    """Rows of named columns, appended at the end, never dropped.

    ``dtype``: one dtype for every column, or a mapping ``{name: dtype}`` (others float64).
    ``chunk_rows``: rows per chunk (the memory taken at a time)."""

    def __init__(self, columns: Sequence[str], chunk_rows: int = CHUNK_ROWS, dtype=np.float64):
        if not columns:
            raise ValueError("a buffer needs at least one column")
        if len(set(columns)) != len(columns):
            raise ValueError("column names must differ")
        self.names: tuple[str, ...] = tuple(columns)
        if isinstance(dtype, Mapping):
            unknown = set(dtype) - set(self.names)
            if unknown:
                raise ValueError(f"no such column: {', '.join(sorted(unknown))}")
            self.dtypes = {name: np.dtype(dtype.get(name, np.float64)) for name in self.names}
        else:
            self.dtypes = {name: np.dtype(dtype) for name in self.names}
        self.chunk_rows = max(1, int(chunk_rows))
        self._chunks: dict[str, list[np.ndarray]] = {name: [] for name in self.names}
        self._n = 0
        self.version = 0
        self.lock = threading.Lock()

    def __len__(self) -> int:
        return self._n

    def nbytes(self) -> int:
        """Bytes the chunks take."""
        return sum(chunk.nbytes for chunks in self._chunks.values() for chunk in chunks)

    def _room(self) -> tuple[int, int]:
        """(chunk index, row in it) of the next row, a new chunk made if needed."""
        k, i = divmod(self._n, self.chunk_rows)
        if k == len(self._chunks[self.names[0]]):
            for name in self.names:
                self._chunks[name].append(np.empty(self.chunk_rows, self.dtypes[name]))
        return k, i

    def append(self, row: Sequence[float] | Mapping[str, float]) -> None:
        """One row: values in column order, or a mapping by name (missing columns: NaN)."""
        if isinstance(row, Mapping):
            values = [row.get(name, np.nan) for name in self.names]
        else:
            if len(row) != len(self.names):
                raise ValueError(f"a row has {len(self.names)} values, not {len(row)}")
            values = list(row)
        with self.lock:
            k, i = self._room()
            for name, value in zip(self.names, values):
                self._chunks[name][k][i] = value
            self._n += 1
            self.version += 1

    def extend(self, columns: Mapping[str, Iterable[float]]) -> None:
        """Many rows at once: one array per column, all of the same length."""
        arrays = {name: np.asarray(columns[name], self.dtypes[name]) for name in self.names}
        sizes = {len(a) for a in arrays.values()}
        if len(sizes) != 1:
            raise ValueError("every column needs the same number of values")
        count = sizes.pop()
        if not count:
            return
        with self.lock:
            done = 0
            while done < count:
                k, i = self._room()
                take = min(count - done, self.chunk_rows - i)
                for name in self.names:
                    self._chunks[name][k][i:i + take] = arrays[name][done:done + take]
                done += take
                self._n += take
            self.version += 1

    def _column(self, name: str) -> Column:
        return Column(self._chunks[name], self._n, self.chunk_rows, self.dtypes[name])

    def snapshot(self) -> tuple[int, dict[str, Column]]:
        """(rows, {name: Column of those rows}); the columns stay valid and unchanged."""
        with self.lock:
            return self._n, {name: self._column(name) for name in self.names}

    def column(self, name: str) -> Column:
        with self.lock:
            return self._column(name)

    def last(self) -> dict[str, float] | None:
        with self.lock:
            if not self._n:
                return None
            k, i = divmod(self._n - 1, self.chunk_rows)
            return {name: float(self._chunks[name][k][i]) for name in self.names}

    def clear(self) -> None:
        """Forget every row (columns handed out before keep their data)."""
        with self.lock:
            self._chunks = {name: [] for name in self.names}
            self._n = 0
            self.version += 1
