"""-dV detection as a B6-class charger does it (cheali-charger, chargers.md §1c; battery-models.md §2.5).

Samples are averaged over fixed windows (cheali: 30 s). At the end of each
window the average is compared with the held peak of earlier averages. During
the hold-off after the phase start the peak simply follows the average, so the
voltage wobble of a freshly connected pack never counts as a drop (seed 001:
ignore the first 5-10 minutes). The charger model sets both numbers
(``[delta_peak]`` in resources/chargers/*.toml).
"""
from __future__ import annotations

from ..i18n import _


class DeltaPeakDetector:
    """Held-peak -dV on window averages; `update` returns the drop below the peak in volts."""

    def __init__(self, window_s: float = 30.0, holdoff_s: float = 300.0) -> None:
        if window_s <= 0 or holdoff_s < 0:
            raise ValueError(_("window_s must be > 0 and holdoff_s >= 0"))
        self.window_s = float(window_s)
        self.holdoff_s = float(holdoff_s)
        self.reset()

    def reset(self) -> None:
        """Forget everything; call at the start of a phase."""
        self.peak_v = 0.0       # 0.0 until the first window has closed
        self.drop_v = 0.0
        self._sum = 0.0
        self._count = 0
        self._window_end: float | None = None

    def update(self, t_phase_s: float, v_pack: float) -> float:
        """Feed one measured (noisy) pack voltage sample at phase time t; returns the current drop below the held peak in volts (>= 0), computed on window averages; 0.0 during hold-off (peak follows V during hold-off, as cheali does)."""
        if self._window_end is None:
            self._window_end = self._next_window_end(t_phase_s)
        # A reading below 0 V (a pack collapsed past empty, a shorted one) counts as 0 V: a charger's ADC
        # reads no less, and the firmware's core sums its readings unsigned (firmware/core/interp.c).
        self._sum += v_pack if v_pack > 0.0 else 0.0
        self._count += 1
        if t_phase_s < self._window_end:
            return self.drop_v
        avg = self._sum / self._count
        self._sum = 0.0
        self._count = 0
        self._window_end = self._next_window_end(t_phase_s)
        if t_phase_s <= self.holdoff_s or avg >= self.peak_v:
            self.peak_v = avg
            self.drop_v = 0.0
        else:
            # To 1 pV: a held constant voltage shows no drop from float rounding of its averages, and a
            # real drop (at least 1 µV / count² apart from any threshold) keeps its order.
            self.drop_v = round(self.peak_v - avg, 12)
        return self.drop_v

    def _next_window_end(self, t: float) -> float:
        # Windows sit on a fixed grid of phase time (0-30 s, 30-60 s, ...), also across sampling gaps.
        return (t // self.window_s + 1.0) * self.window_s
