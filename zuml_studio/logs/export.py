"""``zuml log export``: one CSV row per sample in SI units, charge current positive, empty
where the log does not measure a quantity; or (``--dataexplorer``) DataExplorer-style record sets,
one ``### RECORDSET`` block per phase, each restarting at time 0 (``write_record_sets``), which
``csv_import`` reads back to the same samples."""
from __future__ import annotations

import csv
from typing import TextIO

from ..device.session_log import cell_columns
from .model import Log, state_of

# A phase's state -> its record set's name (DataExplorer's German words, which record_sets reads).
SET_NAMES = {"charge": "Laden", "discharge": "Entladen", "pause": "Pause", "idle": "Idle"}
# Where the time line starts when the log gives no date (ms since 1970: 2001-09-09).
EPOCH_MS = 1.0e12

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


def write_record_sets(log: Log, stream: TextIO, source: str = "") -> int:
    """DataExplorer-style: per phase a ``### RECORDSET`` line, a ``#`` line (source, device, record set
    name, start time stamp, time step), a header and the rows, time from 0. Returns the rows written."""
    writer = csv.writer(stream, lineterminator="\n")
    current = log.meta.get("current_measured", True)
    temp = any(s.temp_c is not None for s in log.samples)
    width = log.cells
    times = [s.time_s for s in log.samples]
    steps = [b - a for a, b in zip(times, times[1:]) if b > a]
    step_ms = min(steps) * 1000.0 if steps else 1000.0
    names = ["time_s", "Spannung [V]"] + (["Strom [A]"] if current else []) + ["Ladung [mAh]"] + \
        (["Temperatur [°C]"] if temp else []) + [f"ZellenSpannung {k + 1} [V]" for k in range(width)]
    rows = 0
    k = 0
    for n, phase in enumerate(log.phases()):
        start = k
        while k < len(log.samples) and (k == start or state_of(log.samples[k]) == phase.state):
            k += 1
        chunk = log.samples[start:k]
        t0 = chunk[0].time_s
        name = f"{n + 1}) {SET_NAMES[phase.state]}"
        stream.write("### RECORDSET\n")
        stream.write(f"# source={source or 'log'} device={log.device.replace(' ', '_')} recordset='{name}' "
                     f"timestep_ms={step_ms!r} startTimeStamp_epoch_ms={EPOCH_MS + t0 * 1000.0!r}\n")
        writer.writerow(names)
        before = log.samples[start - 1] if start else chunk[0]     # the step into the set counts in it
        q_in0, q_out0 = before.mah_in, before.mah_out
        for s in chunk:
            moved = s.mah_out - q_out0 if phase.state == "discharge" else \
                s.mah_in - q_in0 if phase.state == "charge" else 0.0      # a pause holds; idle moves none
            writer.writerow([repr(round(s.time_s - t0, 6)), repr(s.voltage_v)] +
                            ([repr(s.current_a)] if current else []) + [f"{moved:.3f}"] +
                            ([repr(s.temp_c) if s.temp_c is not None else ""] if temp else []) +
                            [repr(c) for c in s.cells_v] + ["0.0"] * (width - len(s.cells_v)))
        rows += len(chunk)
    return rows
