"""Helpers of the device-panel tests (a module of its own name: ``conftest`` collides between
test folders when the whole suite runs)."""
import threading
import time

from helpers import MACROS
from zuml_studio.lang.compiler import compile_source

WAIT_MS = 30_000


def compiled(name: str) -> bytes:
    result = compile_source((MACROS / f"{name}.zuml").read_text())
    assert result.ok, result.diagnostics
    return result.record


def python_threads() -> set:
    """Live Python threads that are not the bookkeeping entries of Qt threads (_DummyThread)."""
    return {t for t in threading.enumerate() if not isinstance(t, threading._DummyThread) and t.is_alive()}


def wait_threads(baseline: set, seconds: float = 10.0) -> set:
    """Wait until no thread is alive beyond ``baseline``; return the extra ones still alive."""
    end = time.monotonic() + seconds
    while True:
        extra = python_threads() - baseline
        if not extra or time.monotonic() > end:
            return extra
        time.sleep(0.05)


class Editor:
    """What the main window hands the panel: the current valid record and its name, or None."""

    def __init__(self, name: str = "NiMh-dV"):
        self.set(name)

    def set(self, name: str | None) -> None:
        self.value = None if name is None else (compiled(name), name)

    def __call__(self):
        return self.value


def connect(qtbot, panel, target="virtual"):
    with qtbot.waitSignal(panel.connectedChanged, timeout=WAIT_MS) as blocker:
        assert panel.connect_to(target)
    assert blocker.args == [True], panel.message_text()
    # the slot list and the passport are read right after connecting
    qtbot.waitUntil(lambda: not panel.connection.busy, timeout=WAIT_MS)
