"""Python's cycle collector runs in whichever thread allocates when a threshold is crossed. When
that is a worker (a simulation, a log being read, a fit) and the garbage holds Qt widgets, Qt
destroys widgets off the GUI thread: seen here as a deadlock (a QMenu's destructor waiting for the
GIL the GUI thread held while it destroyed another widget) and as a crash in the collector. So the
automatic collector is off while the window runs, and the GUI thread collects instead, each
generation when its threshold says so (pyqtgraph's collector, written for exactly this)."""
from __future__ import annotations

from pyqtgraph.util.garbage_collector import GarbageCollector

INTERVAL_S = 0.5


def collect_on_gui_thread() -> GarbageCollector:
    """Switch the automatic collector off and collect from the GUI thread's event loop. Call on
    the GUI thread once a QApplication exists; keep the returned object alive."""
    return GarbageCollector(interval=INTERVAL_S)
