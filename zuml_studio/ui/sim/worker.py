"""Simulations off the GUI thread and out of its process: a QObject worker moved to its own QThread
starts the run in a child process (``sim_process.py``), relays the simulated time it reports
between chunks and passes a cancel on; the child holds its own GIL, so a long run never makes the
GUI thread wait for it. Every signal carries the job's id, so a panel can ignore what an outdated
job still reports. The run is handed over ready to draw (``plot_data.prepare_plot``, done on the
worker's thread): the GUI thread gets no sample to convert. A child that dies (killed, out of
memory) is an error message, never a hang: its end of the pipe closes.

Jobs keep themselves alive (module registry) until their thread has finished, and
any still running when Python exits are abandoned and waited for: a QThread must
never be destroyed while it runs."""
from __future__ import annotations

import atexit
import itertools
import os
import pickle
import threading

from PySide6.QtCore import QObject, Qt, QThread, Signal, Slot

from ...i18n import _, current_language
from . import sim_process
from .sim_process import SimRequest
from ..plots.plot_data import prepare_plot

CHUNK_TICKS = 20_000          # about 0.1–0.2 s of work: a cancel is seen that quickly
POLL_S = 0.02                 # how often the worker looks for a cancel while the child computes


class SimWorker(QObject):
    progress = Signal(int, float)        # job id, simulated seconds so far
    done = Signal(int, object)           # job id, PlotData of the SimResult (the macro ended)
    cancelled = Signal(int, object)      # job id, PlotData of a run stopped early (or None: cancelled before start)
    failed = Signal(int, str)            # job id, message for the user
    ended = Signal(int)                  # job id; always last

    def __init__(self, job_id: int, request: SimRequest, chunk: int = CHUNK_TICKS):
        super().__init__()
        self.job_id = job_id
        self.request = request
        self.chunk = chunk
        self.pid: int | None = None      # the child's, once started
        self._cancel = threading.Event()
        self._abandon = threading.Event()

    def cancel(self) -> None:
        """Thread-safe: the child stops before its next chunk and the run so far is shown."""
        self._cancel.set()

    def abandon(self) -> None:
        """Thread-safe: nobody wants the run any more; the child is killed at once."""
        self._abandon.set()
        self._cancel.set()

    @property
    def is_cancelled(self) -> bool:
        return self._cancel.is_set()

    @Slot()
    def run(self) -> None:
        jid = self.job_id
        try:
            self._run()
        except Exception as exc:            # a bug: say so in the panel, never take the IDE down
            self.failed.emit(jid, _("internal error in the simulator: {error}").format(
                error=f"{type(exc).__name__}: {exc}"))
        finally:
            self.ended.emit(jid)

    def _run(self) -> None:
        jid, req = self.job_id, self.request
        if self.is_cancelled:
            self.cancelled.emit(jid, None)
            return
        ctx = sim_process.context()
        conn, child_end = ctx.Pipe()
        child = ctx.Process(target=sim_process.run_child, name=f"zuml-simulation-{jid}", daemon=True,
                            args=(child_end, req, self.chunk, current_language(), dict(os.environ)))
        child.start()
        child_end.close()
        self.pid = child.pid
        try:
            self._relay(conn, child)
        finally:
            conn.close()
            if child.is_alive():
                child.kill()
            child.join()

    def _relay(self, conn, child) -> None:
        jid, asked = self.job_id, False
        while True:
            if self._abandon.is_set():
                return
            if self.is_cancelled and not asked:
                asked = True
                try:
                    conn.send_bytes(sim_process.CANCEL)
                except OSError:             # the child has just ended: its last message is in the pipe
                    pass
            if not conn.poll(POLL_S):
                continue
            try:
                kind, value = pickle.loads(conn.recv_bytes())
            except (EOFError, OSError):
                child.join(1.0)
                self.failed.emit(jid, _("the simulation process ended unexpectedly (exit code {code})").format(
                    code=child.exitcode))
                return
            if kind == sim_process.PROGRESS:
                self.progress.emit(jid, value)
                continue
            if kind == sim_process.FAILED:
                self.failed.emit(jid, value)
            elif not self._abandon.is_set():
                (self.done if kind == sim_process.DONE else self.cancelled).emit(jid, prepare_plot(value))
            return


class SimJob(QObject):
    """One run: its thread and worker. Start it once; cancel any time; wait if you must."""

    _ids = itertools.count(1)
    _running: dict[int, "SimJob"] = {}

    def __init__(self, request: SimRequest, chunk: int = CHUNK_TICKS):
        super().__init__()
        self.id = next(self._ids)
        self.thread = QThread()
        self.thread.setObjectName(f"simulation-{self.id}")
        self.worker = SimWorker(self.id, request, chunk)
        self.worker.moveToThread(self.thread)
        self.thread.started.connect(self.worker.run)
        # quit() is thread-safe: end the thread's event loop as soon as the worker is through.
        self.worker.ended.connect(self.thread.quit, Qt.ConnectionType.DirectConnection)
        self.thread.finished.connect(self._thread_finished)

    def start(self) -> None:
        SimJob._running[self.id] = self
        self.thread.start()

    def cancel(self) -> None:
        self.worker.cancel()

    def abandon(self) -> None:
        self.worker.abandon()

    def is_running(self) -> bool:
        return self.id in SimJob._running

    def wait(self, msecs: int) -> bool:
        """Block until the thread is finished (does not deliver its queued signals)."""
        return self.thread.wait(msecs)

    @Slot()
    def _thread_finished(self) -> None:
        self.thread.wait(5_000)        # finished is emitted just before the thread really ends
        SimJob._running.pop(self.id, None)

    @classmethod
    def running(cls) -> list["SimJob"]:
        return list(cls._running.values())


def warm_up() -> None:
    """Have the simulation processes' fork server started on a thread of its own (the first run
    then starts in milliseconds, not half a second)."""
    threading.Thread(target=sim_process.warm_up, name="simulation-warm-up", daemon=True).start()


@atexit.register
def _stop_all_jobs() -> None:
    for job in SimJob.running():
        job.abandon()
    for job in SimJob.running():
        job.thread.wait(10_000)
