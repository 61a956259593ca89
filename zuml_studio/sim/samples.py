"""One sample per tick, stored by column (appending to lists is the cheapest thing
the hot loop can do); numpy arrays and CSV on demand."""
from __future__ import annotations

import csv
from typing import TextIO

import numpy as np

COLUMNS = ("time_s", "section", "phase", "voltage_v", "current_a", "temp_c", "heatsink_c", "mah_in", "mah_out")
SECTION_NAMES = ("discharge", "charge")


class SampleLog:
    def __init__(self) -> None:
        self.time_s: list[float] = []
        self.section: list[int] = []       # 0 discharge, 1 charge
        self.phase: list[int] = []         # run number of the phase, 1-based
        self.voltage_v: list[float] = []
        self.current_a: list[float] = []   # signed: + charge, - discharge
        self.temp_c: list[float] = []
        self.heatsink_c: list[float] = []
        self.mah_in: list[float] = []
        self.mah_out: list[float] = []
        self.append = self._appender()

    def _appender(self):
        cols = [getattr(self, name).append for name in COLUMNS]
        t, s, p, v, i, tc, hs, qi, qo = cols

        def append(time_s, section, phase, voltage_v, current_a, temp_c, heatsink_c, mah_in, mah_out) -> None:
            t(time_s); s(section); p(phase); v(voltage_v); i(current_a)
            tc(temp_c); hs(heatsink_c); qi(mah_in); qo(mah_out)

        return append

    def __len__(self) -> int:
        return len(self.time_s)

    def arrays(self, start: int = 0) -> dict[str, np.ndarray]:
        return {name: np.asarray(getattr(self, name)[start:], dtype=float) for name in COLUMNS}

    def write_csv(self, stream: TextIO) -> None:
        writer = csv.writer(stream, lineterminator="\n")
        writer.writerow(COLUMNS)
        for row in zip(*(getattr(self, name) for name in COLUMNS)):
            t, s, p, v, i, tc, hs, qi, qo = row
            writer.writerow((f"{t:.1f}", SECTION_NAMES[s], p, f"{v:.4f}", f"{i:.4f}", f"{tc:.2f}", f"{hs:.2f}",
                             f"{qi:.1f}", f"{qo:.1f}"))
