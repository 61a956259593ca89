"""GUI figures for issue 4, offscreen: window start to first paint (target < 1.5 s), GUI-thread
time per keystroke in a 100-line macro (target < 5 ms; see also bench_editor_keystroke.py), and the
latency from the last keystroke to the error underline (debounce 250 ms + check; target < 300 ms).
Run: python benchmarks/bench_gui.py"""
from __future__ import annotations

import os
import statistics
import sys
import tempfile
import time

os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")
os.environ["ZUML_STUDIO_CONFIG_DIR"] = tempfile.mkdtemp(prefix="zuml-bench-")
T0 = time.perf_counter()

from PySide6.QtCore import QEvent, QObject, Qt  # noqa: E402
from PySide6.QtGui import QTextCursor  # noqa: E402
from PySide6.QtTest import QTest  # noqa: E402
from PySide6.QtWidgets import QApplication  # noqa: E402


class _FirstPaint(QObject):
    at = None

    def eventFilter(self, obj, event):
        if event.type() == QEvent.Type.Paint and self.at is None:
            self.at = time.perf_counter()
        return False


def _hundred_lines() -> str:
    # A commented, valid macro of 100 lines (its record stays under 255 bytes).
    phase = ["", "    // top-up stage: charge at the entered current", "    // until the -dV or the timer ends it",
             "    FAZE", "      CONSTANT_I=INPUT", "      IF(DELTA_PEAK>0.01S) STOP_FAZE", "      IF(tf>2h) STOP_FAZE",
             "    END_FAZE"]
    body = ["MACRO Bench", "  AKK_TYPE=NiMh", "  SERIES=4", "  CAPACITY=2000", "  CHARGE_SECTION"]
    while len(body) < 96:
        body += phase
    body = body[:96]
    return "\n".join(body + ["  END_SECTION", "  MUSIC(STOP)", "END_MACRO", ""])


def main() -> None:
    app = QApplication.instance() or QApplication(sys.argv[:1])
    from zuml_studio.ui import create_main_window

    painted = _FirstPaint()
    app.installEventFilter(painted)
    window = create_main_window()
    window.resize(1600, 1000)
    window.show()
    while painted.at is None:
        app.processEvents()
    print(f"start to first paint: {(painted.at - T0) * 1000:.0f} ms (process start incl. imports; target < 1500 ms)")
    app.removeEventFilter(painted)
    window.sim_panel.form.auto.setChecked(False) if hasattr(window.sim_panel.form, "auto") else None

    window.editor.setPlainText(_hundred_lines())
    window.validate_now()
    cursor = window.editor.textCursor()
    cursor.movePosition(QTextCursor.MoveOperation.Start)
    cursor.movePosition(QTextCursor.MoveOperation.Down, n=50)
    cursor.movePosition(QTextCursor.MoveOperation.EndOfLine)
    window.editor.setTextCursor(cursor)
    times = []
    for i in range(200):
        key = Qt.Key.Key_Space if i % 2 else Qt.Key.Key_Backspace
        t = time.perf_counter()
        QTest.keyClick(window.editor, key)
        app.processEvents()
        times.append((time.perf_counter() - t) * 1000)
    times.sort()
    print(f"GUI thread per keystroke (100 lines): median {statistics.median(times):.2f} ms, "
          f"p90 {times[180]:.2f} ms (target < 5 ms)")

    latencies = []
    for i in range(10):
        window.editor.setPlainText(_hundred_lines())
        window.validate_now()
        cursor = window.editor.textCursor()
        cursor.setPosition(window.editor.document().find("CONSTANT_I=INPUT").selectionEnd())
        window.editor.setTextCursor(cursor)
        runs = window.validator.runs
        for _ in range(4):
            QTest.keyClick(window.editor, Qt.Key.Key_Backspace)
        t = time.perf_counter()
        QTest.keyClick(window.editor, Qt.Key.Key_Backspace)         # INPUT -> nothing: an error
        while not any(d.is_error for d in window.editor.diagnostics()):
            app.processEvents()
            time.sleep(0.001)
        latencies.append((time.perf_counter() - t) * 1000)
        assert window.validator.runs == runs + 1, "one check per burst of typing"
    print(f"last keystroke to underline: median {statistics.median(latencies):.0f} ms, max {max(latencies):.0f} ms "
          f"(debounce 250 ms; target < 300 ms)")
    window.editor.document().setModified(False)
    window.close()


if __name__ == "__main__":
    main()
