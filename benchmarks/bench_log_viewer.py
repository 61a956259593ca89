"""The log viewer opening a long log, offscreen (issue 16): a 78 483-sample Ultramat .osd
(tests/data/logs). Prints the time from File > Open to the drawn document, the longest
GUI-thread stall meanwhile (a 2 ms timer's longest gap, less its interval; target <= 16 ms)
and the GUI thread's longest CPU time in one go (the work it did, without the time a loaded
machine did not schedule it). Numbers only. Run: python benchmarks/bench_log_viewer.py [FILE]"""
from __future__ import annotations

import os
import sys
import time
from pathlib import Path

os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")

from PySide6.QtCore import Qt, QTimer
from PySide6.QtWidgets import QApplication

LOG = Path(__file__).resolve().parents[1] / "tests" / "data" / "logs" / "UltramatACDCEQ_2014-09-16_4S_NiMH_cycle.osd"
PROBE_MS = 2


def main() -> None:
    path = sys.argv[1] if len(sys.argv) > 1 else str(LOG)
    app = QApplication.instance() or QApplication(sys.argv[:1])
    import zuml_studio.ui as ui
    from zuml_studio.ui.logs import LogWindow

    sys.setswitchinterval(ui.GIL_SWITCH_S)      # as the main window sets it
    window = LogWindow()
    window.resize(1366, 768)
    window.show()
    app.processEvents()
    gaps, busy, last = [], [], [None, None]

    def tick() -> None:
        now, cpu = time.perf_counter(), time.thread_time()
        if last[0] is not None:
            gaps.append((now - last[0]) * 1000.0 - PROBE_MS)
            busy.append((cpu - last[1]) * 1000.0)
        last[:] = [now, cpu]

    probe = QTimer(interval=PROBE_MS, timerType=Qt.TimerType.PreciseTimer)
    probe.timeout.connect(tick)
    probe.start()
    settle = time.perf_counter()
    while time.perf_counter() - settle < 0.05:     # the probe running before the file is asked for
        app.processEvents()
        time.sleep(0.0005)
    start = time.perf_counter()
    window.open_path(path)
    while window.tabs.count() == 0 and time.perf_counter() - start < 60:
        app.processEvents()
        time.sleep(0.0005)
    window.tabs.currentWidget().repaint()
    opened = time.perf_counter() - start
    for _ in range(20):                         # the first paints after it
        app.processEvents()
        time.sleep(0.002)
    probe.stop()
    samples = len(window.tabs.currentWidget().log.samples)
    print(f"log viewer, {Path(path).name} ({samples} samples): open to drawn {opened * 1000:.0f} ms; longest GUI "
          f"stall {max(gaps, default=0):.0f} ms (target <= 16 ms), longest GUI-thread CPU in one go "
          f"{max(busy, default=0):.0f} ms")
    window.close()


if __name__ == "__main__":
    main()
