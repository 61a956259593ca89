"""Python's cycle collector runs in whichever thread allocates when a threshold is crossed. When
that is a worker (a simulation, a log being read, a fit) and the garbage holds Qt widgets, Qt
destroys widgets off the GUI thread: seen here as a deadlock (a QMenu's destructor waiting for the
GIL the GUI thread held while it destroyed another widget) and as a crash in the collector. So the
automatic collector is off while the window runs, and the GUI thread collects instead, each
generation when its threshold says so (pyqtgraph's collector, written for exactly this).

The same workers hold the GIL the GUI thread needs: a thread running Python code keeps it for up to
the switch interval (5 ms by default) after the GUI thread asks. Preparing a long run's plot on the
simulation worker (``ui/sim/worker.py``, 20-25 ms of Python and numpy) then lengthened the event
loop's gaps by up to that much each time; at 1 ms the GUI thread waits at most about 1 ms a turn."""
from __future__ import annotations

import sys

from pyqtgraph.util.garbage_collector import GarbageCollector

INTERVAL_S = 0.5
GIL_SWITCH_S = 0.001


def collect_on_gui_thread() -> GarbageCollector:
    """Switch the automatic collector off and collect from the GUI thread's event loop, and let a
    worker hand the GIL back within 1 ms. Call on the GUI thread once a QApplication exists; keep the
    returned object alive."""
    sys.setswitchinterval(GIL_SWITCH_S)
    return GarbageCollector(interval=INTERVAL_S)
