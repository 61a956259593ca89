"""``zuml log export``: one CSV row per sample in SI units, charge current positive, empty
where the log does not measure a quantity; or (``--dataexplorer``) DataExplorer-style record sets,
one ``### RECORDSET`` block per phase, each restarting at time 0 (``write_record_sets``), which
``csv_import`` reads back to the same samples."""
from __future__ import annotations

import csv
import datetime as dt
from typing import TextIO

from .session_log import cell_columns
import numpy as np

from .model import STATES, Log

# A phase's state -> its record set's name (DataExplorer's German words, which record_sets reads).
SET_NAMES = {"charge": "Laden", "discharge": "Entladen", "pause": "Pause", "idle": "Idle"}
# Where the time line starts when the log gives no date (ms since 1970: 2001-09-09).
EPOCH_MS = 1.0e12


def start_ms(log: Log) -> float:
    """The log's own start (``meta["started"]``; a time without a zone read as UTC) in ms since 1970, else
    ``EPOCH_MS``: an export of a dated log is dated as it is."""
    started = log.meta.get("started")
    if started:
        try:
            when = dt.datetime.fromisoformat(str(started))
        except ValueError:
            return EPOCH_MS
        if when.tzinfo is None:
            when = when.replace(tzinfo=dt.timezone.utc)
        return when.timestamp() * 1000.0
    return EPOCH_MS

COLUMNS = ("t_s", "voltage_v", "current_a", "temp_c", "charge_in_mah", "charge_out_mah", "state")


def header(log: Log) -> list[str]:
    return list(COLUMNS + cell_columns(log.cells))


def write_csv(log: Log, stream: TextIO) -> int:
    """Write the log; returns the number of rows (header not counted)."""
    writer = csv.writer(stream, lineterminator="\n")
    writer.writerow(header(log))
    current = log.meta.get("current_measured", True)
    c = log.columns
    for k in range(len(c)):
        temp = c.temp[k]
        writer.writerow([f"{c.t[k]:.3f}", f"{c.voltage[k]:.4f}", f"{c.current[k]:.4f}" if current else "",
                         "" if np.isnan(temp) else f"{temp:.2f}",
                         f"{c.mah_in[k]:.1f}" if current else "", f"{c.mah_out[k]:.1f}" if current else "",
                         STATES[c.state[k]]] + [f"{v:.4f}" for v in c.cells[k].tolist()])
    return len(c)


def write_record_sets(log: Log, stream: TextIO, source: str = "") -> int:
    """DataExplorer-style: per phase a ``### RECORDSET`` line, a ``#`` line (source, device, record set
    name, start time stamp, time step), a header and the rows, time from 0. Returns the rows written."""
    writer = csv.writer(stream, lineterminator="\n")
    current = log.meta.get("current_measured", True)
    c = log.columns
    temp = bool(np.isfinite(c.temp).any())
    width = log.cells
    steps = np.diff(c.t)
    steps = steps[steps > 0]
    step_ms = float(steps.min()) * 1000.0 if len(steps) else 1000.0
    names = ["time_s", "Spannung [V]"] + (["Strom [A]"] if current else []) + ["Ladung [mAh]"] + \
        (["Temperatur [°C]"] if temp else []) + [f"ZellenSpannung {k + 1} [V]" for k in range(width)]
    rows = 0
    first_ms = start_ms(log)
    for n, (phase, (start, end)) in enumerate(zip(log.phases(), log.phase_bounds())):
        t0 = float(c.t[start])
        name = f"{n + 1}) {SET_NAMES[phase.state]}"
        stream.write("### RECORDSET\n")
        stream.write(f"# source={source or 'log'} device={log.device.replace(' ', '_')} recordset='{name}' "
                     f"timestep_ms={step_ms!r} startTimeStamp_epoch_ms={first_ms + (t0 - float(c.t[0])) * 1000.0!r}\n")
        writer.writerow(names)
        before = start - 1 if start else start              # the step into the set counts in it
        q_in0, q_out0 = float(c.mah_in[before]), float(c.mah_out[before])
        for k in range(start, end):
            moved = float(c.mah_out[k]) - q_out0 if phase.state == "discharge" else \
                float(c.mah_in[k]) - q_in0 if phase.state == "charge" else 0.0      # a pause holds; idle moves none
            t_c = float(c.temp[k])
            writer.writerow([repr(round(float(c.t[k]) - t0, 6)), repr(float(c.voltage[k]))] +
                            ([repr(float(c.current[k]))] if current else []) + [f"{moved:.3f}"] +
                            ([repr(t_c) if not np.isnan(t_c) else ""] if temp else []) +
                            [repr(v) for v in c.cells[k].tolist()])
        rows += end - start
    return rows
