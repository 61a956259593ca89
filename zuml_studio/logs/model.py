"""What reading a log gives: ``Log`` (samples as ``Telemetry``, bad records, charger, metadata),
its phases, and ``SampleBuilder``, which every reader fills column by column."""
from __future__ import annotations

import datetime as dt
import math
from collections.abc import Sequence
from dataclasses import dataclass, field, replace

import numpy as np

from ..device.messages import Telemetry
from .charge import charge_from_counter, disagreement, integrate_current
from ..i18n import _, ngettext

# Volts and amperes beyond any charger (as sim.curve's limits): a sample past them is left out.
MAX_MEASURED = 2000.0
# No cell of any chemistry reads more (LiHV ends at 4.35 V): a per-cell column above it is not a cell.
MAX_CELL_V = 5.0
# The states a log sample can be in; every format maps its own onto these.
STATES = ("charge", "discharge", "pause", "idle")
SECTION_OF = {"charge": "charge", "discharge": "discharge"}


class LogFormatError(ValueError):
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


@dataclass(frozen=True)
class Log:
    format: str
    device: str
    samples: tuple[Telemetry, ...]
    bad_records: int = 0
    meta: dict = field(default_factory=dict)
    # Internal-resistance readings where the charger logs them: (time_s, pack mΩ or None, cells mΩ).
    resistance: tuple[tuple[float, float | None, tuple[float, ...]], ...] = ()

    @property
    def cells(self) -> int:
        return max((len(s.cells_v) for s in self.samples), default=0)

    def arrays(self) -> dict[str, np.ndarray]:
        """Columns for plotting: t, voltage, current, temp and heatsink (NaN: not measured),
        cells (samples × cells, NaN where a sample has fewer). Made once (the log never
        changes; a long one takes a good part of a second), so read-only."""
        made = self.__dict__.get("_arrays")
        if made is None:
            made = self._make_arrays()
            for column in made.values():
                column.flags.writeable = False
            object.__setattr__(self, "_arrays", made)       # a cache, not a field: frozen all the same
        return dict(made)

    def _make_arrays(self) -> dict[str, np.ndarray]:
        s = self.samples
        nan = math.nan
        cells = np.full((len(s), self.cells), nan)
        for k, x in enumerate(s):
            cells[k, :len(x.cells_v)] = x.cells_v
        return {
            "t": np.fromiter((x.time_s for x in s), float, len(s)),
            "voltage": np.fromiter((x.voltage_v for x in s), float, len(s)),
            "current": np.fromiter((x.current_a for x in s), float, len(s)),
            "temp": np.fromiter((nan if x.temp_c is None else x.temp_c for x in s), float, len(s)),
            "heatsink": np.fromiter((nan if x.heatsink_c is None else x.heatsink_c for x in s), float, len(s)),
            "cells": cells,
        }

    def phases(self) -> list[Phase]:
        """Consecutive samples in one state; a phase ends where the next begins."""
        made = self.__dict__.get("_phases")
        if made is None:
            made = self._make_phases()
            object.__setattr__(self, "_phases", made)
        return list(made)

    def _make_phases(self) -> list[Phase]:
        out: list[Phase] = []
        counts: dict[str, int] = {}
        for s in self.samples:
            state = state_of(s)
            if out and out[-1].state == state:
                out[-1] = Phase(state, out[-1].start_s, s.time_s, out[-1].index)
                continue
            if out:
                out[-1] = Phase(out[-1].state, out[-1].start_s, s.time_s, out[-1].index)
            counts[state] = counts.get(state, 0) + 1
            out.append(Phase(state, s.time_s, s.time_s, counts[state]))
        return out


def in_time_order(times: Sequence[float]) -> tuple[list[float] | None, dict | None]:
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
    return shifted.tolist(), note


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
    follows the last (``in_time_order``, said in ``meta["time_order"]``)."""
    placed, note = in_time_order([s.time_s for s in samples])
    if placed is not None:
        samples = [replace(s, time_s=t) for s, t in zip(samples, placed)]
        meta["time_order"] = note
    width = connected_cells([s.cells_v for s in samples])
    cut = [s if len(s.cells_v) <= width else replace(s, cells_v=s.cells_v[:width]) for s in samples]
    if cut and all(s.temp_c == 0.0 for s in cut):           # 0 throughout: no probe
        cut = [replace(s, temp_c=None, sensor=False) for s in cut]
    if cut:
        q_in, q_out, differ = _driver_charge(cut)
        cut = [replace(s, mah_in=a, mah_out=b) for s, a, b in zip(cut, q_in, q_out)]
        if differ is not None:
            meta["charge_check"] = differ
    return Log(fmt, device, tuple(cut), bad_records, dict(meta))


def _driver_charge(samples: Sequence[Telemetry]) -> tuple[list[float], list[float], dict | None]:
    """A driver's samples' charge as a reader's (``SampleBuilder._charge``): the current integrated,
    compared with the driver's counter, which is counted from its first value; the counter alone
    where no current is logged."""
    in0, out0 = samples[0].mah_in, samples[0].mah_out
    counted = ([s.mah_in - in0 for s in samples], [s.mah_out - out0 for s in samples])
    currents = [s.current_a for s in samples]
    if not any(currents):
        return counted[0], counted[1], None
    q_in, q_out = integrate_current([s.time_s for s in samples], currents)
    return q_in, q_out, disagreement((q_in[-1], q_out[-1]), (counted[0][-1], counted[1][-1]))


def connected_cells(cells: Sequence[Sequence[float]]) -> int:
    """How many per-cell columns to keep: those at the end that read 0 V in every sample are
    balance taps not connected; none when a column reads more than any cell can hold (an iCharger
    charging NiMH sends 5.2 V in its first cell slot: a 4-cell pack is not one cell)."""
    if any(v > MAX_CELL_V for c in cells for v in c):
        return 0
    width = max((len(c) for c in cells), default=0)
    while width and all(len(c) < width or c[width - 1] == 0.0 for c in cells):
        width -= 1
    return width


class SampleBuilder:
    """Columns of one log as a reader decodes them; ``build`` turns them into Telemetry.

    Charge: an explicit cumulative in/out wins, else the integral of the current, compared with
    the charger's (signed, per-phase) counter where there is one, else that counter's difference
    (``charge.py``). Per-cell columns that are
    zero in every sample at the end of the list (balance taps not connected) are dropped."""

    def __init__(self) -> None:
        self.t: list[float] = []
        self.v: list[float] = []
        self.i: list[float] = []
        self.state: list[str] = []
        self.temp: list[float | None] = []
        self.heatsink: list[float | None] = []
        self.cells: list[tuple[float, ...]] = []
        self.counter: list[float | None] = []
        self.q_in: list[float | None] = []
        self.q_out: list[float | None] = []
        self.cycle: list[int] = []
        # Samples left out for a voltage or current no charger measures: (how many, the first's number).
        self.out_of_range = (0, 0)

    def __len__(self) -> int:
        return len(self.t)

    def add(self, t: float, v: float, i: float, state: str, *, temp: float | None = None,
            heatsink: float | None = None, cells: Sequence[float] = (), counter: float | None = None,
            mah_in: float | None = None, mah_out: float | None = None, cycle: int = 0) -> None:
        for name, value in (("time", t), ("voltage", v), ("current", i)):
            if not math.isfinite(value):
                raise LogFormatError(_("sample {n_t}: {name} is {value}").format(
                        n_t=len(self.t) + 1, name=name, value=value))
        if state not in STATES:
            raise ValueError(f"state {state!r}")
        if abs(v) > MAX_MEASURED or abs(i) > MAX_MEASURED:      # 1e308 V: a damaged record, not a pack
            count, first = self.out_of_range
            self.out_of_range = (count + 1, first or len(self.t) + count + 1)
            return
        self.t.append(float(t))
        self.v.append(float(v))
        self.i.append(float(i))
        self.state.append(state)
        self.temp.append(_finite(temp))
        self.heatsink.append(_finite(heatsink))
        self.cells.append(tuple(float(c) for c in cells))
        self.counter.append(_finite(counter))
        self.q_in.append(_finite(mah_in))
        self.q_out.append(_finite(mah_out))
        self.cycle.append(int(cycle))

    def _charge(self) -> tuple[list[float], list[float], dict | None]:
        """(in, out, disagreement): explicit totals (our own session CSV) win; else the current
        integrated, compared with the counter where there is one; else the counter's difference."""
        n = len(self.t)
        if n and all(q is not None for q in self.q_in) and all(q is not None for q in self.q_out):
            return list(self.q_in), list(self.q_out), None
        counted = charge_from_counter(self.counter) if n and all(c is not None for c in self.counter) else None
        if counted is not None and not any(self.i):
            return counted[0], counted[1], None
        q_in, q_out = integrate_current(self.t, self.i)
        if counted is None or not n:
            return q_in, q_out, None
        return q_in, q_out, disagreement((q_in[-1], q_out[-1]), (counted[0][-1], counted[1][-1]))

    def build(self, fmt: str, device: str, bad_records: int = 0, *, resistance=(), **meta) -> Log:
        placed, note = in_time_order(self.t)
        if placed is not None:
            self.t[:] = placed
            meta["time_order"] = note
        if self.out_of_range[0]:
            meta["out_of_range"] = {"left_out": self.out_of_range[0], "first_sample": self.out_of_range[1]}
        if self.temp and all(x == 0.0 for x in self.temp):
            self.temp[:] = [None] * len(self.temp)      # a probe column that reads 0 throughout: no probe
        q_in, q_out, differ = self._charge()
        if differ is not None:
            meta["charge_check"] = differ
        width = connected_cells(self.cells)
        samples = []
        runs = 0
        section_count = {"charge": 0, "discharge": 0}
        prev = None
        phase = 0
        for k, state in enumerate(self.state):
            section = SECTION_OF.get(state, "")
            if state != prev:
                if section:
                    runs += 1
                    section_count[section] += 1
                    phase = section_count[section]
                prev = state
            cells = self.cells[k][:width]
            if len(cells) < width:
                cells = cells + (0.0,) * (width - len(cells))
            temp = self.temp[k]
            samples.append(Telemetry(
                time_s=self.t[k], task="discharge" if section == "discharge" else "charge", section=section,
                repetition=0, cycle=self.cycle[k], phase=phase if section else 0, run=runs if section else 0,
                running=state in ("charge", "discharge", "pause"), paused=state == "pause",
                sensor=temp is not None, voltage_v=self.v[k], current_a=self.i[k], temp_c=temp,
                heatsink_c=self.heatsink[k], mah_in=q_in[k], mah_out=q_out[k], cells_v=cells))
        return Log(fmt, device, tuple(samples), bad_records, dict(meta), tuple(resistance))


def _finite(value: float | None) -> float | None:
    if value is None:
        return None
    value = float(value)
    return value if math.isfinite(value) else None


def state_from_current(current_a: float, threshold_a: float = 0.005) -> str:
    """For formats that say nothing about the state: the sign of the current."""
    if current_a > threshold_a:
        return "charge"
    if current_a < -threshold_a:
        return "discharge"
    return "idle"
