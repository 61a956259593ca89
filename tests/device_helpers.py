"""Helpers of the device-panel tests (a module of its own name: ``conftest`` collides between
test folders when the whole suite runs)."""
import threading
import time

from helpers import WAIT_MS, compiled  # noqa: F401 - WAIT_MS: the device tests take it from here


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


def click_flash(qtbot, panel) -> str:
    """Compile & Flash by its button, as a user does; it must succeed. Returns its message."""
    from PySide6.QtCore import Qt

    with qtbot.waitSignal(panel.flashFinished, timeout=WAIT_MS) as flashed:
        qtbot.mouseClick(panel.flash_button, Qt.MouseButton.LeftButton)
    ok, text = flashed.args
    assert ok, text
    return text


def flash_and_start(qtbot, panel) -> tuple:
    """Compile & Flash the editor's macro (it must succeed), then START a 2 A charge without a
    sensor; returns startFinished's (ok, message)."""
    with qtbot.waitSignal(panel.flashFinished, timeout=WAIT_MS) as flashed:
        panel.flash()
    assert flashed.args[0], flashed.args[1]
    panel.set_start_params(current_a=2.0, sensor=False)
    with qtbot.waitSignal(panel.startFinished, timeout=WAIT_MS) as started:
        panel.start()
    return tuple(started.args)
