"""One sample per tick, stored by column in compact numpy chunks; float64 arrays and CSV on
demand.

A 200 h training at a 1 s tick is 720 000 ticks: as Python floats in lists that cost ~225
bytes a tick, here it is 30. The hot loop appends to ``array.array`` staging columns (as
cheap as appending to a list); the interpreter seals a full staging chunk (``CHUNK`` ticks)
into numpy arrays between its runs of ticks:

- time: the chunk's first time (float64) and float32 offsets from it (a chunk spans at most
  CHUNK ticks, so an offset is exact to a few milliseconds even at a 60 s tick);
- phase: the chunk's first phase number and uint16 offsets from it (a chunk cannot hold
  more than CHUNK phases);
- section: once per phase, not per tick (a phase runs in one section; a log that breaks
  this is refused, never stored wrong);
- voltage, current, temperatures, mAh in and out: float32 (seven significant digits; the
  charger's ADC has ten to twelve bits).

A pack of more than one cell adds ``cell1_v`` … ``cellN_v`` (cell k the k-th from the pack's
negative end) and ``balance_mask`` (bit k-1 set while cell k bleeds). A pack of unequal cells
(``per_cell``) stores them, float32 and uint32, 4 N + 4 bytes a tick more; for identical cells
they are the pack voltage / N and 0, made when read.
"""
from __future__ import annotations

import csv
from array import array
from dataclasses import dataclass
from typing import Mapping, NamedTuple, TextIO

import numpy as np
from ..i18n import _

COLUMNS = ("time_s", "section", "phase", "voltage_v", "current_a", "temp_c", "heatsink_c", "mah_in", "mah_out")
SECTION_NAMES = ("discharge", "charge")
MEASURED = COLUMNS[3:]
CHUNK = 16_384           # ticks per sealed chunk: < 65 536 (uint16 phase offsets)
BALANCE_MASK = "balance_mask"
_TYPES = {"d": np.float64, "b": np.int8, "q": np.int64, "f": np.float32, "I": np.uint32}   # of the staging arrays


def cell_columns(cells: int) -> tuple[str, ...]:
    """``cell1_v`` … ``cellN_v`` and ``balance_mask`` for a pack of more than one cell, else ()."""
    return tuple(f"cell{k}_v" for k in range(1, cells + 1)) + (BALANCE_MASK,) if cells > 1 else ()


class Sample(NamedTuple):
    time_s: float
    section: int          # 0 discharge, 1 charge
    phase: int            # run number of the phase, 1-based
    voltage_v: float
    current_a: float      # signed: + charge, - discharge
    temp_c: float
    heatsink_c: float
    mah_in: float
    mah_out: float


@dataclass(frozen=True)
class _Chunk:
    t0: float
    t_off: np.ndarray                 # float32
    phase0: int
    phase_off: np.ndarray             # uint16
    measured: dict[str, np.ndarray]   # float32 each (balance_mask: uint32)

    def __len__(self) -> int:
        return len(self.t_off)


class SampleLog:
    def __init__(self, cells: int = 0, per_cell: bool = False) -> None:
        """``cells``: the pack's cell count (more than one adds the per-cell columns); ``per_cell``:
        its cells differ, and ``append_cells`` gives their voltages and the balancer's mask each tick."""
        self._chunks: list[_Chunk] = []
        self._sealed = 0
        self._sections: dict[int, int] = {}      # phase -> section
        extra = cell_columns(cells)
        self.cells = cells if extra else 0
        self.columns = COLUMNS + extra
        self.per_cell = bool(per_cell and extra)     # False: every cell reads the pack's voltage / cells
        self._stored = MEASURED + (extra if per_cell else ())
        self._stage = {"time_s": array("d"), "section": array("b"), "phase": array("q"),
                       **{name: array("I" if name == BALANCE_MASK else "f") for name in self._stored}}
        if per_cell and extra:
            cell_appends = [self._stage[name].append for name in extra[:-1]]
            mask_append = self._stage[BALANCE_MASK].append

            def append_cells(volts, mask: int) -> None:
                for add, v in zip(cell_appends, volts):
                    add(v)
                mask_append(mask)

            self.append_cells = append_cells
        cols = [self._stage[name].append for name in COLUMNS]
        t, s, p, v, i, tc, hs, qi, qo = cols

        def append(time_s, section, phase, voltage_v, current_a, temp_c, heatsink_c, mah_in, mah_out) -> None:
            t(time_s); s(section); p(phase); v(voltage_v); i(current_a)
            tc(temp_c); hs(heatsink_c); qi(mah_in); qo(mah_out)

        self.append = append

    def __len__(self) -> int:
        return self._sealed + len(self._stage["time_s"])

    # -- writing -----------------------------------------------------------------------------
    def append_block(self, columns: Mapping[str, np.ndarray]) -> None:
        """Many ticks at once (the C engine's, sim/engine.py): each stored column an array, all as long;
        at most ``room`` ticks, so the chunks are those ``append`` makes."""
        for name, column in self._stage.items():
            column.frombytes(np.ascontiguousarray(columns[name], _TYPES[column.typecode]).tobytes())

    @property
    def room(self) -> int:
        """Ticks that still fit in the staging chunk (at least 1)."""
        return max(1, CHUNK - len(self._stage["time_s"]))

    def seal_if_full(self) -> None:
        if len(self._stage["time_s"]) >= CHUNK:
            self.seal()

    def seal(self) -> None:
        """Store the staged samples compactly now (a run that has ended appends no more)."""
        stage = self._stage
        n = len(stage["time_s"])
        if not n:
            return
        # copies: a staging array cannot be emptied while numpy views of it live
        t = np.array(stage["time_s"], np.float64)
        phase = np.array(stage["phase"], np.int64)
        section = np.array(stage["section"], np.int8)
        spans = [(a, min(n, a + CHUNK)) for a in range(0, n, CHUNK)]
        if any(int(np.ptp(phase[a:b])) > np.iinfo(np.uint16).max for a, b in spans):
            raise ValueError(_("more than 65 536 phase numbers in one chunk of samples"))
        self._learn_sections(phase, section)
        for a, b in spans:
            t0, phase0 = float(t[a]), int(phase[a:b].min())
            self._chunks.append(_Chunk(t0, (t[a:b] - t0).astype(np.float32), phase0,
                                       (phase[a:b] - phase0).astype(np.uint16),
                                       {name: _view(stage[name])[a:b].copy() for name in self._stored}))
        self._sealed += n
        for column in stage.values():
            del column[:]

    def _learn_sections(self, phase: np.ndarray, section: np.ndarray) -> None:
        if not len(phase):
            return
        if np.any((section[1:] != section[:-1]) & (phase[1:] == phase[:-1])):
            raise ValueError(_("a phase's samples must all be in one section"))
        for k in np.flatnonzero(np.r_[True, phase[1:] != phase[:-1]]):
            number, sec = int(phase[k]), int(section[k])
            if self._sections.setdefault(number, sec) != sec:
                raise ValueError(_("phase {number} has samples in two sections").format(number=number))

    def keep_last(self) -> None:
        """Forget every sample but the newest (a stream that does not store)."""
        if len(self) > 1:
            last = self.last()
            cells = self.arrays(len(self) - 1) if self._stored != MEASURED else None
            self._chunks.clear()
            self._sealed = 0
            for column in self._stage.values():
                del column[:]
            self.append(*last)
            if cells is not None:
                self.append_cells([float(cells[name][0]) for name in self.columns[len(COLUMNS):-1]],
                                  int(cells[BALANCE_MASK][0]))

    # -- reading -----------------------------------------------------------------------------
    def last(self) -> Sample:
        """The newest sample (IndexError if there is none)."""
        stage = self._stage
        if len(stage["time_s"]):
            return Sample(*(stage[name][-1] for name in COLUMNS))
        c = self._chunks[-1]
        phase = c.phase0 + int(c.phase_off[-1])
        return Sample(c.t0 + float(c.t_off[-1]), self._sections[phase], phase,
                      *(float(c.measured[name][-1]) for name in MEASURED))

    def arrays(self, start: int = 0, stop: int | None = None) -> dict[str, np.ndarray]:
        """Every column for samples ``start`` to ``stop``: float64, section, phase and balance_mask as integers."""
        stage = self._stage
        self._learn_sections(np.frombuffer(stage["phase"], np.int64), np.frombuffer(stage["section"], np.int8))
        stop = len(self) if stop is None else min(stop, len(self))
        parts: dict[str, list[np.ndarray]] = {name: [] for name in ("time_s", "phase") + self._stored}
        at = 0
        for c in self._chunks:
            a, b = max(0, start - at), min(len(c), stop - at)
            at += len(c)
            if a >= b:
                continue
            parts["time_s"].append(c.t0 + c.t_off[a:b].astype(np.float64))
            parts["phase"].append(c.phase0 + c.phase_off[a:b].astype(np.int64))
            for name in self._stored:
                parts[name].append(c.measured[name][a:b].astype(np.float64))
        a, b = max(0, start - at), max(0, stop - at)
        parts["time_s"].append(np.frombuffer(stage["time_s"], np.float64)[a:b].copy())
        parts["phase"].append(np.frombuffer(stage["phase"], np.int64)[a:b].copy())
        for name in self._stored:
            parts[name].append(_view(stage[name])[a:b].astype(np.float64))
        out = {name: np.concatenate(chunks) for name, chunks in parts.items()}
        out["section"] = self._section_of(out["phase"])
        if self.cells and BALANCE_MASK not in out:
            # identical cells: each is the pack's share, and nothing bleeds
            for name in self.columns[len(COLUMNS):-1]:
                out[name] = out["voltage_v"] / self.cells
            out[BALANCE_MASK] = np.zeros(len(out["phase"]))
        if self.cells:
            out[BALANCE_MASK] = out[BALANCE_MASK].astype(np.int64)
        return {name: out[name] for name in self.columns}

    def _section_of(self, phase: np.ndarray) -> np.ndarray:
        if not len(phase):
            return np.zeros(0, np.int64)
        table = np.zeros(max(self._sections, default=0) + 1, np.int64)
        for number, sec in self._sections.items():
            table[number] = sec
        return table[phase]

    def column(self, name: str) -> np.ndarray:
        return self.arrays()[name]

    time_s = property(lambda self: self.column("time_s"))
    section = property(lambda self: self.column("section"))
    phase = property(lambda self: self.column("phase"))
    voltage_v = property(lambda self: self.column("voltage_v"))
    current_a = property(lambda self: self.column("current_a"))
    temp_c = property(lambda self: self.column("temp_c"))
    heatsink_c = property(lambda self: self.column("heatsink_c"))
    mah_in = property(lambda self: self.column("mah_in"))
    mah_out = property(lambda self: self.column("mah_out"))

    def nbytes(self) -> int:
        """Bytes the samples take (sealed chunks and the staging chunk)."""
        sealed = sum(c.t_off.nbytes + c.phase_off.nbytes + sum(a.nbytes for a in c.measured.values())
                     for c in self._chunks)
        return sealed + sum(col.itemsize * len(col) for col in self._stage.values())

    def write_csv(self, stream: TextIO) -> None:
        writer = csv.writer(stream, lineterminator="\n")
        writer.writerow(self.columns)
        n = len(self)
        for a in range(0, n, CHUNK):
            cols = self.arrays(a, a + CHUNK)
            rows = zip(*(cols[name].tolist() for name in COLUMNS))
            lines = [(f"{t:.1f}", SECTION_NAMES[s], p, f"{v:.4f}", f"{i:.4f}", f"{tc:.2f}", f"{hs:.2f}",
                      f"{qi:.1f}", f"{qo:.1f}") for t, s, p, v, i, tc, hs, qi, qo in rows]
            if self.cells:
                cells = zip(*(cols[name].tolist() for name in self.columns[len(COLUMNS):-1]))
                lines = [line + tuple(f"{v:.4f}" for v in volts) + (mask,)
                         for line, volts, mask in zip(lines, cells, cols[BALANCE_MASK].tolist())]
            writer.writerows(lines)


def _view(column: array) -> np.ndarray:
    return np.frombuffer(column, np.uint32 if column.typecode == "I" else np.float32)
