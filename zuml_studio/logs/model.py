"""What reading a log gives: ``Log`` (its samples as numpy ``Columns``, each a ``Telemetry`` when asked
for; bad records, charger, metadata), its phases, and ``SampleBuilder``, which every reader fills row by
row or a block of columns at a time."""
from __future__ import annotations

import datetime as dt
import math
from array import array
from collections.abc import Sequence
from dataclasses import dataclass, field, fields, replace

import numpy as np

from ..protocol.messages import Telemetry
from .charge import charge_from_counter, counter_totals, disagreement, integrate_current
from ..errors import ZumlError
from ..i18n import _, ngettext

# Volts and amperes beyond any charger (as sim.curve's limits): a sample past them is left out.
MAX_MEASURED = 2000.0
# No cell of any chemistry reads more (LiHV ends at 4.35 V): a per-cell column above it is not a cell.
MAX_CELL_V = 5.0
# The states a log sample can be in; every format maps its own onto these.
STATES = ("charge", "discharge", "pause", "idle")
SECTION_OF = {"charge": "charge", "discharge": "discharge"}


class LogFormatError(ZumlError, ValueError):
    """The bytes are not a log this reader understands; the message says where and why."""


@dataclass(frozen=True)
class Phase:
    """A stretch of samples in one state; ``index`` counts the phases of that state from 1."""
    state: str
    start_s: float
    end_s: float
    index: int = 0

    def as_dict(self) -> dict:
        return {"state": self.state, "start_s": round(self.start_s, 3), "end_s": round(self.end_s, 3)}


def state_of(t: Telemetry) -> str:
    """One of ``STATES`` for a sample (also for samples from live drivers)."""
    if t.paused:
        return "pause"
    if not t.running:
        return "idle"
    return t.section if t.section in SECTION_OF else "idle"


# A column absent from a log: NaN at no memory cost (read-only, as every column of a Log).
def _absent(n: int) -> np.ndarray:
    return np.broadcast_to(np.float64(math.nan), (n,))


@dataclass(frozen=True, eq=False)
class Columns:
    """A log's samples, one numpy array per quantity (a 100 MB CSV is read in a few times its size, where a
    Telemetry per row took 25 times). ``temp`` and ``heatsink`` are NaN where not measured; ``cells`` is
    samples × cells; ``state`` indexes ``STATES``; ``phase`` and ``run`` count as ``Telemetry``'s do."""
    t: np.ndarray
    voltage: np.ndarray
    current: np.ndarray
    temp: np.ndarray
    heatsink: np.ndarray
    mah_in: np.ndarray
    mah_out: np.ndarray
    cells: np.ndarray
    state: np.ndarray
    cycle: np.ndarray
    phase: np.ndarray
    run: np.ndarray

    def __post_init__(self) -> None:
        for f in fields(self):
            getattr(self, f.name).flags.writeable = False

    def __len__(self) -> int:
        return len(self.t)

    def sample(self, k: int) -> Telemetry:
        """Sample ``k`` as the one sample type the plot, the CSV, the logbook and the CLI share."""
        state = STATES[self.state[k]]
        section = SECTION_OF.get(state, "")
        temp, heatsink = float(self.temp[k]), float(self.heatsink[k])
        return Telemetry(
            time_s=float(self.t[k]), task="discharge" if section == "discharge" else "charge", section=section,
            repetition=0, cycle=int(self.cycle[k]), phase=int(self.phase[k]), run=int(self.run[k]),
            running=state in ("charge", "discharge", "pause"), paused=state == "pause",
            sensor=not math.isnan(temp), voltage_v=float(self.voltage[k]), current_a=float(self.current[k]),
            temp_c=None if math.isnan(temp) else temp, heatsink_c=None if math.isnan(heatsink) else heatsink,
            mah_in=float(self.mah_in[k]), mah_out=float(self.mah_out[k]), cells_v=tuple(self.cells[k].tolist()))

    def window(self, lo: int, hi: int) -> "Columns":
        """Samples lo..hi-1 (views, no copy)."""
        return Columns(**{f.name: getattr(self, f.name)[lo:hi] for f in fields(self)})


class Samples(Sequence):
    """A Log's samples as ``Telemetry``, made one at a time when asked for (never all held)."""

    def __init__(self, columns: Columns) -> None:
        self._columns = columns

    def __len__(self) -> int:
        return len(self._columns)

    def __getitem__(self, k):
        if isinstance(k, slice):              # as a tuple's slice; a long stretch is better read as columns
            return tuple(self._columns.sample(j) for j in range(*k.indices(len(self))))
        n = len(self)
        if k < 0:
            k += n
        if not 0 <= k < n:
            raise IndexError(k)
        return self._columns.sample(k)

    def __iter__(self):
        for k in range(len(self)):
            yield self._columns.sample(k)


@dataclass(frozen=True, eq=False)
class Log:
    format: str
    device: str
    columns: Columns
    bad_records: int = 0
    meta: dict = field(default_factory=dict)
    # Internal-resistance readings where the charger logs them: (time_s, pack mΩ or None, cells mΩ).
    resistance: tuple[tuple[float, float | None, tuple[float, ...]], ...] = ()

    @property
    def samples(self) -> Samples:
        return Samples(self.columns)

    def __len__(self) -> int:
        return len(self.columns)

    @property
    def cells(self) -> int:
        return int(self.columns.cells.shape[1])

    def arrays(self) -> dict[str, np.ndarray]:
        """Columns for plotting: t, voltage, current, temp and heatsink (NaN: not measured),
        cells (samples × cells); read-only views of the log's own."""
        c = self.columns
        return {"t": c.t, "voltage": c.voltage, "current": c.current, "temp": c.temp, "heatsink": c.heatsink,
                "cells": c.cells}

    def states(self) -> np.ndarray:
        """Each sample's state as an index into ``STATES``."""
        return self.columns.state

    def piece(self, lo: int, hi: int) -> "Log":
        """Samples lo..hi-1 as a log of their own, its time and charge counted from its first sample."""
        part = self.columns.window(lo, hi)
        if not len(part):
            return replace(self, columns=part, resistance=())
        return replace(self, columns=replace(part, t=part.t - part.t[0], mah_in=part.mah_in - part.mah_in[0],
                                             mah_out=part.mah_out - part.mah_out[0]), resistance=())

    def head(self, n: int) -> "Log":
        """The first ``n`` samples, as they are."""
        return replace(self, columns=self.columns.window(0, n))

    def phases(self) -> list[Phase]:
        """Consecutive samples in one state; a phase ends where the next begins."""
        made = self.__dict__.get("_phases")
        if made is None:
            made = self._make_phases()
            object.__setattr__(self, "_phases", made)
        return list(made)

    def phase_bounds(self) -> list[tuple[int, int]]:
        """Each phase's samples as (first, after last) indices, in ``phases()``'s order."""
        state = self.columns.state
        if not len(state):
            return []
        starts = [0] + (np.flatnonzero(np.diff(state) != 0) + 1).tolist()
        return list(zip(starts, starts[1:] + [len(state)]))

    def _make_phases(self) -> list[Phase]:
        out: list[Phase] = []
        counts: dict[str, int] = {}
        t, state = self.columns.t, self.columns.state
        for lo, hi in self.phase_bounds():
            name = STATES[state[lo]]
            counts[name] = counts.get(name, 0) + 1
            end = t[hi] if hi < len(t) else t[-1]
            out.append(Phase(name, float(t[lo]), float(end), counts[name]))
        return out


def in_time_order(times: Sequence[float] | np.ndarray) -> tuple[np.ndarray | None, dict | None]:
    """Where time goes back, a new record set starts (a CSV export's next block, a charger's clock reset):
    its samples are moved to follow the previous set's end by one time step (the log's median step),
    so no sample is left out and no duration is negative. Returns the times so placed and a note saying
    where the first fall is and how many record sets there are; (None, None) when time never falls.
    A time repeated is not a fall: a session's next run starts at the instant the last one ended."""
    t = np.asarray(times, float)
    if len(t) < 2:
        return None, None
    steps = np.diff(t)
    falls = np.flatnonzero(steps < 0)
    if not len(falls):
        return None, None
    forward = steps[steps > 0]
    step = float(np.median(forward)) if len(forward) else 1.0
    shifted = t.copy()
    offset = 0.0
    for k in (falls + 1).tolist():
        offset = shifted[k - 1] + step - t[k]
        shifted[k:] = t[k:] + offset
    first = int(falls[0]) + 1
    note = {"first_sample": first + 1, "time_s": float(t[first]), "previous_s": float(t[first - 1]),
            "record_sets": len(falls) + 1, "left_out": 0}
    return shifted, note


def out_of_range_text(note: dict) -> str:
    """The one line a reader of the log is told about samples no charger could have measured."""
    return ngettext("{n} sample with a voltage or current past ±{top:g} (no charger measures that) left out, "
                    "the first at sample {k}",
                    "{n} samples with a voltage or current past ±{top:g} (no charger measures that) left out, "
                    "the first at sample {k}", note["left_out"]).format(
            n=note["left_out"], top=MAX_MEASURED, k=note["first_sample"])


def time_order_text(note: dict) -> str:
    """The one line a reader of the log is told about time that goes back."""
    return ngettext("time goes back at sample {k} ({t:g} s after {prev:g} s): read as {n} record set, "
                    "each following the last; no sample left out",
                    "time goes back at sample {k} ({t:g} s after {prev:g} s): read as {n} record sets, "
                    "each following the last; no sample left out", note["record_sets"]).format(
            k=note["first_sample"], t=note["time_s"], prev=note["previous_s"], n=note["record_sets"])


def started_at_ms(epoch_ms: float) -> str | None:
    """A record set's start time stamp (ms since 1970, UTC) as an ISO date-time, None when implausible."""
    if not 315_532_800_000 <= epoch_ms <= 4_102_444_800_000:       # 1980 to 2100
        return None
    return dt.datetime.fromtimestamp(epoch_ms / 1000.0, dt.timezone.utc).isoformat(timespec="seconds")


def charge_check_text(note: dict) -> str:
    """The one line a reader of the log is told when the charger's counter and the integrated current
    disagree (``charge.disagreement``)."""
    return _("the charger's counter says in {cin:.0f} mAh, out {cout:.0f} mAh, the integrated current in "
             "{iin:.0f}, out {iout:.0f} mAh (shown; they differ by {pct:.0f} %): a gap in the log or a counter "
             "that does not count this charge").format(cin=note["in_counter_mah"], cout=note["out_counter_mah"],
                                         pct=note["difference"] * 100, iin=note["in_integrated_mah"],
                                         iout=note["out_integrated_mah"])


def from_samples(fmt: str, device: str, samples: Sequence[Telemetry], bad_records: int = 0, **meta) -> Log:
    """A Log from ready samples (a live driver's decoder, for instance); cell columns are cut
    to ``connected_cells`` as every reader's are; where time goes back a new record set
    follows the last (``in_time_order``, said in ``meta["time_order"]``). The driver's charge counter
    is compared with the integrated current as a reader's (``SampleBuilder``)."""
    n = len(samples)
    width = max((len(s.cells_v) for s in samples), default=0)
    cells = np.zeros((n, width))
    for k, s in enumerate(samples):
        cells[k, :len(s.cells_v)] = s.cells_v
    temp = np.array([math.nan if s.temp_c is None else s.temp_c for s in samples], float)
    if n and (temp == 0.0).all():                          # 0 throughout: no probe
        temp = _absent(n)
    t = np.array([s.time_s for s in samples], float)
    placed, note = in_time_order(t)
    if placed is not None:
        t = placed
        meta["time_order"] = note
    current = np.array([s.current_a for s in samples], float)
    counted_in = np.array([s.mah_in for s in samples], float)
    counted_out = np.array([s.mah_out for s in samples], float)
    if n:
        counted_in -= counted_in[0]
        counted_out -= counted_out[0]
    if current.any():
        q_in, q_out = integrate_current(t, current)
        differ = disagreement((q_in[-1], q_out[-1]), (counted_in[-1], counted_out[-1]))
        if differ is not None:
            meta["charge_check"] = differ
    else:
        q_in, q_out = counted_in, counted_out
    columns = Columns(
        t=t, voltage=np.array([s.voltage_v for s in samples], float), current=current, temp=temp,
        heatsink=np.array([math.nan if s.heatsink_c is None else s.heatsink_c for s in samples], float),
        mah_in=q_in, mah_out=q_out, cells=cells[:, :connected_cells(cells)],
        state=np.array([STATES.index(state_of(s)) for s in samples], np.int8),
        cycle=np.array([s.cycle for s in samples], np.int32), phase=np.array([s.phase for s in samples], np.int32),
        run=np.array([s.run for s in samples], np.int32))
    return Log(fmt, device, columns, bad_records, dict(meta))


def connected_cells(cells: Sequence[Sequence[float]] | np.ndarray) -> int:
    """How many per-cell columns to keep: those at the end that read 0 V in every sample are
    balance taps not connected; none when a column reads more than any cell can hold (an iCharger
    charging NiMH sends 5.2 V in its first cell slot: a 4-cell pack is not one cell). ``cells``: samples ×
    cells, or one sequence per sample (a shorter one reads 0 V in the cells it lacks)."""
    if not isinstance(cells, np.ndarray):
        width = max((len(c) for c in cells), default=0)
        padded = np.zeros((len(cells), width))
        for k, c in enumerate(cells):
            padded[k, :len(c)] = c
        cells = padded
    if not cells.size:
        return 0
    if (cells > MAX_CELL_V).any():
        return 0
    used = np.flatnonzero((cells != 0.0).any(axis=0))
    return int(used[-1]) + 1 if len(used) else 0


# The builder's columns: (name, array type code, value when not given).
_ROW_COLUMNS = (("t", "d"), ("v", "d"), ("i", "d"), ("state", "b"), ("temp", "d"), ("heatsink", "d"),
                ("counter", "d"), ("q_in", "d"), ("q_out", "d"), ("cycle", "i"))
_OPTIONAL = ("temp", "heatsink", "counter", "q_in", "q_out")


class SampleBuilder:
    """Columns of one log as a reader decodes them, row by row (``add``) or a block of columns at a time
    (``add_columns``: numpy arrays, kept as they are); ``build`` makes the Log's ``Columns``.

    Charge: an explicit cumulative in/out wins, else the integral of the current, compared with
    the charger's (signed, per-phase) counter where there is one, else that counter's difference
    (``charge.py``). Per-cell columns that are
    zero in every sample at the end of the list (balance taps not connected) are dropped."""

    def __init__(self) -> None:
        self._blocks: list[dict] = []
        self._rows = {name: array(code) for name, code in _ROW_COLUMNS}
        self._cells = array("d")
        self._widths = array("H")
        # Samples left out for a voltage or current no charger measures: (how many, the first's number).
        self.out_of_range = (0, 0)
        self._count = 0

    def __len__(self) -> int:
        return self._count

    def last(self, name: str) -> float | None:
        """The last sample's ``t`` or ``counter`` (None: no sample, or no counter)."""
        if self._rows["t"]:
            value = self._rows[name][-1]
        elif self._blocks:
            column = self._blocks[-1].get(name)
            value = None if column is None else float(column[-1])
        else:
            return None
        return None if value is None or math.isnan(value) else value

    def add(self, t: float, v: float, i: float, state: str, *, temp: float | None = None,
            heatsink: float | None = None, cells: Sequence[float] = (), counter: float | None = None,
            mah_in: float | None = None, mah_out: float | None = None, cycle: int = 0) -> None:
        for name, value in (("time", t), ("voltage", v), ("current", i)):
            if not math.isfinite(value):
                raise LogFormatError(_("sample {n_t}: {name} is {value}").format(
                        n_t=self._count + 1, name=name, value=value))
        if state not in STATES:
            raise ValueError(f"state {state!r}")
        if abs(v) > MAX_MEASURED or abs(i) > MAX_MEASURED:      # 1e308 V: a damaged record, not a pack
            count, first = self.out_of_range
            self.out_of_range = (count + 1, first or self._count + count + 1)
            return
        row = self._rows
        row["t"].append(float(t))
        row["v"].append(float(v))
        row["i"].append(float(i))
        row["state"].append(STATES.index(state))
        for name, value in (("temp", temp), ("heatsink", heatsink), ("counter", counter), ("q_in", mah_in),
                            ("q_out", mah_out)):
            row[name].append(_finite(value))
        row["cycle"].append(int(cycle))
        self._cells.extend(float(c) for c in cells)
        self._widths.append(len(cells))
        self._count += 1

    def add_columns(self, t: np.ndarray, v: np.ndarray, i: np.ndarray, state: np.ndarray, *,
                    temp: np.ndarray | None = None, heatsink: np.ndarray | None = None,
                    cells: np.ndarray | None = None, counter: np.ndarray | None = None) -> None:
        """A block of samples as columns (``state``: indices into ``STATES``; None: not logged). Samples
        with a voltage or current past ``MAX_MEASURED`` or not finite are left out and counted as ``add``'s."""
        self._flush()
        for name, column in (("time", t), ("voltage", v), ("current", i)):
            wrong = np.flatnonzero(~np.isfinite(column))
            if len(wrong):
                raise LogFormatError(_("sample {n_t}: {name} is {value}").format(
                        n_t=self._count + int(wrong[0]) + 1, name=name, value=column[wrong[0]]))
        ok = (np.abs(v) <= MAX_MEASURED) & (np.abs(i) <= MAX_MEASURED)
        bad = np.flatnonzero(~ok)
        if len(bad):
            count, first = self.out_of_range
            self.out_of_range = (count + len(bad), first or self._count + count + int(bad[0]) + 1)
            keep = np.flatnonzero(ok)
            pick = lambda a: None if a is None else a[keep]
            t, v, i, state = t[keep], v[keep], i[keep], state[keep]
            temp, heatsink, cells, counter = pick(temp), pick(heatsink), pick(cells), pick(counter)
        if not len(t):
            return
        self._blocks.append({"t": t, "v": v, "i": i, "state": np.asarray(state, np.int8), "temp": temp,
                             "heatsink": heatsink, "counter": counter, "q_in": None, "q_out": None,
                             "cycle": None, "cells": np.zeros((len(t), 0)) if cells is None else cells})
        self._count += len(t)

    def _flush(self) -> None:
        """The rows added one by one so far as a block of columns."""
        rows = self._rows
        n = len(rows["t"])
        if not n:
            return
        block: dict = {name: np.frombuffer(rows[name], np.int8 if code == "b" else np.int32 if code == "i"
                                           else float).copy() for name, code in _ROW_COLUMNS}
        for name in _OPTIONAL:
            if np.isnan(block[name]).all():
                block[name] = None
        widths = np.frombuffer(self._widths, np.uint16)
        width = int(widths.max())
        if (widths == width).all():
            block["cells"] = np.frombuffer(self._cells, float).reshape(n, width).copy()
        else:
            cells = np.zeros((n, width))
            at = 0
            for k, w in enumerate(widths.tolist()):
                cells[k, :w] = self._cells[at:at + w]
                at += w
            block["cells"] = cells
        self._blocks.append(block)
        self._rows = {name: array(code) for name, code in _ROW_COLUMNS}
        self._cells, self._widths = array("d"), array("H")

    def _column(self, name: str, n: int) -> np.ndarray | None:
        """One column over all blocks; None when no block has it; NaN (or 0) where a block lacks it."""
        parts = [b[name] for b in self._blocks]
        if all(p is None for p in parts):
            return None
        if len(parts) == 1:
            return parts[0]
        fill = 0 if name in ("cycle", "state") else math.nan
        return np.concatenate([np.full(len(b["t"]), fill) if p is None else p
                               for b, p in zip(self._blocks, parts)])

    def _cell_columns(self, n: int) -> np.ndarray:
        parts = [b["cells"] for b in self._blocks]
        if len(parts) == 1:
            return parts[0]
        width = max((p.shape[1] for p in parts), default=0)
        return np.concatenate([np.pad(p, ((0, 0), (0, width - p.shape[1]))) for p in parts]) if parts \
            else np.zeros((0, 0))

    @staticmethod
    def _charge(t: np.ndarray, i: np.ndarray, counter: np.ndarray | None, q_in: np.ndarray | None,
                q_out: np.ndarray | None) -> tuple[np.ndarray, np.ndarray, dict | None]:
        """(in, out, disagreement): explicit totals (our own session CSV) win; else the current
        integrated, compared with the counter where there is one; else the counter's difference."""
        n = len(t)
        if n and q_in is not None and q_out is not None and np.isfinite(q_in).all() and np.isfinite(q_out).all():
            return q_in, q_out, None
        counter_ok = n and counter is not None and np.isfinite(counter).all()
        if counter_ok and not i.any():
            ins, outs = charge_from_counter(counter.tolist())
            return np.asarray(ins, float), np.asarray(outs, float), None
        ins, outs = integrate_current(t, i)
        if not counter_ok:
            return ins, outs, None
        return ins, outs, disagreement((ins[-1], outs[-1]), counter_totals(counter))

    def build(self, fmt: str, device: str, bad_records: int = 0, *, resistance=(), **meta) -> Log:
        self._flush()
        n = self._count
        if not self._blocks:
            empty = np.zeros(0)
            columns = Columns(t=empty, voltage=empty, current=empty, temp=empty, heatsink=empty, mah_in=empty,
                              mah_out=empty, cells=np.zeros((0, 0)), state=np.zeros(0, np.int8),
                              cycle=np.zeros(0, np.int32), phase=np.zeros(0, np.int32), run=np.zeros(0, np.int32))
            return Log(fmt, device, columns, bad_records, dict(meta), tuple(resistance))
        t = self._column("t", n)
        placed, note = in_time_order(t)
        if placed is not None:
            t = placed
            meta["time_order"] = note
        if self.out_of_range[0]:
            meta["out_of_range"] = {"left_out": self.out_of_range[0], "first_sample": self.out_of_range[1]}
        temp = self._column("temp", n)
        if temp is None or (temp == 0.0).all():         # a probe column that reads 0 throughout: no probe
            temp = _absent(n)
        heatsink = self._column("heatsink", n)
        i = self._column("i", n)
        q_in, q_out, differ = self._charge(t, i, self._column("counter", n), self._column("q_in", n),
                                           self._column("q_out", n))
        if differ is not None:
            meta["charge_check"] = differ
        cells = self._cell_columns(n)
        state = self._column("state", n)
        cycle = self._column("cycle", n)
        phase, run = _phase_and_run(state)
        voltage = self._column("v", n)
        self._blocks = []
        columns = Columns(t=t, voltage=voltage, current=i, temp=temp,
                          heatsink=_absent(n) if heatsink is None else heatsink, mah_in=q_in, mah_out=q_out,
                          cells=cells[:, :connected_cells(cells)], state=state,
                          cycle=np.broadcast_to(np.int32(0), (n,)) if cycle is None else
                          cycle.astype(np.int32, copy=False),
                          phase=phase, run=run)
        return Log(fmt, device, columns, bad_records, dict(meta), tuple(resistance))

def _phase_and_run(state: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Per sample, as ``Telemetry`` counts them: ``run``, the charge or discharge stretch's number in the
    log from 1, and ``phase``, its number among its kind; 0 for pause and idle."""
    n = len(state)
    if not n:
        return np.zeros(0, np.int32), np.zeros(0, np.int32)
    starts = [0] + (np.flatnonzero(np.diff(state) != 0) + 1).tolist()
    lengths = np.diff(starts + [n])
    runs, phases = [], []
    count = {"charge": 0, "discharge": 0}
    run = 0
    for k in starts:
        section = SECTION_OF.get(STATES[state[k]], "")
        if section:
            run += 1
            count[section] += 1
        runs.append(run if section else 0)
        phases.append(count[section] if section else 0)
    return np.repeat(np.array(phases, np.int32), lengths), np.repeat(np.array(runs, np.int32), lengths)


def _finite(value: float | None) -> float:
    """A value as a float column holds it: NaN where there is none."""
    if value is None:
        return math.nan
    value = float(value)
    return value if math.isfinite(value) else math.nan


def state_from_current(current_a: float, threshold_a: float = 0.005) -> str:
    """For formats that say nothing about the state: the sign of the current."""
    if current_a > threshold_a:
        return "charge"
    if current_a < -threshold_a:
        return "discharge"
    return "idle"


def states_from_current(current_a: np.ndarray, threshold_a: float = 0.005) -> np.ndarray:
    """``state_from_current`` of a column: indices into ``STATES``."""
    out = np.full(len(current_a), STATES.index("idle"), np.int8)
    out[current_a > threshold_a] = STATES.index("charge")
    out[current_a < -threshold_a] = STATES.index("discharge")
    return out
