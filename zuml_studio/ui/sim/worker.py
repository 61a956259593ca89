"""Simulations off the GUI thread: a QObject worker moved to its own QThread runs
``Interpreter.advance`` chunk by chunk, reports the simulated time between chunks
and checks a cancel flag there. Every signal carries the job's id, so a panel can
ignore what an outdated job still reports. The run is handed over ready to draw
(``plot_data.prepare_plot``): the GUI thread gets no sample to convert.

Jobs keep themselves alive (module registry) until their thread has finished, and
any still running when Python exits are cancelled and waited for: a QThread must
never be destroyed while it runs."""
from __future__ import annotations

import atexit
import itertools
import logging
import threading
from dataclasses import dataclass

from PySide6.QtCore import QObject, Qt, QThread, Signal, Slot

from ...data import DataFileError
from ...i18n import _
from ...sim.batteries import BatteryFileError
from ...sim.interpreter import StartError, StartParams
from ...sim.simulate import BatterySetup, prepare
from .plot_data import prepare_plot

log = logging.getLogger(__name__)

CHUNK_TICKS = 20_000          # about 0.1–0.2 s of work: a cancel is seen that quickly


@dataclass(frozen=True)
class SimRequest:
    record: bytes
    params: StartParams
    setup: BatterySetup
    macro_name: str = ""


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
        self._cancel = threading.Event()

    def cancel(self) -> None:
        """Thread-safe: the loop stops before its next chunk."""
        self._cancel.set()

    @property
    def is_cancelled(self) -> bool:
        return self._cancel.is_set()

    @Slot()
    def run(self) -> None:
        jid = self.job_id
        try:
            self._run()
        except StartError as exc:
            self.failed.emit(jid, str(exc))
        except DataFileError as exc:        # a broken installation: the message names the file
            self.failed.emit(jid, str(exc))
        except KeyError as exc:             # a battery model that does not exist
            self.failed.emit(jid, str(exc.args[0]) if exc.args else _("unknown battery model"))
        except BatteryFileError as exc:     # a saved fitted battery deleted or damaged since it was listed
            self.failed.emit(jid, str(exc))
        except Exception as exc:            # a bug: say so in the panel, never take the IDE down
            log.exception("simulation failed")
            self.failed.emit(jid, _("internal error in the simulator: {error}").format(error=f"{type(exc).__name__}: {exc}"))
        finally:
            self.ended.emit(jid)

    def _run(self) -> None:
        jid, req = self.job_id, self.request
        if self.is_cancelled:
            self.cancelled.emit(jid, None)
            return
        result = prepare(req.record, req.params, req.setup)
        it = result.interpreter
        self.progress.emit(jid, 0.0)
        while not it.finished:
            if self.is_cancelled:
                it.stop("cancelled")
                self.cancelled.emit(jid, prepare_plot(result))
                return
            it.advance(self.chunk)
            self.progress.emit(jid, it.time_s)
        self.done.emit(jid, prepare_plot(result))


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


@atexit.register
def _stop_all_jobs() -> None:
    for job in SimJob.running():
        job.cancel()
    for job in SimJob.running():
        job.thread.wait(10_000)
