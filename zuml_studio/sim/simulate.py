"""One call from a record and start parameters to a finished simulation:
builds the battery and charger models and runs the interpreter on the bytes."""
from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Mapping

from ..domain.units import AS_PER_MAH, MAH_PER_AH
from ..lang import opcodes as ops
from ..lang.record import DecodeError
from .battery import Pack
from .cell_pack import CellPack, CellSpec, build_pack, check_cells, spread_cells, weaken
from .charger_model import Charger, ChargerLimits, load_charger
from . import engine as c_engine
from ..domain.chemistry import Chemistry, load_chemistry
from .interpreter import AKK_NAMES, Interpreter, Measurement, PhaseResult, StartError, StartParams, with_template
from .program import Program
from ..domain.start_templates import StartTemplate
from ..errors import ZumlError
from ..i18n import _


# The widest spread drawn: capacity and resistance within ± 50 %, start states within ± 50 points.
SPREAD_MAX_PCT = (50.0, 50.0, 50.0)


def parse_spread(text: str) -> tuple[float, float, float]:
    """A cell spread typed as CAP,R,SOC (three percentages within ``SPREAD_MAX_PCT``); ValueError otherwise."""
    try:
        values = tuple(float(x) for x in text.split(","))
    except ValueError:
        values = ()
    if len(values) != 3 or not all(0.0 <= x <= top for x, top in zip(values, SPREAD_MAX_PCT)):
        raise ValueError(text)
    return values  # type: ignore[return-value]


@dataclass(frozen=True)
class BatterySetup:
    chemistry: str | None = None        # battery model; None: the macro's AKK_TYPE
    soc: float | None = None            # None: empty for charge, full for discharge and training
    ambient_c: float = 25.0
    charger: str | ChargerLimits = "imax_b6"   # a resources/chargers name, or limits made for the run
    battery: str | None = None          # a saved named battery (batteries.py): its model, capacity and cells
    cell_spread: tuple[float, float, float] | None = None   # ± percent of capacity, resistance, SOC, drawn per cell
    seed: int = 1                       # draws the spread
    weak_cell_pct: float = 0.0          # one cell with this % less capacity ...
    weak_cell: int | None = None        # ... this one (1-based; None: the last)
    chem: Chemistry | None = None       # the model's parameters in place of its chemistry's table (a variant
                                        # of it: compare's measured resistance)


ENGINES = ("auto", "c", "python")


class EngineError(ZumlError):
    """The C engine was asked for and cannot run this simulation (one line: why)."""


@dataclass
class SimResult:
    interpreter: Interpreter
    chemistry: str
    capacity_mah: float
    series: int
    engine: str = "python"              # which ran it: "c" (sim/engine.py) or "python" (the reference)
    engine_note: str | None = None      # why the reference ran where the C engine was not asked against

    @property
    def phases(self) -> list[PhaseResult]:
        return self.interpreter.phases

    @property
    def log(self):
        return self.interpreter.log

    def totals(self) -> dict:
        it = self.interpreter
        return {"duration_s": round(it.time_s, 1), "mah_in": round(it.q_in / AS_PER_MAH, 1),
                "mah_out": round(it.q_out / AS_PER_MAH, 1), "end": it.end_reason}

    def repetitions(self) -> list[dict]:
        """Per training repetition: what the discharge took out (the measured capacity) and the charge put in."""
        reps: dict[int, dict] = {}
        for p in self.phases:
            rep = reps.setdefault(p.repetition, {"repetition": p.repetition, "discharged_mah": 0.0,
                                                 "charged_mah": 0.0})
            if p.section == "discharge":
                rep["discharged_mah"] += p.mah_out
            else:
                rep["charged_mah"] += p.mah_in
        return [{k: round(v, 1) if isinstance(v, float) else v for k, v in r.items()} for r in reps.values()]

    def to_json(self) -> dict:
        phases = [{"section": p.section, "index": p.index, "repetition": p.repetition, "start_s": round(p.start_s, 1),
                   "end_s": round(p.end_s, 1), "reason": p.reason, "mah_in": round(p.mah_in, 1),
                   "mah_out": round(p.mah_out, 1), "v_end": round(p.v_end, 3), "temp_end": round(p.temp_end, 2),
                   "soc_end": round(p.soc_end, 4), "by_default": p.by_default,
                   "timer_before_full": p.timer_before_full,
                   "pauses": [[round(a, 1), round(b, 1)] for a, b in p.pauses], "paused_s": round(p.paused_s, 1),
                   "clip": {"asked_a": round(p.clip_asked_a, 3), "given_a": round(p.clip_given_a, 3),
                            "limit": p.clip_limit, "clipped_s": round(p.clipped_s, 1)} if p.clip_limit else None,
                   "cells": _cells_json(p.cells_end), "balancer_s": [round(s, 1) for s in p.bled_s] or None}
                  for p in self.phases]
        pack = self.interpreter.pack
        battery = {"chemistry": self.chemistry, "capacity_mah": self.capacity_mah, "series": self.series}
        if isinstance(pack, CellPack):
            battery["cells"] = [{"capacity_mah": round(c.capacity_mah, 1), "r_scale": round(c.r_scale, 4),
                                 "soc": None if c.soc is None else round(c.soc, 4)} for c in pack.specs]
        return {"macro": self.interpreter.program.name, "engine": self.engine, "battery": battery,
                "phases": phases, "totals": self.totals(), "repetitions": self.repetitions()}


def _cells_json(volts: tuple) -> dict | None:
    """The lowest and highest cell at a phase's end (cell numbers from 1), or None for one cell."""
    if not volts:
        return None
    low = min(range(len(volts)), key=volts.__getitem__)
    high = max(range(len(volts)), key=volts.__getitem__)
    return {"min_v": round(volts[low], 4), "min_cell": low + 1, "max_v": round(volts[high], 4), "max_cell": high + 1}


def model_chemistry(record: bytes, setup: BatterySetup) -> str:
    if setup.chemistry:
        return load_chemistry(setup.chemistry).name
    akk = Program(record).intro.declarations.get(ops.AKK_TYPE.code, 0)
    name = AKK_NAMES.get(akk, "UNDEF")
    try:
        return load_chemistry(name).name
    except KeyError:
        raise StartError(_("AKK_TYPE {format} has no battery model: choose one (Pb, NiCd, NiMh, LiPo, LiIon, "
                           "LiFe)").format(format=ops.AKK_TYPE.operands[0].kind.format(akk))) from None


def start_values(record: bytes, params: StartParams,
                 templates: Mapping[int, StartTemplate] | None = None) -> tuple[Program, StartParams]:
    """The decoded program and the start values a run needs, after the start template (the
    interpreter's rule); capacity and cell count must be known (the battery model needs them): the
    capacity entered at start is the battery's, else the macro's CAPACITY; the macro's SERIES wins over
    the cells entered. (The interpreter itself still takes C units from a declared CAPACITY first, as
    the charger would.)"""
    try:
        program = Program(record)
    except DecodeError as exc:
        raise StartError(_("not a valid record: byte {offset}: {message}").format(
                offset=exc.offset, message=exc.message)) from None
    params = with_template(program, params, templates)
    declared_ah = program.intro.capacity_ah(None)
    capacity = params.capacity_mah or (round(declared_ah * MAH_PER_AH) if declared_ah else None)
    if not capacity:
        raise StartError(_("the battery's capacity is needed: the macro takes it at start (give --capacity MAH)"))
    series = program.intro.series(params.series)
    if not series:
        raise StartError(_("the number of cells is needed: the macro takes it at start (give --series N)"))
    return program, replace(params, capacity_mah=capacity, series=series)


def models(record: bytes, params: StartParams, setup: BatterySetup = BatterySetup(),
           templates: Mapping[int, StartTemplate] | None = None) -> tuple[StartParams, str, Pack | CellPack, Charger]:
    """The resolved start values and the battery and charger models a run of ``record`` starts from
    (also what the firmware's differential test runs the C core against)."""
    named = None
    file_cells = None
    if setup.battery:
        from .batteries import load_battery_cells
        named, file_cells = load_battery_cells(setup.battery)
        params = replace(params, capacity_mah=params.capacity_mah or round(named.capacity_mah),
                         series=params.series or named.series)
    program, params = start_values(record, params, templates)
    base = named.chem if named else setup.chem
    chemistry = base.name if base else model_chemistry(record, setup)
    soc = setup.soc if setup.soc is not None else (0.0 if params.task == "charge" else 1.0)
    pack = build_pack(base or load_chemistry(chemistry), params.capacity_mah, params.series, soc,
                      setup.ambient_c, pack_cells(setup, params.capacity_mah, params.series, soc, file_cells))
    limits = load_charger(setup.charger) if isinstance(setup.charger, str) else setup.charger
    charger = Charger(limits, setup.ambient_c)
    return params, chemistry, pack, charger


def pack_cells(setup: BatterySetup, capacity_mah: float, series: int, soc: float,
               file_cells: list[CellSpec] | None = None) -> list[CellSpec] | None:
    """The cells a run's pack has: the battery file's, else drawn from the spread; then the weak cell.
    None: identical cells. StartError says what does not fit."""
    if setup.weak_cell_pct and not 0.0 < setup.weak_cell_pct < 100.0:
        raise StartError(_("weak cell: {pct:g} is no percentage of capacity to take off (0 to 100)").format(
            pct=setup.weak_cell_pct))
    if setup.weak_cell is not None and not 1 <= setup.weak_cell <= series:
        raise StartError(_("weak cell {k}: the pack has cells 1 to {series}").format(k=setup.weak_cell, series=series))
    if setup.cell_spread and (len(setup.cell_spread) != 3 or
                              not all(0.0 <= x <= top for x, top in zip(setup.cell_spread, SPREAD_MAX_PCT))):
        raise StartError(_("cell spread CAP,R,SOC: each from 0 to {tops} %").format(
            tops="/".join(f"{x:g}" for x in SPREAD_MAX_PCT)))
    if file_cells is not None and setup.cell_spread:
        raise StartError(_("the battery file lists its cells: a cell spread cannot be drawn on top"))
    if file_cells is not None and len(file_cells) != series:
        raise StartError(_("the battery file lists {given} cells, the pack has {series}").format(
            given=len(file_cells), series=series))
    if file_cells is None and not setup.cell_spread and not setup.weak_cell_pct:
        return None
    cells = file_cells if file_cells is not None else spread_cells(capacity_mah, series, setup.cell_spread,
                                                                   setup.seed, soc)
    if setup.weak_cell_pct:
        cells = weaken(cells, setup.weak_cell_pct, setup.weak_cell)
    try:
        check_cells(cells)
    except ValueError as exc:
        raise StartError(str(exc)) from None
    return cells


def prepare(record: bytes, params: StartParams, setup: BatterySetup = BatterySetup(), *,
            tick_s: float = 1.0, measurement: Measurement = Measurement(),
            templates: Mapping[int, StartTemplate] | None = None) -> SimResult:
    """Builds everything; the caller runs ``result.interpreter`` (all at once, or tick by tick).
    ``templates``: the charger's start templates (default: the factory table)."""
    params, chemistry, pack, charger = models(record, params, setup, templates)
    interpreter = Interpreter(record, params, pack, charger, tick_s=tick_s, measurement=measurement,
                              templates=templates)
    return SimResult(interpreter, chemistry, float(params.capacity_mah), int(params.series))


def simulate(record: bytes, params: StartParams, setup: BatterySetup = BatterySetup(), *, engine: str = "auto",
             **kw) -> SimResult:
    """``engine``: "auto" runs the C engine when it can run this simulation and the Python reference
    otherwise (noise drawn with Python's generator, a tick not whole seconds, the library not built: see
    `engine.unavailable`), "c" the C engine or EngineError, "python" the reference."""
    if engine not in ENGINES:
        raise ValueError(f"engine {engine!r}: one of {', '.join(ENGINES)}")
    result = prepare(record, params, setup, **kw)
    it = result.interpreter
    why = None if engine == "python" else c_engine.unavailable(it)
    if engine == "c" and why:
        raise EngineError(why)
    if engine != "python" and why is None:
        c_engine.run(it, kw.get("templates"))
        result.engine = "c"
    else:
        it.run()
        result.engine_note = why
    return result
