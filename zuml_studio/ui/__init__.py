"""ZUML Studio's window (the only package that imports Qt)."""
from __future__ import annotations

import sys
from pathlib import Path

# The GUI thread shares the GIL with the simulation worker and the device's reader thread: each
# call into Qt releases it, and taking it back from a busy thread waits up to this interval
# (Python's default is 5 ms, felt as a sluggish GUI while a long run is simulated).
GIL_SWITCH_S = 0.0005


def create_main_window(path: str | None = None, config: Path | None = None):
    """The ready main window, with ``path`` open if given, else the file open when it last
    closed; needs a QApplication, not its event loop."""
    from .window.main_window import MainWindow

    sys.setswitchinterval(GIL_SWITCH_S)
    window = MainWindow(config)
    if path:
        window.open_file(path, ask=False)
    else:
        window.reopen_last()
    return window
