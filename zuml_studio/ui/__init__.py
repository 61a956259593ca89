"""ZUML Studio's window (the only package that imports Qt)."""
from __future__ import annotations

from pathlib import Path


def create_main_window(path: str | None = None, config: Path | None = None):
    """The ready main window, with ``path`` open if given, else the file open when it last
    closed; needs a QApplication, not its event loop."""
    from .main_window import MainWindow

    window = MainWindow(config)
    if path:
        window.open_file(path, ask=False)
    else:
        window.reopen_last()
    return window
