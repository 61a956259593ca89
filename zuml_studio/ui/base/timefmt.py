"""Times as chargers show them (h:mm, h:mm:ss) and a pyqtgraph time axis that
ticks at round minutes and hours, for the simulator plot and the live device plot.

The axis values are seconds since the start of the run."""
from __future__ import annotations

import math

import pyqtgraph as pg

from ...i18n import _

# Round tick steps in seconds: what a person reads off a clock.
TICK_STEPS_S = (1, 2, 5, 10, 15, 30, 60, 120, 300, 600, 900, 1800, 3600, 2 * 3600, 3 * 3600, 6 * 3600,
                12 * 3600, 24 * 3600, 48 * 3600)
# Each step's minor ticks.
_MINOR = {1: 0.5, 2: 1, 5: 1, 10: 5, 15: 5, 30: 10, 60: 30, 120: 60, 300: 60, 600: 300, 900: 300, 1800: 600,
          3600: 900, 7200: 1800, 10800: 3600, 21600: 3600, 43200: 7200, 86400: 21600, 172800: 43200}


def _split(seconds: float) -> tuple[str, int, int, int]:
    sign = "-" if seconds < 0 else ""
    total = int(round(abs(seconds)))
    return sign, total // 3600, total // 60 % 60, total % 60


def hmm(seconds: float) -> str:
    """``3725`` -> ``"1:02"`` (rounded to the minute)."""
    sign, _, _, _ = _split(seconds)
    minutes = int(round(abs(seconds) / 60.0))
    return f"{sign}{minutes // 60}:{minutes % 60:02d}"


def hmmss(seconds: float) -> str:
    """``3725`` -> ``"1:02:05"``."""
    sign, h, m, s = _split(seconds)
    return f"{sign}{h}:{m:02d}:{s:02d}"


def duration(seconds: float) -> str:
    """A short, readable length of time: ``"45 s"``, ``"12:30"`` (m:ss), ``"1:04:30"``."""
    sign, h, m, s = _split(seconds)
    if not h and not m:
        return sign + _("{seconds} s").format(seconds=s)
    if not h:
        return sign + _("{minutes}:{seconds} min").format(minutes=m, seconds=f"{s:02d}")
    return f"{sign}{h}:{m:02d}:{s:02d}"


def tick_step(span_s: float, size_px: float, min_px: float = 48.0) -> float:
    """The smallest round step that keeps major ticks at least ``min_px`` apart."""
    if span_s <= 0 or size_px <= 0:
        return TICK_STEPS_S[-1]
    most = max(1.0, size_px / min_px)
    for step in TICK_STEPS_S:
        if span_s / step <= most:
            return float(step)
    # More than two days on screen: whole multiples of two days.
    return float(TICK_STEPS_S[-1] * math.ceil(span_s / most / TICK_STEPS_S[-1]))


def tick_format(step: float) -> str:
    """The format of an axis's labels: h:mm for steps of a minute or more, h:mm:ss below."""
    return "h:mm" if step >= 60 else "h:mm:ss"


def tick_label(seconds: float, step: float) -> str:
    return hmm(seconds) if tick_format(step) == "h:mm" else hmmss(seconds)


def elapsed(seconds: float) -> str:
    """A length of simulated or run time that cannot be read as a clock: ``"19 h 43 min"``,
    ``"58 min"``, ``"45 s"``."""
    sign, h, m, s = _split(seconds)
    if h:
        return sign + _("{hours} h {minutes} min").format(hours=h, minutes=f"{m:02d}")
    if m:
        return sign + _("{minutes} min").format(minutes=m)
    return sign + _("{seconds} s").format(seconds=s)


class TimeAxisItem(pg.AxisItem):
    """A bottom axis over seconds that ticks at round clock steps, labels them h:mm or h:mm:ss,
    and says which in its title ("time (h:mm:ss)"): one format per axis at a time."""

    def __init__(self, orientation: str = "bottom", min_px: float = 48.0, **kw):
        super().__init__(orientation, **kw)
        self.min_px = min_px
        self.title_style: dict = {}
        self.shown_format = ""
        self.enableAutoSIPrefix(False)
        self.setStyle(maxTextLevel=0)      # labels on the round steps only, minor ticks unlabelled

    def tickSpacing(self, minVal, maxVal, size):  # noqa: N802 (pyqtgraph's name)
        span = abs(maxVal - minVal)
        if span == 0:
            return []
        major = tick_step(span, size, self.min_px)
        minor = _MINOR.get(int(major), major / 4)
        return [(major, 0.0), (minor, 0.0)]

    def tickStrings(self, values, scale, spacing):  # noqa: N802
        self.set_format(tick_format(spacing))
        return [tick_label(v, spacing) for v in values]

    def set_format(self, name: str) -> None:
        """Title the axis with the labels' format (only when it changes: a title costs a relayout)."""
        if name != self.shown_format:
            self.shown_format = name
            self.setLabel(_("time ({format})").format(format=name), **self.title_style)
