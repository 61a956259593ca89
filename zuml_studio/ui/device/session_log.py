"""The session CSV: every telemetry frame and event of a connection, written as it comes.

No Qt here. The reader thread hands rows over (``add_telemetry``/``add_event`` only put
them on a queue: they never wait for the disk); a writer thread writes them and flushes
at least every ``flush_s`` (0.5 s), so a crash loses at most that much. ``close`` writes
what is left and joins the thread.

Columns are the simulator's CSV (``sim.samples.COLUMNS``) plus ``event``: a telemetry row
leaves it empty, an event row fills it ("phase_end charge 1: IF(DELTA_PEAK>0.01S) STOP_FAZE")
and leaves the measurements empty. ``time_s`` is the macro's clock, ``phase`` the phase's
run number (1-based; 0: none), as in the simulator's CSV.
"""
from __future__ import annotations

import csv
import datetime as _dt
import os
import queue
import threading
import time
from pathlib import Path

from ...sim.samples import COLUMNS as SIM_COLUMNS

COLUMNS = tuple(SIM_COLUMNS) + ("event",)
FLUSH_S = 0.5
_STOP = object()


def session_path(folder: str | Path, when: _dt.datetime | None = None) -> Path:
    """``folder/session-YYYYmmdd-HHMMSS.csv``; ``-2``, ``-3``… if that name is taken."""
    folder = Path(folder)
    stamp = (when or _dt.datetime.now()).strftime("%Y%m%d-%H%M%S")
    path = folder / f"session-{stamp}.csv"
    k = 2
    while path.exists():
        path = folder / f"session-{stamp}-{k}.csv"
        k += 1
    return path


def _num(value, fmt: str) -> str:
    return "" if value is None else format(value, fmt)


def telemetry_row(t) -> tuple:
    """A ``device.messages.Telemetry`` (or anything with its fields) as a CSV row."""
    return (f"{t.time_s:.1f}", t.section, t.run, f"{t.voltage_v:.3f}", f"{t.current_a:.3f}",
            _num(t.temp_c, ".2f"), _num(t.heatsink_c, ".2f"), f"{t.mah_in:.1f}", f"{t.mah_out:.1f}", "")


def event_text(e) -> str:
    where = ""
    if e.kind.startswith("phase"):
        where = f" {e.section} {e.index}"
    elif e.section:
        where = f" {e.section}"
    return f"{e.kind}{where}" + (f": {e.detail}" if e.detail else "")


def event_row(e) -> tuple:
    return (f"{e.time_s:.1f}", e.section, "", "", "", "", "", "", "", event_text(e))


class SessionLog:
    """A CSV file written by its own thread (``threaded=False``: written by the caller,
    flushed by ``flush_if_due``, for tests and scripts)."""

    def __init__(self, path: str | Path, *, flush_s: float = FLUSH_S, threaded: bool = True):
        self.path = Path(path)
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self.flush_s = float(flush_s)
        self._fh = open(self.path, "w", encoding="utf-8", newline="")
        self._writer = csv.writer(self._fh, lineterminator="\n")
        self._writer.writerow(COLUMNS)
        self._fh.flush()
        self._lock = threading.Lock()
        self._flushed_at = time.monotonic()
        self._dirty = False
        self.rows = 0                   # rows written (header not counted)
        self.error: str | None = None   # the first write failure (disk full, …), for the GUI
        self.closed = False
        self._queue: queue.SimpleQueue | None = None
        self._thread: threading.Thread | None = None
        if threaded:
            self._queue = queue.SimpleQueue()
            self._thread = threading.Thread(target=self._run, name=f"session-log {self.path.name}", daemon=True)
            self._thread.start()

    # -- any thread ------------------------------------------------------------------------
    def add_telemetry(self, t) -> None:
        self._put(telemetry_row(t))

    def add_event(self, e) -> None:
        self._put(event_row(e))

    def add_row(self, row: tuple) -> None:
        if len(row) != len(COLUMNS):
            raise ValueError(f"a session row has {len(COLUMNS)} values")
        self._put(tuple(row))

    def _put(self, row: tuple) -> None:
        if self.closed:
            return
        if self._queue is not None:
            self._queue.put(row)
        else:
            self._write([row])

    # -- writing -------------------------------------------------------------------------------
    def _write(self, rows: list) -> None:
        with self._lock:
            if self._fh.closed or self.error:
                return
            try:
                self._writer.writerows(rows)
                self.rows += len(rows)
                self._dirty = True
            except (OSError, ValueError) as exc:
                self.error = f"cannot write {self.path}: {getattr(exc, 'strerror', None) or exc}"

    def flush(self) -> None:
        with self._lock:
            if self._fh.closed or self.error:
                return
            try:
                self._fh.flush()
            except OSError as exc:
                self.error = f"cannot write {self.path}: {exc.strerror or exc}"
            self._dirty = False
            self._flushed_at = time.monotonic()

    def flush_if_due(self) -> None:
        if self._dirty and time.monotonic() - self._flushed_at >= self.flush_s:
            self.flush()

    def _run(self) -> None:
        q = self._queue
        while True:
            timeout = max(0.01, self.flush_s - (time.monotonic() - self._flushed_at)) if self._dirty else self.flush_s
            try:
                item = q.get(timeout=timeout)
            except queue.Empty:
                self.flush_if_due()
                continue
            batch = []
            stop = False
            while True:
                if item is _STOP:
                    stop = True
                    break
                batch.append(item)
                if len(batch) >= 2000:
                    break
                try:
                    item = q.get_nowait()
                except queue.Empty:
                    break
            if batch:
                self._write(batch)
            self.flush_if_due()
            if stop:
                return

    def close(self) -> None:
        """Write what is queued, flush, close the file, join the thread. Idempotent."""
        if self.closed:
            return
        self.closed = True
        if self._thread is not None:
            self._queue.put(_STOP)
            self._thread.join(timeout=5)
            self._thread = None
        self.flush()
        with self._lock:
            try:
                self._fh.close()
            except OSError:
                pass

    def __enter__(self) -> "SessionLog":
        return self

    def __exit__(self, *exc) -> None:
        self.close()


def display_path(path: Path) -> str:
    """The path as the panel shows it: ~ for the home folder."""
    text = str(path)
    home = os.path.expanduser("~")
    if home and home != "/" and text.startswith(home + os.sep):
        return "~" + text[len(home):]
    return text
