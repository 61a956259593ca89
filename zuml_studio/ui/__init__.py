"""ZUML Studio's window: the only package that imports Qt.

Its packages depend one way, each only on those in the rows below its own (``LAYERS``; the test
tests/ui/test_ui_package_order.py holds every import to it), never on a package beside it:

- ``app`` (the entry point ``zuml-studio``) and this package's ``create_main_window``;
- ``window``: the main window and its parts (actions, docks, modes, documents, preferences);
- ``packs``: the Packs dock (it sets the simulator's battery, starts in the device's folder);
- ``editor``, ``visual``, ``logs``, ``sim``, ``device``: one feature each, none importing another;
- ``plots``: the plots and the phase table of a run, which several features show;
- ``base``: the foundations (colours, times, number boxes, background calls, settings, language).

Each package's docstring says what it owns and what it may import. Any ui package may import the
packages outside ``ui/``."""
from __future__ import annotations

import sys
from pathlib import Path

# The GUI thread shares the GIL with the simulation worker and the device's reader thread: each
# call into Qt releases it, and taking it back from a busy thread waits up to this interval
# (Python's default is 5 ms, felt as a sluggish GUI while a long run is simulated).
GIL_SWITCH_S = 0.0005

# The order of the packages above, bottom row first: a package imports only its own modules and
# those of the rows below its own.
LAYERS = (("base",), ("plots",), ("editor", "visual", "logs", "sim", "device"), ("packs",), ("window",), ("app",))


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
