"""The device panel's live plot, offscreen: 1 M points per curve (4 curves: V, I, T, heat sink),
then ~30 frames each with a few new samples: take them (setData) and repaint the widget.
Prints the median redraw time per frame (target < 20 ms), for the last 30 minutes in view
(follow: the view moves every frame), for the whole session in view with the new samples in it
(every frame takes the new samples into the min/max envelopes and draws the view from them),
and for a view that stays while samples arrive right of it (no setData; the repaint alone).
Every frame paints the whole plot widget exactly once. Numbers only.
Run: python benchmarks/bench_live_plot.py [points]

With ``--hours H`` (issue 16): H hours of 50 Hz telemetry fed as the reader thread does
(one-second blocks, a redraw every simulated minute), then the memory the process gained
(resident set; target <= 150 MB after 24 h) and the frame cost with the whole session in view.
Run: python benchmarks/bench_live_plot.py --hours 24"""
from __future__ import annotations

import os
import statistics
import sys
import time

os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")

import numpy as np
from PySide6.QtWidgets import QApplication

FRAMES = 30


class _Event:
    def __init__(self, number, time_s, kind, section="charge", index=1, detail=""):
        self.number, self.time_s, self.kind, self.section, self.index = number, time_s, kind, section, index
        self.repetition, self.offset, self.detail = 1, 17, detail


def fill(series, n: int) -> None:
    t = np.arange(n, dtype=float)                       # one sample per macro second
    rng = np.random.default_rng(1)
    series.buffer.extend({"t": t, "voltage": 5.6 + 0.4 * np.sin(t / 5000.0) + rng.normal(0, 0.003, n),
                          "current": np.where((t // 20000) % 2 == 0, 2.0, -1.0),
                          "temp": 25 + 5 * np.sin(t / 9000.0), "heatsink": 30 + 3 * np.cos(t / 7000.0)})
    # phases every 20 000 s, as events would make them
    number = 0
    for k, start in enumerate(range(0, n, 20000)):
        section = "charge" if k % 2 == 0 else "discharge"
        series.add_event(_Event(number, start, "phase_start", section, 1))
        series.add_event(_Event(number + 1, min(start + 20000, n - 1), "phase_end", section, 1,
                                "IF(DELTA_PEAK>0.01S) STOP_FAZE"))
        number += 2


def frames(app, plot, follow: bool, room: bool = True) -> float:
    """Median ms per frame: 5 new samples, refresh (setData), repaint. ``room``: with follow
    off, the view reaches past the newest sample, so every frame's samples are drawn."""
    plot.set_follow(follow)
    buf = plot.series.buffer
    if not follow:
        last = buf.last()["t"]
        plot.tplot.setXRange(0.0, last + (6 * FRAMES if room else 0.0), padding=0)
        app.processEvents()
    costs = []
    for _ in range(FRAMES):
        last = buf.last()
        t0 = last["t"] if last else 0.0
        buf.extend({"t": t0 + np.arange(1, 6), "voltage": np.full(5, 5.7), "current": np.full(5, 2.0),
                    "temp": np.full(5, 26.0), "heatsink": np.full(5, 31.0)})
        painted = plot.paints
        start = time.perf_counter()
        plot.refresh()
        app.processEvents()                 # delivers the scene's update: one paint if anything changed
        if plot.paints == painted:
            plot.viewport().repaint()       # nothing changed on screen: force the paint anyway
        costs.append((time.perf_counter() - start) * 1000.0)
    return statistics.median(costs)


def _status_mb(key: str) -> float:
    with open("/proc/self/status") as fh:
        for line in fh:
            if line.startswith(key):
                return int(line.split()[1]) / 1024.0
    return float("nan")


def rss_mb() -> float:
    return _status_mb("VmRSS:")


def peak_mb() -> float:
    return _status_mb("VmHWM:")


def session(app, hours: float) -> None:
    from zuml_studio.ui.device.live_plot import LivePlot

    plot = LivePlot()
    plot.resize(840, 360)
    plot.show()
    app.processEvents()
    base = rss_mb()
    buf = plot.series.buffer
    rng = np.random.default_rng(1)
    seconds = int(hours * 3600)
    start = time.perf_counter()
    for s in range(seconds):
        t = s + np.arange(50) / 50.0
        buf.extend({"t": t, "voltage": 5.6 + 0.4 * np.sin(t / 5000.0) + rng.normal(0, 0.003, 50),
                    "current": np.full(50, 2.0 if (s // 20000) % 2 == 0 else -1.0),
                    "temp": 25 + 5 * np.sin(t / 9000.0), "heatsink": 30 + 3 * np.cos(t / 7000.0)})
        if s % 60 == 59:
            plot.refresh()
    plot.refresh()
    app.processEvents()
    fed = time.perf_counter() - start
    gained = rss_mb() - base
    peak = peak_mb() - base
    whole = frames(app, plot, False)
    print(f"{hours:g} h at 50 Hz: {len(buf):,} samples fed in {fed:.1f} s; the process gained {gained:.0f} MB, "
          f"{peak:.0f} MB at its peak "
          f"(target <= 150 MB); redraw per frame, whole session in view: {whole:.1f} ms (target <= 20 ms)")


def main() -> None:
    app = QApplication.instance() or QApplication(sys.argv[:1])
    if "--hours" in sys.argv:
        session(app, float(sys.argv[sys.argv.index("--hours") + 1]))
        return
    points = int(sys.argv[1]) if len(sys.argv) > 1 else 1_000_000
    from zuml_studio.ui.device.live_plot import LivePlot

    plot = LivePlot()
    plot.resize(840, 360)
    plot.show()
    app.processEvents()
    fill(plot.series, points)
    painted = plot.paints
    start = time.perf_counter()
    plot.refresh()
    app.processEvents()
    if plot.paints == painted:
        plot.viewport().repaint()
    first = (time.perf_counter() - start) * 1000.0
    follow = frames(app, plot, True)
    whole = frames(app, plot, False)
    still = frames(app, plot, False, room=False)
    print(f"points per curve: {plot.points}")
    print(f"first draw: {first:.1f} ms")
    print(f"redraw per frame, last 30 min in view (follow): {follow:.1f} ms (median of {FRAMES}; target < 20 ms)")
    print(f"redraw per frame, whole session in view: {whole:.1f} ms (median of {FRAMES}; target < 20 ms)")
    print(f"frame, whole session in view, new samples right of it (follow off): {still:.1f} ms")
    print(f"phase bands: {plot.band_count()}")


if __name__ == "__main__":
    main()
