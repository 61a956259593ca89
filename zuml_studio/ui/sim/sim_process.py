"""A simulation in a process of its own, so that it never holds the GUI's GIL (issue 26: a thread
running the interpreter stalled the window 40-60 ms while a long run was re-simulated).

``run_child`` is the child's whole life: it runs ``Interpreter.advance`` (or the C engine, sim/engine.py,
when it can run the simulation) chunk by chunk, sends
the simulated time after each chunk, stops between chunks when the parent sends ``CANCEL``, and
sends the run back (the ``SimResult``: phases and the compact sample log) or a message for the
user. Every message is one pickled tuple ``(kind, value)``. The parent's side is ``worker.py``.

A finished run is read, never continued: the interpreter's stepping generator and the sample
log's append closure are left behind (``_FinishedRunPickler``), which is all of a run that does
not pickle. No Qt here (the child imports only the simulator)."""
from __future__ import annotations

import io
import logging
import multiprocessing
import os
import pickle
from dataclasses import dataclass
from multiprocessing.connection import Connection

from ... import i18n
from ...data import DataFileError
from ...i18n import _
from ...sim import engine as c_engine
from ...sim.batteries import BatteryFileError
from ...sim.interpreter import Interpreter, StartError, StartParams
from ...domain.samples import SampleLog
from ...sim.simulate import BatterySetup, prepare

log = logging.getLogger(__name__)

CANCEL = b"cancel"
PROGRESS, DONE, CANCELLED, FAILED = "progress", "done", "cancelled", "failed"


@dataclass(frozen=True)
class SimRequest:
    """What to simulate (defined here, not beside the worker: unpickling it must not import Qt)."""
    record: bytes
    params: StartParams
    setup: BatterySetup
    macro_name: str = ""


def context() -> multiprocessing.context.BaseContext:
    """Where the platform has it, a fork server that has the simulator imported (a run starts in a
    few milliseconds, not the ~0.5 s of a fresh interpreter importing numpy); spawn elsewhere.
    Each child runs the main script again as ``__mp_main__`` (multiprocessing's rule): the
    application's entry points import nothing heavy at their top level; a script that imports Qt
    there costs each run ~130 ms (and preloading it into the server makes every fork that slow)."""
    if "forkserver" in multiprocessing.get_all_start_methods():
        ctx = multiprocessing.get_context("forkserver")
        ctx.set_forkserver_preload([__name__])
        return ctx
    return multiprocessing.get_context("spawn")


def warm_up() -> None:
    """Start the fork server now (about half a second, once), not when the first run is asked for.
    Blocks: call it off the GUI thread."""
    ctx = context()
    if ctx.get_start_method() == "forkserver":
        from multiprocessing import forkserver
        forkserver.ensure_running()


def _without(obj, *names: str) -> dict:
    return {k: v for k, v in vars(obj).items() if k not in names}


def _rebuilt(cls: type, state: dict):
    obj = cls.__new__(cls)
    obj.__dict__.update(state)
    return obj


class _FinishedRunPickler(pickle.Pickler):
    dispatch_table = {
        Interpreter: lambda it: (_rebuilt, (Interpreter, _without(it, "_steps"))),
        SampleLog: lambda samples: (_rebuilt, (SampleLog, _without(samples, "append", "append_cells"))),
    }


def dumps(message: tuple) -> bytes:
    buf = io.BytesIO()
    _FinishedRunPickler(buf, protocol=pickle.HIGHEST_PROTOCOL).dump(message)
    return buf.getvalue()


def run_child(conn: Connection, request: SimRequest, chunk: int, language: str, environ: dict[str, str]) -> None:
    """The child process. ``environ`` is the parent's environment now (a fork server's children
    inherit the server's, from when it started), ``language`` its language (the messages are the user's)."""
    os.environ.clear()
    os.environ.update(environ)
    if i18n.current_language() != language:
        i18n.install(language)
    try:
        conn.send_bytes(dumps(_run(conn, request, chunk)))
    except (BrokenPipeError, EOFError):     # the parent has gone: nobody to tell
        pass
    finally:
        conn.close()


def _run(conn: Connection, request: SimRequest, chunk: int) -> tuple:
    try:
        result = prepare(request.record, request.params, request.setup)
        it = result.interpreter
        conn.send_bytes(dumps((PROGRESS, 0.0)))
        if c_engine.unavailable(it) is None:
            def chunk_done(time_s: float) -> str | None:
                conn.send_bytes(dumps((PROGRESS, time_s)))
                return "cancelled" if conn.poll() and conn.recv_bytes() == CANCEL else None

            c_engine.run(it, on_chunk=chunk_done)
            result.engine = "c"
            return (CANCELLED if it.end_reason == "cancelled" else DONE), result
        while not it.finished:
            if conn.poll() and conn.recv_bytes() == CANCEL:
                it.stop("cancelled")
                return CANCELLED, result
            it.advance(chunk)
            conn.send_bytes(dumps((PROGRESS, it.time_s)))
        return DONE, result
    except (StartError, DataFileError, BatteryFileError) as exc:     # the message names the cause (or the file)
        return FAILED, str(exc)
    except (BrokenPipeError, EOFError):
        raise
    except KeyError as exc:             # a battery model that does not exist
        return FAILED, str(exc.args[0]) if exc.args else _("unknown battery model")
    except Exception as exc:            # a bug: say so in the panel, never take the IDE down
        log.exception("simulation failed")
        return FAILED, _("internal error in the simulator: {error}").format(error=f"{type(exc).__name__}: {exc}")
