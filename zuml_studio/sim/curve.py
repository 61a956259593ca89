"""A measured charge or discharge as the battery-model fit needs it: time, pack voltage, current
(+ = charge, - = discharge), temperature.

From any log ``zuml_studio.logs`` reads (the longest charge or discharge, short idle blips merged), or
from a plain curve CSV (``time_s,voltage_v,current_a[,temp_c]``, '#' comment lines), which is the
form the validation curves in tests/data/curves/ are stored in."""
from __future__ import annotations

import csv
import io
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..domain.units import AS_PER_MAH
from ..file_errors import read_file_bytes
from .battery import AMBIENT_MAX_C, AMBIENT_MIN_C
from ..domain.csv_columns import CURRENT_A, CURVE_COLUMNS, TEMP_C, TIME_S, VOLTAGE_V
from ..logs import Log, LogFormatError, read_log
from ..logs.model import MAX_MEASURED, STATES
from ..errors import ZumlError
from ..i18n import _

# Chargers drop out of "charge" for a sample or two (a measurement pause); gaps up to this
# long are part of the same charge.
_MERGE_GAP_S = 120.0
_DROPOUT_C = 5.0             # a sensor sample this far from both neighbours is a dropout
_SHOWN_FIELD = 24           # characters of a bad line's field an error shows
# Beyond these no charger measures: a value past them is a damaged or hostile file, refused before
# the model's arithmetic overflows on it (1e308 A made the fit's residuals infinite). A year of
# log; 2 kV covers the longest pack a logging charger takes; the sensors' own ranges for °C.
_LIMITS = {TIME_S: (0.0, 3.2e7), VOLTAGE_V: (-MAX_MEASURED, MAX_MEASURED),
           CURRENT_A: (-MAX_MEASURED, MAX_MEASURED), TEMP_C: (-100.0, 400.0)}
# A charge puts at least this much in; a voltage that ends this fraction below its start and never
# climbs this fraction above it falls all the way: a discharge read as a charge (a log without a
# direction column: an AkkuMaster "Entladen" file, 5.13 V to 3.21 V at +0.15 A).
_MIN_CHARGE_MAH = 1.0
_FALL_FRACTION = 0.03
_RISE_FRACTION = 0.01


DIRECTIONS = ("charge", "discharge")


class CurveError(ZumlError, ValueError):
    """The file holds no charge the fit can use; the message says why."""


@dataclass(frozen=True)
class Curve:
    t: np.ndarray            # s from the start of the charge
    v: np.ndarray            # pack V
    i: np.ndarray            # A, + = charge
    temp: np.ndarray | None  # °C, None where not recorded
    cells: int               # per-cell voltages the log carried (0: none)
    name: str = ""
    chemistry: str = ""      # the battery type the log names, if it names one (iCharger logs do)
    start_s: float = 0.0     # its first sample on the log's own clock (where its rests are found)
    # Per-cell voltages (samples x cells, V, NaN where not read) where the log has balance taps;
    # the per-cell fit (fit_cells.py) reads them. Not carried by ``decimated``.
    cells_v: np.ndarray | None = None

    def __post_init__(self) -> None:
        name = self.name or "curve"
        if len(self.t) < 10:
            raise CurveError(_("{value}: only {n_t} samples of charge").format(value=name, n_t=len(self.t)))
        _check_values(name, {TIME_S: self.t, VOLTAGE_V: self.v, CURRENT_A: self.i, TEMP_C: self.temp},
                      lambda k: _("sample {k}").format(k=k + 1))

    @property
    def ambient_c(self) -> float:
        """The ambient a model of this charge starts in: the first temperature logged (25 °C
        without one), within the model's range (a sensor reading 85 °C or -50 °C is no room)."""
        first = float(self.temp[0]) if self.temp is not None else 25.0
        return min(AMBIENT_MAX_C, max(AMBIENT_MIN_C, first))

    @property
    def mah(self) -> np.ndarray:
        """Charge put in since the start, mAh (trapezoid on the log's own current)."""
        dt = np.diff(self.t, prepend=self.t[0])
        i_mid = np.concatenate(([self.i[0]], (self.i[1:] + self.i[:-1]) / 2))
        return np.cumsum(np.clip(i_mid, 0.0, None) * dt) / AS_PER_MAH

    @property
    def delivered_mah(self) -> np.ndarray:
        """Charge taken out since the start, mAh (a discharge's capacity figure)."""
        dt = np.diff(self.t, prepend=self.t[0])
        i_mid = np.concatenate(([self.i[0]], (self.i[1:] + self.i[:-1]) / 2))
        return np.cumsum(np.clip(-i_mid, 0.0, None) * dt) / AS_PER_MAH

    @property
    def direction(self) -> str:
        """"discharge" where more charge goes out than in, else "charge"."""
        return "discharge" if self.delivered_mah[-1] > self.mah[-1] else "charge"

    def decimated(self, step_s: float) -> "Curve":
        """One sample per step_s: the mean current over the step (the charge stays the same), the
        median voltage (a charger's short measurement pause does not pull it down), the mean temperature."""
        edges = [0]
        for k in range(1, len(self.t)):
            if self.t[k] - self.t[edges[-1]] >= step_s:
                edges.append(k)
        if edges[-1] != len(self.t) - 1:
            edges.append(len(self.t) - 1)
        if len(edges) == len(self.t):
            return self
        dt = np.diff(self.t, prepend=self.t[0])
        t, v, i, temp = [self.t[0]], [self.v[0]], [self.i[0]], [] if self.temp is None else [self.temp[0]]
        for lo, hi in zip(edges, edges[1:]):
            part = slice(lo + 1, hi + 1)
            t.append(self.t[hi])
            v.append(float(np.median(self.v[part])))
            i.append(float(np.sum(self.i[part] * dt[part]) / max(np.sum(dt[part]), 1e-9)))
            if self.temp is not None:
                temp.append(float(np.mean(self.temp[part])))
        return Curve(np.array(t), np.array(v), np.array(i), None if self.temp is None else np.array(temp),
                     self.cells, self.name, self.chemistry, self.start_s)

    def to_csv(self) -> str:
        out = io.StringIO()
        out.write(",".join(CURVE_COLUMNS + ((TEMP_C,) if self.temp is not None else ())) + "\n")
        for k in range(len(self.t)):
            row = [f"{self.t[k]:.1f}", f"{self.v[k]:.4f}", f"{self.i[k]:.4f}"]
            if self.temp is not None:
                row.append(f"{self.temp[k]:.2f}")
            out.write(",".join(row) + "\n")
        return out.getvalue()


def _check_values(name: str, columns: dict[str, np.ndarray | None], where) -> None:
    """Every value finite, time rising, every value within what a charger measures (in that order: a
    time that goes back is said as such, not as a time out of range); ``where(k)`` names sample k."""
    present = {column: values for column, values in columns.items() if values is not None}
    for column, values in present.items():
        if not np.isfinite(values).all():
            k = int(np.flatnonzero(~np.isfinite(values))[0])
            raise CurveError(_("{value}: {where}: {column} is not a finite number").format(
                    value=name, where=where(k), column=column))
    t = present[TIME_S]
    back = np.flatnonzero(np.diff(t) <= 0)
    if len(back):
        k = int(back[0]) + 1
        raise CurveError(_("{value}: {where}: time {t:g} s does not follow {before:g} s: time must rise from "
                           "sample to sample").format(value=name, where=where(k), t=float(t[k]),
                                                      before=float(t[k - 1])))
    for column, values in present.items():
        lo, hi = _LIMITS[column]
        if column == TIME_S and len(values):
            values = values - values[0]         # a log's clock may start anywhere: its length counts
        outside = (values < lo) | (values > hi)
        if outside.any():
            k = int(np.flatnonzero(outside)[0])
            raise CurveError(_("{value}: {where}: {column} {x:g} is outside {lo:g} to {hi:g}: no charger measures "
                               "that").format(value=name, where=where(k), column=column, x=float(values[k]),
                                              lo=lo, hi=hi))


def require_charge(curve: Curve) -> None:
    """Refuse, in words, a curve that is no charge: what the fit and the comparison model is one."""
    name = curve.name or "curve"
    if not (curve.i > 0).any():
        raise CurveError(_("{name}: nothing to fit: the current is never positive (a charge's is): "
                           "this curve only discharges or rests").format(name=name))
    mah = float(curve.mah[-1])
    if mah < _MIN_CHARGE_MAH:
        raise CurveError(_("{name}: nothing to fit: the curve puts in only {mah:.2f} mAh").format(name=name, mah=mah))
    fall = falls_all_the_way(curve)
    if fall:
        v0, v1 = fall
        raise CurveError(_("{name}: the voltage falls all the way, from {v0:.2f} V to {v1:.2f} V: a discharge, not "
                           "a charge (its current is read as charging where the file has no direction)").format(
                name=name, v0=v0, v1=v1))


def falls_all_the_way(curve: Curve) -> tuple[float, float] | None:
    """(start V, end V) where the voltage ends well below its start and never climbs above it: a
    discharge, whatever the sign of its current; else None."""
    # The first and last twentieth, and the top tenth: a sample's noise or a pause is no rise or fall.
    part = max(1, len(curve.v) // 20)
    v0, v1 = float(np.median(curve.v[:part])), float(np.median(curve.v[-part:]))
    if v1 < v0 * (1.0 - _FALL_FRACTION) and float(np.percentile(curve.v, 90)) <= v0 * (1.0 + _RISE_FRACTION):
        return v0, v1
    return None


def require_discharge(curve: Curve) -> None:
    """Refuse, in words, a curve that is no discharge."""
    name = curve.name or "curve"
    mah = float(curve.delivered_mah[-1])
    if mah < _MIN_CHARGE_MAH:
        raise CurveError(_("{name}: nothing to fit: the curve takes out only {mah:.2f} mAh").format(name=name, mah=mah))
    part = max(1, len(curve.v) // 20)
    v0, v1 = float(np.median(curve.v[:part])), float(np.median(curve.v[-part:]))
    if v1 > v0 * (1.0 + _FALL_FRACTION) and float(np.percentile(curve.v, 10)) >= v0 * (1.0 - _RISE_FRACTION):
        raise CurveError(_("{name}: the voltage rises all the way, from {v0:.2f} V to {v1:.2f} V: a charge, not a "
                           "discharge (its current is negative)").format(name=name, v0=v0, v1=v1))


def charge_from_log(log: Log, name: str = "") -> Curve:
    """The longest charge in the log (phases of state "charge" closer than two minutes merged)."""
    return _longest(log, "charge", name)


def discharge_from_log(log: Log, name: str = "") -> Curve:
    """The longest discharge in the log, its current negative. A log without a direction (an AkkuMaster
    "Entladen" export) calls its discharge a charge: a "charge" whose voltage falls all the way is taken."""
    if (log.states() == STATES.index("discharge")).any():
        return _longest(log, "discharge", name)
    try:
        curve = _longest(log, "charge", name)
    except CurveError:
        curve = None
    if curve is None or not falls_all_the_way(curve):
        raise CurveError(_("{value}: no discharge in the log").format(value=name or 'log'))
    return _negated(curve)


def curve_from_log(log: Log, name: str = "", direction: str | None = None) -> Curve:
    """The log's charge or discharge; without a direction its charge where it has one (a charge that
    falls all the way is a discharge without a direction column), else its discharge."""
    if direction == "charge":
        return charge_from_log(log, name)
    if direction == "discharge":
        return discharge_from_log(log, name)
    try:
        curve = charge_from_log(log, name)
    except CurveError:
        return discharge_from_log(log, name)
    return _negated(curve) if falls_all_the_way(curve) else curve


def log_directions(log: Log) -> list[str]:
    """Which of charge and discharge the log holds (a "charge" that falls all the way is a discharge)."""
    held = []
    for direction in DIRECTIONS:
        try:
            curve = curve_from_log(log, "", direction)
        except CurveError:
            continue
        if direction == "discharge" or not falls_all_the_way(curve):
            held.append(direction)
    return held


def _negated(curve: Curve) -> Curve:
    return Curve(curve.t, curve.v, -np.abs(curve.i), curve.temp, curve.cells, curve.name, curve.chemistry,
                 curve.start_s)


def _longest(log: Log, section: str, name: str) -> Curve:
    """The longest phase of ``section`` in the log (phases closer than two minutes merged); its current
    positive for a charge, negative for a discharge."""
    a = log.arrays()
    charging = log.states() == STATES.index(section)
    if not charging.any():
        raise CurveError((_("{value}: no charge in the log") if section == "charge" else
                          _("{value}: no discharge in the log")).format(value=name or 'log'))
    runs: list[list[int]] = []
    for k in np.flatnonzero(charging):
        if runs and a["t"][k] - a["t"][runs[-1][1]] <= _MERGE_GAP_S:
            runs[-1][1] = k
        else:
            runs.append([k, k])
    lo, hi = max(runs, key=lambda r: a["t"][r[1]] - a["t"][r[0]])
    sel = np.arange(lo, hi + 1)
    # A sample without a voltage or a current (a torn record) is no sample of the charge; nor is the
    # second of two at one instant (a session's next run starts when the last ended).
    sel = sel[charging[sel] & np.isfinite(a["voltage"][sel]) & np.isfinite(a["current"][sel])]
    sel = sel[np.concatenate(([True], np.diff(a["t"][sel]) > 0))] if len(sel) else sel
    if not len(sel):
        raise CurveError((_("{value}: no charge in the log") if section == "charge" else
                          _("{value}: no discharge in the log")).format(value=name or 'log'))
    t = a["t"][sel]
    sign = 1.0 if section == "charge" else -1.0
    return Curve(t - t[0], a["voltage"][sel], sign * np.abs(a["current"][sel]), _sensor(t, a["temp"][sel]),
                 log.cells, name, str(log.meta.get("battery", "")), float(t[0]),
                 a["cells"][sel] if log.cells else None)


def _sensor(t: np.ndarray, temp: np.ndarray) -> np.ndarray | None:
    """The temperature channel, None where the log has none worth the name (mostly missing, or flat).
    A lone sample far from both neighbours is a dropout, not the pack (the iCharger 308DUO log reads
    0 °C for one second amid 22 °C): it and missing samples take the line between their neighbours."""
    ok = np.isfinite(temp)
    if ok.sum() <= len(temp) // 2:
        return None
    inner = np.abs(temp[1:-1] - temp[:-2]), np.abs(temp[1:-1] - temp[2:])
    ok[1:-1] &= ~((inner[0] > _DROPOUT_C) & (inner[1] > _DROPOUT_C))
    clean = np.interp(t, t[ok], temp[ok])
    return clean if clean.max() > clean.min() else None


def read_curve_csv(text: str, name: str = "") -> Curve:
    """A plain curve CSV (see module doc)."""
    # Errors name the file's own line numbers (comment and blank lines counted).
    kept = [(k, ln) for k, ln in enumerate(text.splitlines(), start=1)
            if ln.strip() and not ln.lstrip().startswith("#")]
    reader = csv.reader(ln for _k, ln in kept)
    rows, at = [], []
    try:
        for row in reader:
            rows.append(row)
            at.append(kept[reader.line_num - 1][0])
    except csv.Error as exc:           # a field past the csv module's limit (128 KiB)
        raise CurveError(_("{name}: data line {n}: {error}").format(name=name, n=kept[reader.line_num - 1][0],
                                                                    error=exc)) from None
    if not rows or tuple(c.strip() for c in rows[0][:3]) != CURVE_COLUMNS:
        raise CurveError(_("{name}: a curve CSV starts with the header {csv_columns}[,temp_c]").format(
                name=name, csv_columns=','.join(CURVE_COLUMNS)))
    has_temp = len(rows[0]) > 3 and rows[0][3].strip() == TEMP_C
    cols: list[list[float]] = [[], [], [], []]
    for n, row in zip(at[1:], rows[1:]):
        try:
            values = [float(x) for x in row[:4 if has_temp else 3]]
        except ValueError:
            # A line without its line ends can be the rest of the file: its fields are shown cut.
            shown = [f if len(f) <= _SHOWN_FIELD else f[:_SHOWN_FIELD] + "…" for f in row[:5]]
            raise CurveError(_("{name}: data line {n}: not a number in {row!r}").format(
                    name=name, n=n, row=shown)) from None
        if len(values) < (4 if has_temp else 3) or not all(math.isfinite(x) for x in values):
            raise CurveError(_("{name}: data line {n}: expected {value} finite numbers").format(
                    name=name, n=n, value=4 if has_temp else 3))
        for c, x in zip(cols, values):
            c.append(x)
    t = np.array(cols[0])
    _check_values(name, {TIME_S: t, VOLTAGE_V: np.array(cols[1]),
                         CURRENT_A: np.array(cols[2]), TEMP_C: np.array(cols[3]) if has_temp else None},
                  lambda k: _("data line {n}").format(n=at[k + 1]))
    return Curve(t - t[0] if len(t) else t, np.array(cols[1]), np.array(cols[2]),
                 np.array(cols[3]) if has_temp else None, 0, name)


def read_curve(path: str | Path, direction: str | None = None) -> Curve:
    """A charge or discharge (``direction``; None: as ``curve_from_log`` picks) from any log file the log
    readers know, else from a plain curve CSV (its current's sign says which)."""
    return read_curve_and_log(path, direction)[0]


def read_curve_and_log(path: str | Path, direction: str | None = None) -> tuple[Curve, Log | None]:
    """``read_curve`` and the whole log it came from (None for a curve CSV): its rests lie outside the curve."""
    p = Path(path)
    data = read_file_bytes(p)
    text = data.decode("utf-8", "replace")
    first = next((ln for ln in text.splitlines() if ln.strip() and not ln.lstrip().startswith("#")), "")
    if first.lstrip().startswith(TIME_S):
        # The plain curve CSV is read as itself, strictly (a bad value is its line), before the
        # log readers' general CSV import would guess its columns and leave bad samples out.
        return read_curve_csv(text, p.name), None
    try:
        log = read_log(data, p.name)
        return curve_from_log(log, p.name, direction), log
    except LogFormatError as exc:
        raise CurveError(_("{name}: {reason}; nor a curve CSV (its header: {csv_columns}[,temp_c])").format(
                name=p.name, reason=exc, csv_columns=",".join(CURVE_COLUMNS))) from None
