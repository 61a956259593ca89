"""The window while it simulates (issue 26): wall-clock gaps of the GUI event loop while the run of a
training macro is changed over and over with Auto re-simulate on. Numbers only; run by hand:
    python benchmarks/bench_sim_stalls.py [--quick] [--seconds N] [--toggle-ms MS] [--slices]

A precise timer fires every 2 ms (``bench_gui.Probe``); a gap is the wall time between two firings
less 2 ms: whatever kept the event loop from turning, the GUI thread's own work, waiting for the GIL
or not being scheduled. The battery's capacity is toggled every 700 ms (2000 <-> 2100 mAh, as if
typed): each change re-simulates after the 300 ms debounce and the run lands while the next change
comes. Printed per training (NiMH 2000 mAh x 4 at 2 A; 1 repetition ~3 h, 16 ~47 h): the longest gap
and the 99th percentile (target: one frame, 16 ms), the GUI thread's longest CPU time in one go, the
runs drawn and the load average (a shared machine's gaps include time the thread was not scheduled).
A 47 h run takes about as long as the toggle's period to simulate, so most are replaced before they
end; ``--toggle-ms 2500`` lets each run end and be drawn.

``--slices`` also prints the GUI thread's CPU time (``time.thread_time``) in each slice a new run is
drawn in (the panel's steps, the table, the plot's paint, the collector's turns): a loaded machine
stretches the wall-clock gaps, hardly a thread's own CPU time, so this is the figure to cut on a
shared machine (the worst slice wants a clear margin under 16 ms: a worker holding the GIL can
double a slice's wall time).
"""
from __future__ import annotations

import collections
import os
import sys
import time

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import bench_gui  # noqa: E402  (sets the offscreen platform and a scratch config directory)
from PySide6.QtCore import Qt, QTimer  # noqa: E402
from PySide6.QtWidgets import QApplication  # noqa: E402

TOGGLE_MS = 700
CAPACITIES = (2000, 2100)


def toggling(app, window, label: str, repetitions: int, seconds: float, toggle_ms: int = TOGGLE_MS) -> None:
    panel = window.sim_panel
    panel.form.auto.setChecked(True)
    hours = bench_gui._training(window, repetitions)
    drawn = [0]
    panel.simulationFinished.connect(lambda _r: drawn.__setitem__(0, drawn[0] + 1))
    flips = [0]

    def flip() -> None:
        flips[0] += 1
        panel.form.set_values(capacity_mah=CAPACITIES[flips[0] % 2])

    toggler = QTimer(interval=toggle_ms, timerType=Qt.TimerType.PreciseTimer)
    toggler.timeout.connect(flip)
    probe = bench_gui.Probe()
    load = os.getloadavg()[0]
    toggler.start()
    probe.start()
    bench_gui.run_loop(int(seconds * 1000))
    gaps = sorted(probe.gaps) or [0.0]
    longest, p99, busy = probe.stop()
    toggler.stop()
    panel.form.auto.setChecked(False)
    assert panel.wait(120_000), "the last run did not end"
    panel.simulationFinished.disconnect()
    print(f"{label} ({hours:.1f} h), capacity toggled every {toggle_ms} ms for {seconds:g} s, {flips[0]} changes, "
          f"{drawn[0]} runs drawn: longest gap {longest:.1f} ms, p99 {p99:.1f} ms, p90 {gaps[int(len(gaps) * 0.9)]:.1f} "
          f"ms (target <= 16 ms); GUI-thread CPU in one go, longest {busy:.1f} ms; load average {load:.2f}")


class Slices:
    """The GUI thread's CPU time in each slice of a drawn run, by kind (``--slices``)."""

    def __init__(self, window, collector) -> None:
        self.cpu: dict[str, list[float]] = collections.defaultdict(list)
        panel = self.panel = window.sim_panel
        show = panel._show

        def timed_show(run, finished=False):
            self._time("run shown (show_run)", show, run, finished)
            panel._steps = [self._timer(self._name(step), step) for step in panel._steps]
        panel._show = timed_show
        for name in ("_show_table", "_show_totals"):
            setattr(panel, name, self._timer(name.strip("_"), getattr(panel, name)))
        self.painted = panel.plot
        collector.timer.timeout.disconnect()
        collector.timer.timeout.connect(self._timer("collector", collector.check))

    @classmethod
    def watch_paints(cls) -> dict[str, list[float]]:
        """Before the window is made (PySide looks a virtual method up once): each plot's paint timed;
        the simulator's plot's kept."""
        import pyqtgraph as pg
        painted: dict[str, list[float]] = collections.defaultdict(list)
        paint = pg.GraphicsView.paintEvent

        def timed(view, event):
            t = time.thread_time()
            try:
                return paint(view, event)
            finally:
                painted[type(view).__name__].append((time.thread_time() - t) * 1000.0)
        pg.GraphicsView.paintEvent = timed
        return painted

    @staticmethod
    def _name(step) -> str:
        func = getattr(step, "func", step)
        return getattr(func, "__qualname__", getattr(func, "__name__", "step")).split(".")[-1]

    def _time(self, name: str, fn, *args):
        t = time.thread_time()
        try:
            return fn(*args)
        finally:
            self.cpu[name].append((time.thread_time() - t) * 1000.0)

    def _timer(self, name: str, fn):
        return lambda *args: self._time(name, fn, *args)

    def report(self, painted: dict[str, list[float]]) -> None:
        self.cpu["plot paint"] = painted.pop(type(self.painted).__name__, [0.0])
        painted.clear()
        for name, values in sorted(self.cpu.items(), key=lambda kv: -max(kv[1])):
            values = sorted(values)
            print(f"  {name:28s} {len(values):4d} slices: median {values[len(values) // 2]:5.2f} ms, "
                  f"p90 {values[int(len(values) * 0.9)]:5.2f} ms, longest {values[-1]:5.2f} ms (thread CPU)")
        self.cpu.clear()


def main() -> None:
    quick = "--quick" in sys.argv
    seconds = float(sys.argv[sys.argv.index("--seconds") + 1]) if "--seconds" in sys.argv else (8.0 if quick else 20.0)
    toggle_ms = int(sys.argv[sys.argv.index("--toggle-ms") + 1]) if "--toggle-ms" in sys.argv else TOGGLE_MS
    app = QApplication.instance() or QApplication(sys.argv[:1])
    from zuml_studio.ui import create_main_window
    from zuml_studio.ui.base.gui_thread_gc import collect_on_gui_thread

    collector = collect_on_gui_thread()         # as the application does (ui/app.py)
    painted = Slices.watch_paints() if "--slices" in sys.argv else {}
    window = create_main_window()
    window.resize(1366, 768)
    window.show()
    bench_gui.run_loop(1000)
    t0 = time.perf_counter()
    slices = Slices(window, collector) if "--slices" in sys.argv else None
    for label, repetitions in bench_gui.TRAININGS.items():
        toggling(app, window, label, repetitions, seconds, toggle_ms)
        if slices is not None:
            slices.report(painted)
    window.editor.document().setModified(False)
    window.close()
    collector.timer.stop()
    print(f"(whole benchmark {time.perf_counter() - t0:.0f} s)")


if __name__ == "__main__":
    main()
