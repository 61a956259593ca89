"""The session CSV: every telemetry frame and event of a connection, written as it comes.

No Qt here. The reader thread hands rows over (``add_telemetry``/``add_event`` only put
them on a queue: they never wait for the disk); a writer thread writes them and flushes
at least every ``flush_s`` (0.5 s), so a crash loses at most that much. ``close`` writes
what is left and joins the thread.

Columns are the simulator's CSV (``domain.samples.COLUMNS``) plus ``event``: a telemetry row
leaves it empty, an event row fills it ("phase_end charge 1: IF(DELTA_PEAK>0.01S) STOP_FAZE")
and leaves the measurements empty. ``time_s`` is the macro's clock, ``phase`` the phase's
run number (1-based; 0: none), as in the simulator's CSV. A charger that measures its cells
adds ``cell1_v … cellN_v`` after ``event`` (N from the first telemetry of the session when
``cells=None``; a sample with fewer cells leaves the rest empty, extra cells are dropped).
With ``idle_s`` (the device panel passes ``IDLE_LOG_S``, 10 s, for a ZUML charger) an idle
charger (a frame with ``running`` false) is written at most once every ``idle_s`` and on the
first idle frame after a run: a connected charger left idle for a day would otherwise fill
the file at the telemetry rate. Every running frame and every event is written; without
``idle_s`` (``zuml monitor``, monitor-only chargers: their frames are the recording) every
frame is. Lives outside ``ui`` because ``zuml monitor`` writes the same file.
"""
from __future__ import annotations

import csv
import datetime as _dt
import os
import queue
import threading
import time
from pathlib import Path

from ..domain.samples import COLUMNS as SIM_COLUMNS
from ..i18n import _

COLUMNS = tuple(SIM_COLUMNS) + ("event",)
FLUSH_S = 0.5
IDLE_LOG_S = 10.0
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


def cell_columns(cells: int) -> tuple[str, ...]:
    return tuple(f"cell{k}_v" for k in range(1, cells + 1))


def telemetry_row(t, cells: int = 0) -> tuple:
    """A ``protocol.messages.Telemetry`` (or anything with its fields) as a CSV row."""
    row = (f"{t.time_s:.1f}", t.section, t.run, f"{t.voltage_v:.3f}", f"{t.current_a:.3f}",
           _num(t.temp_c, ".2f"), _num(t.heatsink_c, ".2f"), f"{t.mah_in:.1f}", f"{t.mah_out:.1f}", "")
    if cells:
        measured = tuple(getattr(t, "cells_v", ()))[:cells]
        row += tuple(f"{v:.3f}" for v in measured) + ("",) * (cells - len(measured))
    return row


def event_text(e) -> str:
    where = ""
    if e.kind.startswith("phase"):
        where = f" {e.section} {e.index}"
    elif e.section:
        where = f" {e.section}"
    return f"{e.kind}{where}" + (f": {e.detail}" if e.detail else "")


def event_row(e, cells: int = 0) -> tuple:
    return (f"{e.time_s:.1f}", e.section, "", "", "", "", "", "", "", event_text(e)) + ("",) * cells


class SessionLog:
    """A CSV file written by its own thread (``threaded=False``: written by the caller,
    flushed by ``flush_if_due``, for tests and scripts)."""

    def __init__(self, path: str | Path, *, flush_s: float = FLUSH_S, threaded: bool = True,
                 cells: int | None = 0, idle_s: float = 0.0, clock=time.monotonic):
        self.path = Path(path)
        self.idle_s = float(idle_s)
        self._clock = clock
        self._idle_at: float | None = None    # when the last idle frame was written
        self.path.parent.mkdir(parents=True, exist_ok=True)
        self.flush_s = float(flush_s)
        self._fh = open(self.path, "w", encoding="utf-8", newline="")
        self._writer = csv.writer(self._fh, lineterminator="\n")
        self.cells = cells
        if cells is not None:
            self._writer.writerow(COLUMNS + cell_columns(cells))
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
        if self.idle_s and not getattr(t, "running", True):
            now = self._clock()
            if self._idle_at is not None and now - self._idle_at < self.idle_s:
                return
            self._idle_at = now
        else:
            self._idle_at = None
        self._header(len(getattr(t, "cells_v", ())))
        self._put(telemetry_row(t, self.cells))

    def add_event(self, e) -> None:
        self._header(0)
        self._put(event_row(e, self.cells))

    def add_row(self, row: tuple) -> None:
        self._header(0)
        if len(row) != len(COLUMNS) + self.cells:
            raise ValueError(_("a session row has {n_columns} values").format(n_columns=len(COLUMNS) + self.cells))
        self._put(tuple(row))

    def _header(self, cells: int) -> None:
        """The header waits for the first row when the cell count was left open."""
        if self.cells is None:
            self.cells = cells
            self._put(COLUMNS + cell_columns(cells), header=True)

    def _put(self, row: tuple, header: bool = False) -> None:
        if self.closed:
            return
        if self._queue is not None:
            self._queue.put((row, header))
        else:
            self._write([(row, header)])

    # -- writing -------------------------------------------------------------------------------
    def _write(self, rows: list) -> None:
        with self._lock:
            if self._fh.closed or self.error:
                return
            try:
                self._writer.writerows(row for row, __ in rows)
                self.rows += sum(1 for __, header in rows if not header)
                self._dirty = True
            except (OSError, ValueError) as exc:
                self.error = _("cannot write {path}: {error}").format(path=self.path,
                                                                      error=getattr(exc, "strerror", None) or exc)

    def flush(self) -> None:
        with self._lock:
            if self._fh.closed or self.error:
                return
            try:
                self._fh.flush()
            except OSError as exc:
                self.error = _("cannot write {path}: {error}").format(path=self.path, error=exc.strerror or exc)
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
        self._header(0)                  # an empty session still gets its header
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
