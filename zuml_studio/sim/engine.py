"""The C simulation engine: the firmware's interpreter core on the host board with the battery and
charger models in C (firmware/boards/host/engine.c, firmware/model/), run for a whole simulation in one
library, ``_engine/libzuml_engine.so``, built with the package (setup.py, from firmware/engine.sources).

The Python interpreter (`interpreter.py`) stays the reference: `run` builds the same `Interpreter` (its
program, start values, pack and charger, its StartErrors), hands the models' constants and state to C,
and fills the interpreter's results from what C reports: the phases, the events, the sample log, the
totals, so a caller cannot tell the two apart (tests/sim/test_engine.py holds them tick for tick).
`unavailable` says when the reference must run instead.
"""
from __future__ import annotations

import ctypes
import sys
import threading
from pathlib import Path
from typing import Callable, Mapping

import numpy as np

from ..protocol import messages
from .battery import Pack
from .cell_pack import CellPack
from .interpreter import FULL_SOC, Event, Interpreter, PhaseResult
from ..domain import samples
from ..domain.samples import BALANCE_MASK, COLUMNS
from ..domain.start_templates import StartTemplate, factory_templates
from ..i18n import _

LIBRARY = Path(__file__).with_name("_engine") / "libzuml_engine.so"

_TASKS = {"charge": 0, "discharge": 1, "train": 2}
_NONE = -1
(_EV_SECTION, _EV_PHASE_START, _EV_PHASE_END, _EV_PAUSE, _EV_RESUME, _EV_MUSIC, _EV_LIGHT,
 _EV_FINISH) = range(1, 9)
_EV_LIMIT = 100
_R_CONDITION, _R_STOP_MACRO = 1, 6
_IF_TF_GT = 88                     # its byte code: a timer, like the macro's IF(tm>x) STOP_MACRO
_SECTIONS = ("discharge", "charge")
_EVENTS_CAP = 1024                 # engine.c returns early while fewer than 300 are free
_PHASE_ENDS = 256                  # a phase end's cells per ze_run (it returns early as they fill)
_MAX_CELLS = 32                   # the balance mask is a uint32
_K_LENGTH = 32                    # Pack.step_constants' length, as _Constants carries it
_STATE_FIELDS = ("soc", "temp_c", "current", "cell_voltage", "voltage", "v1", "v2", "vp", "oc", "over", "h",
                 "surf")
_D, _I32, _U8 = ctypes.c_double, ctypes.c_int32, ctypes.c_uint8
_P = ctypes.POINTER


class ZcStart(ctypes.Structure):
    _fields_ = [("task", _U8), ("repetitions", _U8), ("capacity_mah", _I32), ("current_ua", _I32),
                ("voltage_uv", _I32), ("series", ctypes.c_int16), ("sensor", _U8), ("template_no", _U8)]


class ZcBoard(ctypes.Structure):
    _fields_ = [("max_charge_ua", _I32), ("max_discharge_ua", _I32), ("fallback_end_uv_per_cell", _I32),
                ("tick_ms", ctypes.c_uint16), ("dp_window_s", ctypes.c_uint16), ("dp_holdoff_s", ctypes.c_uint16)]


class _Constants(ctypes.Structure):
    _fields_ = [(name, _D) for name in ("r0", "r1b", "a1", "r2b", "a2", "ea_r", "ea_r_ref", "kc", "kd", "eps",
                                        "inv_w0", "w_t", "dv_o2", "k_t", "q_rev", "ds_k", "a_th", "inv_ha",
                                        "a_p", "vp_max", "k_dip", "a_o", "k_over", "half_m", "h_k",
                                        "a_x", "b_x", "ambient_c")] + \
               [("xs", _P(_D)), ("ys", _P(_D)), ("slopes", _P(_D)), ("last", _I32), ("series", _I32)]


class _State(ctypes.Structure):
    _fields_ = [(name, _D) for name in _STATE_FIELDS]


class _Pack(ctypes.Structure):
    _fields_ = [("cells", _I32), ("neumaier_sum", _I32), ("k", _P(_Constants)), ("s", _P(_State)),
                ("q", _P(_D)), ("q_total", _D), ("bleed_a", _P(_D)), ("cell_voltages", _P(_D)),
                ("voltage", _D), ("current", _D), ("cv_guess", _D)]


class _Charger(ctypes.Structure):
    _fields_ = [(name, _D) for name in ("max_charge_a", "max_charge_w", "max_discharge_a", "max_discharge_w",
                                        "loss_per_w", "r", "tau", "ambient_c", "heatsink_c", "a")]


class _Balancer(ctypes.Structure):
    _fields_ = [("on", _I32), ("cv_only", _I32), ("bleed_r_ohm", _D), ("bleed_a", _D), ("spread_v", _D),
                ("ceiling_v", _D), ("window_s", _D), ("settle_s", _D), ("spread_off_v", _D), ("from_v", _D),
                ("max_bleeders", _I32)]


class _Event(ctypes.Structure):
    _fields_ = [(name, _U8) for name in ("kind", "section", "index", "repetition", "cycle_pass", "offset",
                                         "reason", "reason_offset")] + \
               [("text_len", _I32), ("text", ctypes.c_char * 80), ("time_s", _D)] + \
               [(name, _D) for name in ("mah_in", "mah_out", "v_end", "temp_end", "soc_end", "pack_v",
                                        "clip_asked_a", "clip_given_a", "clip_pack_v", "clipped_s")] + \
               [("cells_at", _I32)]


class _Run(ctypes.Structure):
    _fields_ = [("pack", _P(_Pack)), ("charger", _P(_Charger)), ("balancer", _P(_Balancer)),
                ("per_cell", _I32), ("dt", _D), ("limit_s", _D), ("lsb_v", _D),
                ("time_s", _P(_D)), ("section", _P(ctypes.c_int8)), ("phase", _P(ctypes.c_int64))] + \
               [(name, _P(ctypes.c_float)) for name in ("voltage_v", "current_a", "temp_c", "heatsink_c",
                                                       "mah_in", "mah_out", "cells")] + \
               [("balance_mask", _P(ctypes.c_uint32)), ("events", _P(_Event)), ("events_cap", _I32),
                ("n_events", _I32), ("phase_cells", _P(_D)), ("phase_cells_cap", _I32),
                ("n_phase_cells", _I32), ("time", _D), ("q_in", _D), ("q_out", _D), ("ticks", ctypes.c_int64),
                ("finished", _I32), ("paused", _I32)]


_lock = threading.Lock()           # the library holds one run (the host board is one device)
_library: list = []                # [CDLL] once loaded, [None] when it cannot be
_templates_set: list = [None]      # the template table the library holds now


def library() -> ctypes.CDLL | None:
    """The engine's library, or None when it is not built (the reference runs)."""
    if not _library:
        try:
            lib = ctypes.CDLL(str(LIBRARY))
        except OSError:
            _library.append(None)
            return None
        lib.ze_start.argtypes = [_P(_Run), ctypes.c_char_p, ctypes.c_uint16, _P(ZcStart), _P(ZcBoard)]
        lib.ze_start.restype = _U8
        lib.ze_run.argtypes = [_P(_Run), _I32]
        lib.ze_run.restype = _I32
        lib.ze_stop.argtypes = [_P(_Run)]
        lib.zh_set_template.argtypes = [_U8, ctypes.c_char_p]
        lib.zm_drive.argtypes = [_P(_Pack), _P(_P(_Constants)), _P(_I32), _P(_D), _P(_D), _P(_U8), _I32, _D,
                                 _P(_D), _P(_D), _P(_D)]
        lib.zm_drive.restype = _I32
        _library.append(lib)
    return _library[0]


def missing_text() -> str:
    """The one line for a run that asks for the C engine where the library is not built."""
    return _("the C simulation engine is not built ({path}): install a C compiler (apt-get install gcc) and "
             "reinstall ZUML Studio (in a checkout: ./dev, or pip install -e .)").format(path=LIBRARY)


def unavailable(interpreter: Interpreter) -> str | None:
    """Why the C engine cannot run this simulation (the reference runs it), or None when it can."""
    it = interpreter
    tick_ms = it.tick_s * 1000.0
    limits = it.charger.limits
    if library() is None:
        return missing_text()
    if it.measurement.noise_v:
        return _("measurement noise is drawn with Python's generator")
    if not (1000.0 <= tick_ms <= 65000.0 and tick_ms % 1000.0 == 0.0):
        return _("the C engine runs whole-second ticks of 1 to 65 s")
    if not it.limit_s < 4e6:
        return _("the C engine's clock runs to 1100 h")
    if limits.dpeak_window_s % 1.0 or limits.dpeak_holdoff_s % 1.0:
        return _("the charger's -dV window is not whole seconds")
    if isinstance(it.pack, CellPack) and it.pack.series > _MAX_CELLS:
        return _("the C engine balances at most {n} cells").format(n=_MAX_CELLS)
    cells = it.pack.cells if isinstance(it.pack, CellPack) else [it.pack]
    if not all(type(c) is Pack and len(c.step_constants(it.tick_s)) == _K_LENGTH for c in cells):
        return _("the battery model is not the one the C engine carries")
    return None


def template_bytes(t: StartTemplate) -> bytes:
    """A start template as the firmware stores it: the protocol's SET_TEMPLATE fields after the number
    (docs/protocol.md; one codec, messages.py's); 0 = not given."""
    return messages.encode_response("SET_TEMPLATE", **messages.template_fields(0, t))[1:]


def _fixed(x: float) -> int:
    return max(-2**31, min(2**31 - 1, round(x * 1e6)))


def _doubles(values) -> ctypes.Array:
    return (_D * len(values))(*values)


def _constants(cell: Pack, dt: float, keep: list, tables: list | None = None) -> _Constants:
    """The cell's constants at a tick of dt; ``tables``: its OCV table as C arrays where already made (they
    do not change with dt)."""
    (r0, r1b, a1, r2b, a2, ea_r, ea_r_ref, kc, kd, eps, inv_w0, w_t, dv_o2, k_t, q_rev, ds_k, a_th, inv_ha,
     xs, ys, slopes, last, series, a_p, vp_max, k_dip, a_o, k_over, half_m, h_k, a_x, b_x) = cell.step_constants(dt)
    if tables is None:
        tables = [_doubles(xs), _doubles(ys), _doubles(slopes)]
        keep.extend(tables)
    return _Constants(r0, r1b, a1, r2b, a2, ea_r, ea_r_ref, kc, kd, eps, inv_w0, w_t, dv_o2, k_t, q_rev, ds_k,
                      a_th, inv_ha, a_p, vp_max, k_dip, a_o, k_over, half_m, h_k, a_x, b_x, cell.ambient_c, *tables,
                      last,
                      series)


def _cells(pack: Pack | CellPack) -> list[Pack]:
    return pack.cells if isinstance(pack, CellPack) else [pack]


def _c_pack(pack: Pack | CellPack, dt: float, keep: list) -> _Pack:
    cells = _cells(pack)
    k = (_Constants * len(cells))(*(_constants(c, dt, keep) for c in cells))
    s = (_State * len(cells))(*(_State(*(getattr(c, name) for name in Pack.STATE)) for c in cells))
    keep.extend([k, s])
    c = _Pack(0, int(sys.version_info >= (3, 12)), k, s, None, 0.0, None, None, pack.voltage, pack.current, 0.0)
    if isinstance(pack, CellPack):
        q = [spec.capacity_mah for spec in pack.specs]
        arrays = [_doubles(q), _doubles(pack.bleed_a), _doubles(pack.cell_voltages)]
        keep.extend(arrays)
        c.cells, c.q_total = len(cells), sum(q)
        c.q, c.bleed_a, c.cell_voltages = arrays
    return c


def _c_charger(charger) -> _Charger:
    lim = charger.limits
    return _Charger(lim.max_charge_a, lim.max_charge_w, lim.max_discharge_a, lim.max_discharge_w,
                    1.0 - lim.charge_efficiency, lim.heatsink_r_k_per_w,
                    lim.heatsink_r_k_per_w * lim.heatsink_c_j_per_k, charger.ambient_c, charger.heatsink_c, 0.0)


def _c_balancer(it: Interpreter) -> _Balancer:
    spec = it._balancer           # the interpreter's own decision: unequal cells, a chemistry with a ceiling
    if spec is None:
        return _Balancer()
    chem = it.pack.chem.name
    return _Balancer(1, int(spec.during == "cv"), spec.bleed_r_ohm or 0.0, spec.bleed_a or 0.0, spec.spread_v,
                     spec.ceiling_v[chem], spec.window_s, spec.settle_s, spec.spread_off_v, spec.from_v.get(chem, 0.0),
                     spec.max_bleeders)


def _set_templates(lib: ctypes.CDLL, templates: Mapping[int, StartTemplate]) -> None:
    table = {n: template_bytes(t) for n, t in templates.items()}
    if _templates_set[0] != table:
        for number in range(256):
            lib.zh_set_template(number, table.get(number))
        _templates_set[0] = table


class _Buffers:
    """One chunk of samples as C writes them, and the event buffers."""

    def __init__(self, run: _Run, cells: int) -> None:
        chunk = samples.CHUNK           # the log's: a run of ticks fills at most its room
        self.columns = {"time_s": np.empty(chunk, np.float64), "section": np.empty(chunk, np.int8),
                        "phase": np.empty(chunk, np.int64),
                        **{name: np.empty(chunk, np.float32) for name in COLUMNS[3:]}}
        for name, array in self.columns.items():
            setattr(run, name, array.ctypes.data_as(type(getattr(run, name))))
        self.cells = np.empty((chunk, cells), np.float32) if cells else None
        self.mask = np.empty(chunk, np.uint32) if cells else None
        if cells:
            run.cells = self.cells.ctypes.data_as(_P(ctypes.c_float))
            run.balance_mask = self.mask.ctypes.data_as(_P(ctypes.c_uint32))
        self.events = (_Event * _EVENTS_CAP)()
        self.phase_cells = (_D * (_PHASE_ENDS * 2 * cells))()
        run.events, run.events_cap = self.events, _EVENTS_CAP
        run.phase_cells, run.phase_cells_cap = self.phase_cells, len(self.phase_cells)

    def block(self, n: int) -> dict[str, np.ndarray]:
        out = {name: array[:n] for name, array in self.columns.items()}
        if self.cells is not None:
            out.update({f"cell{k + 1}_v": self.cells[:n, k] for k in range(self.cells.shape[1])})
            out[BALANCE_MASK] = self.mask[:n]
        return out


def run(interpreter: Interpreter, templates: Mapping[int, StartTemplate] | None = None,
        on_chunk: Callable[[float], str | None] | None = None) -> None:
    """Runs a freshly built interpreter's simulation to its end in C and fills its results as its own
    ``run()`` would (check `unavailable` first). ``on_chunk(time_s)``, after every chunk of ticks, may
    return a reason to stop the run with, as ``Interpreter.stop(reason)`` does. RuntimeError when the
    core refuses a start the reference accepted."""
    lib = library()
    if lib is None:
        raise RuntimeError(missing_text())
    with _lock:
        _run(lib, interpreter, factory_templates() if templates is None else templates, on_chunk)


def _run(lib: ctypes.CDLL, it: Interpreter, templates: Mapping[int, StartTemplate],
         on_chunk: Callable[[float], str | None] | None) -> None:
    keep: list = []
    pack, charger, p = it.pack, it.charger, it.params
    c_pack, c_charger, c_balancer = _c_pack(pack, it.tick_s, keep), _c_charger(charger), _c_balancer(it)
    per_cell = it._per_cell       # the interpreter's: a pack of several unequal cells
    c_run = _Run(ctypes.pointer(c_pack), ctypes.pointer(c_charger), ctypes.pointer(c_balancer), int(per_cell),
                 it.tick_s, it.limit_s, it.measurement.lsb_v)
    buffers = _Buffers(c_run, pack.series if per_cell else 0)
    _set_templates(lib, templates)
    start = ZcStart(_TASKS[p.task], p.repetitions, _NONE if p.capacity_mah is None else round(p.capacity_mah),
                    _NONE if p.current_a is None else _fixed(p.current_a),
                    _NONE if p.voltage_v is None else _fixed(p.voltage_v), p.series or 0, int(p.sensor),
                    p.template or 0)
    lim = charger.limits
    board = ZcBoard(_fixed(lim.max_charge_a), _fixed(lim.max_discharge_a), _fixed(pack.chem.discharge_end_v),
                    round(it.tick_s * 1000), round(lim.dpeak_window_s), round(lim.dpeak_holdoff_s))
    record = it.program.record
    err = lib.ze_start(ctypes.byref(c_run), record, len(record), ctypes.byref(start), ctypes.byref(board))
    if err:
        raise RuntimeError(f"the C core refused a start the reference accepted (error {err})")
    reader = _Reader(it, record, buffers)
    log = it.log
    while not c_run.finished:
        n = lib.ze_run(ctypes.byref(c_run), log.room)
        if n:
            log.append_block(buffers.block(n))
            log.seal_if_full()
        reader.events(c_run.n_events)
        stop = on_chunk(c_run.time) if on_chunk is not None and not c_run.finished else None
        if stop is not None:
            lib.ze_stop(ctypes.byref(c_run))
            reader.events(c_run.n_events, stop)
    log.seal()
    it.time_s, it.q_in, it.q_out, it.paused = c_run.time, c_run.q_in, c_run.q_out, bool(c_run.paused)
    _write_back(pack, c_pack, charger, c_charger)


def drivable(pack: Pack | CellPack) -> bool:
    """Whether `drive` can run this pack in C (the library is built and carries its model)."""
    return library() is not None and all(type(c) is Pack and len(c.step_constants(1.0)) == _K_LENGTH
                                         for c in _cells(pack))


class Track:
    """Samples as `drive` steps them (built once, driven many times: a fit runs one curve hundreds of times):
    sample k lasts dt[k] at current[k], or where cv[k] at the current that holds voltage[k], kept to
    current[k]'s direction."""

    def __init__(self, dt: np.ndarray, current: np.ndarray, voltage: np.ndarray, cv: np.ndarray) -> None:
        steps, which = np.unique(np.asarray(dt, np.float64), return_inverse=True)
        self.steps = [float(x) for x in steps]
        self.n = len(dt)
        self._arrays = (np.ascontiguousarray(which, np.int32), np.ascontiguousarray(current, np.float64),
                        np.ascontiguousarray(voltage, np.float64), np.ascontiguousarray(cv, np.uint8))
        which, current, voltage, cv = self._arrays
        self.pointers = (which.ctypes.data_as(_P(_I32)), current.ctypes.data_as(_P(_D)),
                         voltage.ctypes.data_as(_P(_D)), cv.ctypes.data_as(_P(_U8)))


def drive(pack: Pack | CellPack, track: Track, stop_v: float = -np.inf) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Steps ``pack`` through the track's samples in C, as a fit's Python loop does (sim/fit.py simulate_curve,
    bit for bit), stopping after the first sample at or below ``stop_v``; the pack is left in its end state.
    Returns the pack's voltage, current and temperature per sample done (check `drivable` first)."""
    lib = library()
    keep: list = []
    c_pack = _c_pack(pack, track.steps[0], keep)
    if isinstance(pack, CellPack):
        c_pack.cv_guess = pack._cv_guess
    cells = _cells(pack)
    first = [c_pack.k[k] for k in range(len(cells))]
    ocv = [[c.xs, c.ys, c.slopes] for c in first]
    tables = [(_Constants * len(cells))(*(_constants(c, step, keep, t) for c, t in zip(cells, ocv)))
              for step in track.steps[1:]]
    ks = (_P(_Constants) * len(track.steps))(c_pack.k, *tables)
    v, i, temp = np.empty(track.n), np.empty(track.n), np.empty(track.n)
    done = lib.zm_drive(ctypes.byref(c_pack), ks, *track.pointers, track.n, stop_v, v.ctypes.data_as(_P(_D)),
                        i.ctypes.data_as(_P(_D)), temp.ctypes.data_as(_P(_D)))
    _write_back_pack(pack, c_pack)
    if isinstance(pack, CellPack):
        pack._cv_guess = c_pack.cv_guess
    return v[:done], i[:done], temp[:done]


def _write_back(pack: Pack | CellPack, c_pack: _Pack, charger, c_charger: _Charger) -> None:
    """The models' state at the end, as the reference leaves it."""
    _write_back_pack(pack, c_pack)
    charger.heatsink_c = c_charger.heatsink_c


def _write_back_pack(pack: Pack | CellPack, c_pack: _Pack) -> None:
    for k, cell in enumerate(_cells(pack)):
        for name, field in zip(Pack.STATE, _STATE_FIELDS):
            setattr(cell, name, getattr(c_pack.s[k], field))
    if isinstance(pack, CellPack):
        pack.bleed_a = c_pack.bleed_a[:pack.series]
        pack.cell_voltages = c_pack.cell_voltages[:pack.series]
        pack.voltage, pack.cell_voltage = c_pack.voltage, c_pack.voltage / pack.series
        pack.current = c_pack.current


class _Reader:
    """Turns the engine's events into the interpreter's phases and events."""

    def __init__(self, it: Interpreter, record: bytes, buffers: _Buffers) -> None:
        self.it, self.record, self.buffers = it, record, buffers
        self.paused = False

    def events(self, n: int, stopped: str | None = None) -> None:
        """The first n events of the buffer; ``stopped``: the reason the run was stopped with (the
        core's "stopped" is the user's stop)."""
        it = self.it
        for ev in self.buffers.events[:n]:
            t = ev.time_s
            text = stopped or ev.text[:ev.text_len].decode("ascii")
            kind = ev.kind
            if kind == _EV_SECTION:
                it.events.append(Event(t, "section", section=_SECTIONS[ev.section], repetition=ev.repetition))
            elif kind == _EV_PHASE_START:
                r = PhaseResult(_SECTIONS[ev.section], ev.index, ev.repetition, ev.cycle_pass, ev.offset, t)
                r.run = len(it.phases) + 1
                if self.paused:
                    r.pauses.append([t, t])
                it.phases.append(r)
                it.events.append(Event(t, "phase_start", section=r.section, index=r.index,
                                       repetition=r.repetition, offset=r.offset))
            elif kind in (_EV_PHASE_END, _EV_LIMIT):
                reason = text if kind == _EV_PHASE_END else f"limit: simulation stopped after {it.limit_s / 3600:g}h"
                self._end_phase(ev, reason)
                if kind == _EV_LIMIT:
                    self._finish(t, reason)
            elif kind in (_EV_PAUSE, _EV_RESUME):
                self.paused = kind == _EV_PAUSE
                pauses = it.phases[-1].pauses
                if self.paused:
                    pauses.append([t, t])
                else:
                    pauses[-1][1] = t
                it.events.append(Event(t, "pause" if self.paused else "resume", detail=text))
            elif kind in (_EV_MUSIC, _EV_LIGHT):
                it.events.append(Event(t, "music" if kind == _EV_MUSIC else "light", offset=ev.offset, detail=text))
            elif kind == _EV_FINISH:
                self._finish(t, text)

    def _end_phase(self, ev: _Event, reason: str) -> None:
        it = self.it
        r = it.phases[-1]
        r.end_s, r.reason = ev.time_s, reason
        r.mah_in, r.mah_out, r.v_end, r.temp_end, r.soc_end = ev.mah_in, ev.mah_out, ev.v_end, ev.temp_end, ev.soc_end
        if ev.clipped_s:
            r.clip_asked_a, r.clip_given_a, r.clipped_s = ev.clip_asked_a, ev.clip_given_a, ev.clipped_s
            r.clip_limit = it.charger.clip_reason(ev.clip_asked_a, ev.clip_pack_v)
        series = it.pack.series
        if ev.cells_at >= 0:
            at = ev.cells_at
            cells = self.buffers.phase_cells
            r.cells_end = tuple(cells[at:at + series])
            r.bled_s = tuple(n * it.tick_s for n in cells[at + series:at + 2 * series])
        elif series > 1:
            r.cells_end = (ev.pack_v / series,) * series
        if r.pauses and self.paused:
            r.pauses[-1][1] = ev.time_s
        by_timer = ev.kind == _EV_PHASE_END and (ev.reason == _R_STOP_MACRO or (
            ev.reason == _R_CONDITION and self.record[ev.reason_offset] == _IF_TF_GT))
        r.timer_before_full = bool(by_timer and r.section == "charge" and r.soc_end < FULL_SOC)
        it.events.append(Event(ev.time_s, "phase_end", section=r.section, index=r.index, repetition=r.repetition,
                               offset=r.offset, detail=reason))

    def _finish(self, t: float, reason: str) -> None:
        it = self.it
        it.finished, it.end_reason = True, reason
        it.events.append(Event(t, "finish", detail=reason))
