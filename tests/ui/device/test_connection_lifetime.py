"""A device connection dropped without shutdown() (a main window garbage-collected unclosed) ends its
worker thread instead of letting Qt abort the process ("QThread: Destroyed while thread
'device-worker' is still running"). Run in a child process: an abort would take pytest with it."""
import subprocess
import sys
import textwrap

DROP_A_CONNECTION = textwrap.dedent("""
    import gc, os
    os.environ["QT_QPA_PLATFORM"] = "offscreen"
    from PySide6.QtWidgets import QApplication
    app = QApplication([])
    from zuml_studio.ui.device.connection import DeviceConnection
    connection = DeviceConnection()
    app.processEvents()
    del connection
    gc.collect()
    app.processEvents()
    print("collected")
    """)

LEAVE_A_WINDOW = textwrap.dedent("""
    import os, sys, tempfile
    from pathlib import Path
    os.environ["QT_QPA_PLATFORM"] = "offscreen"
    os.environ["ZUML_STUDIO_CONFIG_DIR"] = tempfile.mkdtemp()
    from PySide6.QtWidgets import QApplication
    app = QApplication([])
    from zuml_studio.ui import create_main_window
    window = create_main_window(None, Path(tempfile.mkdtemp()) / "config")
    window.show()
    window.device_panel          # built: its connection's worker thread runs
    app.processEvents()
    print("left open")
    """)


def _run(script: str) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, timeout=120)


def test_a_connection_collected_without_shutdown_ends_its_thread():
    proc = _run(DROP_A_CONNECTION)
    assert proc.returncode == 0 and "collected" in proc.stdout, proc.stderr


def test_a_window_left_open_at_exit_ends_its_threads():
    proc = _run(LEAVE_A_WINDOW)
    assert proc.returncode == 0 and "left open" in proc.stdout, proc.stderr
    assert "QThread: Destroyed" not in proc.stderr
