"""The numpy table live telemetry goes into: filled by a reader thread, read by the GUI.

No Qt here (unit-tested on its own).

``GrowingBuffer``: named float columns that keep everything, growing by doubling. The live
plot keeps a whole session in one (a million rows cost 8 MB per float64 column).

It is safe for one writer thread and any number of readers: writes happen under a lock,
and a reader gets views of rows that are never written again (a grown buffer is a new
array; the views a reader holds keep the old one alive and unchanged). ``version`` counts
appends, so a reader can tell cheaply whether anything is new.
"""
from __future__ import annotations

import threading
from typing import Iterable, Mapping, Sequence

import numpy as np


class GrowingBuffer:
    """Rows of named float columns, appended at the end, never dropped.

    ``dtype``: one dtype for every column, or a mapping ``{name: dtype}`` (others float64)."""

    def __init__(self, columns: Sequence[str], capacity: int = 1024, dtype=np.float64):
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
        self._capacity = max(1, int(capacity))
        self._data = {name: np.empty(self._capacity, self.dtypes[name]) for name in self.names}
        self._n = 0
        self.version = 0
        self.lock = threading.Lock()

    def __len__(self) -> int:
        return self._n

    @property
    def capacity(self) -> int:
        return self._capacity

    def _reserve(self, extra: int) -> None:
        need = self._n + extra
        if need <= self._capacity:
            return
        cap = self._capacity
        while cap < need:
            cap *= 2
        for name in self.names:
            old = self._data[name]
            new = np.empty(cap, self.dtypes[name])
            new[:self._n] = old[:self._n]
            self._data[name] = new          # readers holding views of `old` keep them
        self._capacity = cap

    def append(self, row: Sequence[float] | Mapping[str, float]) -> None:
        """One row: values in column order, or a mapping by name (missing columns: NaN)."""
        with self.lock:
            self._reserve(1)
            i = self._n
            if isinstance(row, Mapping):
                for name in self.names:
                    self._data[name][i] = row.get(name, np.nan)
            else:
                if len(row) != len(self.names):
                    raise ValueError(f"a row has {len(self.names)} values, not {len(row)}")
                for name, value in zip(self.names, row):
                    self._data[name][i] = value
            self._n = i + 1
            self.version += 1

    def extend(self, columns: Mapping[str, Iterable[float]]) -> None:
        """Many rows at once: one array per column, all of the same length."""
        arrays = {name: np.asarray(columns[name], self.dtypes[name]) for name in self.names}
        sizes = {len(a) for a in arrays.values()}
        if len(sizes) != 1:
            raise ValueError("every column needs the same number of values")
        k = sizes.pop()
        if not k:
            return
        with self.lock:
            self._reserve(k)
            for name in self.names:
                self._data[name][self._n:self._n + k] = arrays[name]
            self._n += k
            self.version += 1

    def snapshot(self, start: int = 0) -> tuple[int, dict[str, np.ndarray]]:
        """(rows, {name: view of rows start..rows}); the views stay valid and unchanged."""
        with self.lock:
            n = self._n
            return n, {name: self._data[name][start:n] for name in self.names}

    def column(self, name: str) -> np.ndarray:
        with self.lock:
            return self._data[name][:self._n]

    def last(self) -> dict[str, float] | None:
        with self.lock:
            if not self._n:
                return None
            return {name: float(self._data[name][self._n - 1]) for name in self.names}

    def clear(self) -> None:
        """Forget every row (views handed out before keep their data)."""
        with self.lock:
            self._data = {name: np.empty(self._capacity, self.dtypes[name]) for name in self.names}
            self._n = 0
            self.version += 1

