"""Python's cyclic garbage collector, run in the GUI thread only.

A Qt object that Python owns is destroyed when the collector frees it. A collection can start in any
thread that allocates: the serial reader, the device worker. Destroyed there, Qt locks the object's
mutexes in that thread and calls back into Python for the GIL, while the GUI thread holds the GIL and
waits for one of those mutexes: both wait forever (it hung the device panel's tests). So automatic
collection is off and a timer in the GUI thread collects (pyqtgraph's ``GarbageCollector``, made for
this)."""
from __future__ import annotations

_collector = None


def collect_in_gui_thread(interval_s: float = 1.0) -> None:
    """Turn automatic collection off and collect from a GUI-thread timer instead (once per process;
    call it from the GUI thread after the QApplication exists)."""
    global _collector
    if _collector is None:
        from pyqtgraph.util.garbage_collector import GarbageCollector
        _collector = GarbageCollector(interval=interval_s)
