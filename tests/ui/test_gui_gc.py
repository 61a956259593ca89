"""The cyclic garbage collector runs in the GUI thread only (ui/gui_gc.py): a Qt object destroyed
by a collection in a device thread deadlocks with the GUI thread."""
import gc
import threading

from zuml_studio.ui.gui_gc import collect_in_gui_thread


class _Cycle:
    freed_in: list = []

    def __init__(self):
        self.me = self

    def __del__(self):
        _Cycle.freed_in.append(threading.current_thread().name)


def test_garbage_made_in_another_thread_is_collected_in_the_gui_thread(qapp):
    collect_in_gui_thread()
    assert not gc.isenabled()

    def worker():
        _Cycle()
        junk = [[i] for i in range(200_000)]      # far past every automatic threshold
        del junk
    thread = threading.Thread(target=worker, name="device-reader")
    thread.start()
    thread.join()
    assert _Cycle.freed_in == []                   # nothing collected in the worker
    gc.collect()
    assert _Cycle.freed_in == [threading.main_thread().name]
