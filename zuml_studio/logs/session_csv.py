"""ZUML Studio's own CSV files: the device panel's session CSV (``logs/session_log.py``:
the simulator's columns plus ``event``), the simulator's sample CSV (the same columns
without ``event``) and ``zuml log export``'s CSV (``export.py``), so an export reads back.

A session's ``time_s`` is the macro's clock: when a new run starts it again, the run is put
after the previous one (as the live plot does). Event rows carry no measurement and are
counted, not plotted; telemetry rows of section "" (idle) are kept as idle samples."""
from __future__ import annotations

import csv
import io
import math

from ..domain.samples import COLUMNS as SIM_COLUMNS
from . import export
from .model import STATES, Log, LogFormatError, SampleBuilder
from ..i18n import _

SESSION_HEAD = ",".join(SIM_COLUMNS)          # the session CSV adds "event" and the cells after these
EXPORT_HEAD = ",".join(export.COLUMNS)
_SECTION_STATE = {"charge": "charge", "discharge": "discharge", "": "idle"}


def _first_line(head: bytes) -> str:
    return head.lstrip(b"\xef\xbb\xbf").split(b"\n", 1)[0].strip().decode("latin-1")


def sniff(head: bytes, name: str) -> bool:
    line = _first_line(head)
    return line.startswith(SESSION_HEAD) or line.startswith(EXPORT_HEAD)


def _num(text: str, empty_ok: bool) -> float | None:
    if text == "":
        if empty_ok:
            return None
        raise ValueError("empty")
    value = float(text)
    if not math.isfinite(value):
        raise ValueError(_("not finite"))
    return value


def read(data: bytes) -> Log:
    try:
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise LogFormatError(_("not UTF-8 text (byte 0x{data:02x} at offset {start})").format(
                data=data[exc.start], start=exc.start)) from None
    if "\0" in text:
        raise LogFormatError(_("a NUL character in a CSV file"))
    rows = csv.reader(io.StringIO(text, newline=""))
    try:
        header = next(rows)
    except (StopIteration, csv.Error):
        raise LogFormatError(_("no header line")) from None
    for head, session in ((SESSION_HEAD, True), (EXPORT_HEAD, False)):
        if set(head.split(",")) <= set(header) and ",".join(header).startswith(head):
            return _read_rows(rows, header, session=session)
    raise LogFormatError(_("header is neither '{session_head}…' nor '{export_head}…'").format(
            session_head=SESSION_HEAD, export_head=EXPORT_HEAD))


def _cell_columns(header: list[str]) -> list[int]:
    cols = [k for k, name in enumerate(header) if name.startswith("cell") and name.endswith("_v")]
    return cols


def _read_rows(rows, header: list[str], session: bool) -> Log:
    index = {name: k for k, name in enumerate(header)}
    cells = _cell_columns(header)
    builder = SampleBuilder()
    bad = events = 0
    offset = last_t = 0.0
    run_t = None
    width = len(header)
    try:
        for row in rows:
            if not row:
                continue
            if len(row) != width:
                bad += 1
                continue
            try:
                if session:
                    if "event" in index and row[index["event"]]:
                        events += 1
                        continue
                    state = _SECTION_STATE.get(row[index["section"]])
                    t = _num(row[index["time_s"]], False)
                    if run_t is not None and t < run_t - 1e-6:
                        offset = last_t
                    run_t = t
                    t += offset
                    q_in, q_out = _num(row[index["mah_in"]], False), _num(row[index["mah_out"]], False)
                else:
                    state = row[index["state"]] if row[index["state"]] in STATES else None
                    t = _num(row[index["t_s"]], False)
                    q_in = _num(row[index["charge_in_mah"]], True)
                    q_out = _num(row[index["charge_out_mah"]], True)
                if state is None:
                    bad += 1
                    continue
                v = _num(row[index["voltage_v"]], False)
                i = _num(row[index["current_a"]], False)
                temp = _num(row[index["temp_c"]], True)
                heatsink = _num(row[index["heatsink_c"]], True) if "heatsink_c" in index else None
                cell_v = [_num(row[k], True) or 0.0 for k in cells]
            except ValueError:
                bad += 1
                continue
            last_t = max(last_t, t)
            builder.add(t, v, i, state, temp=temp, heatsink=heatsink, cells=cell_v, mah_in=q_in, mah_out=q_out)
    except csv.Error as exc:
        raise LogFormatError(_("CSV line {line_num}: {exc}").format(line_num=rows.line_num, exc=exc)) from None
    if not len(builder):
        raise LogFormatError(_("no sample row ({bad} bad rows, {events} event rows)").format(bad=bad, events=events))
    fmt = "session-csv" if session else "export-csv"
    device = "ZUML Studio session" if session else "ZUML Studio export"
    return builder.build(fmt, device, bad, events=events)
