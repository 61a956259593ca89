"""Python's cycle collector runs in whichever thread allocates when a threshold is crossed. When
that is a worker (a simulation, a log being read, a fit) and the garbage holds Qt widgets, Qt
destroys widgets off the GUI thread: seen here as a deadlock (a QMenu's destructor waiting for the
GIL the GUI thread held while it destroyed another widget) and as a crash in the collector. So the
automatic collector is off while the window runs, and the GUI thread collects instead, each
generation when its threshold says so (pyqtgraph's collector, written for exactly this).

The same workers hold the GIL the GUI thread needs: a thread running Python code keeps it for up to
the switch interval (5 ms by default) after the GUI thread asks. Preparing a long run's plot on the
simulation worker (``ui/sim/worker.py``, 20-25 ms of Python and numpy) then lengthened the event
loop's gaps by up to that much each time; at 1 ms the GUI thread waits at most about 1 ms a turn.

A full collection walks every object the collector tracks, the modules and the window's widgets
included: 5-7 ms of the GUI thread in one go, the longest slice while a long run is re-simulated
and drawn (``benchmarks/bench_sim_stalls.py``). What is alive when the event loop first turns lives
as long as the application: it is moved out of the collector's sight then (``gc.freeze``), and a
full collection walks only what came after (under 1 ms)."""
from __future__ import annotations

import gc
import sys

from pyqtgraph.util.garbage_collector import GarbageCollector

INTERVAL_S = 0.5
GIL_SWITCH_S = 0.001


class _GuiThreadCollector(GarbageCollector):
    """pyqtgraph's collector that, at its first turn, freezes what the application started with."""

    def __init__(self, interval: float):
        self._frozen = False
        super().__init__(interval=interval)

    def check(self) -> None:
        if not self._frozen:
            gc.freeze()
            self._frozen = True
        super().check()


def collect_on_gui_thread() -> GarbageCollector:
    """Switch the automatic collector off and collect from the GUI thread's event loop, and let a
    worker hand the GIL back within 1 ms. Call on the GUI thread once a QApplication exists; keep the
    returned object alive."""
    sys.setswitchinterval(GIL_SWITCH_S)
    return _GuiThreadCollector(INTERVAL_S)
