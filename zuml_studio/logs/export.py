"""``zuml log export``: one CSV row per sample in SI units, charge current positive, empty
where the log does not measure a quantity."""
from __future__ import annotations

import csv
from typing import TextIO

from ..device.session_log import cell_columns
from .model import Log, state_of

COLUMNS = ("t_s", "voltage_v", "current_a", "temp_c", "charge_in_mah", "charge_out_mah", "state")


def header(log: Log) -> list[str]:
    return list(COLUMNS + cell_columns(log.cells))


def write_csv(log: Log, stream: TextIO) -> int:
    """Write the log; returns the number of rows (header not counted)."""
    writer = csv.writer(stream, lineterminator="\n")
    writer.writerow(header(log))
    current = log.meta.get("current_measured", True)
    width = log.cells
    for s in log.samples:
        cells = [f"{v:.4f}" for v in s.cells_v] + [""] * (width - len(s.cells_v))
        writer.writerow([f"{s.time_s:.3f}", f"{s.voltage_v:.4f}", f"{s.current_a:.4f}" if current else "",
                         "" if s.temp_c is None else f"{s.temp_c:.2f}",
                         f"{s.mah_in:.1f}" if current else "", f"{s.mah_out:.1f}" if current else "",
                         state_of(s)] + cells)
    return len(log.samples)
