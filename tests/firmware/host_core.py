"""The C core's host build (firmware/build/host/libzuml_host.so) driven through ctypes on the same
battery and charger models as the Python interpreter, tick for tick.

The loop below is the host board: it turns the core's set point into a current the way the Python
interpreter's power stage does (CV through the pack's algebraic solve, the charger's limits), steps
the same models, and hands the readings back in the core's fixed-point units.
"""
from __future__ import annotations

import ctypes
import os
import random
from dataclasses import dataclass
from pathlib import Path

from zuml_studio.sim.charger_model import load_charger
from zuml_studio.sim.engine import ZcBoard, ZcStart, template_bytes
from zuml_studio.sim.interpreter import Measurement, StartError, StartParams
from zuml_studio.sim.simulate import BatterySetup, models, prepare
from zuml_studio.domain.start_templates import factory_templates

ROOT = Path(__file__).resolve().parents[2]
# tools/mutate_firmware.py points the firmware tests at a worker's mutated copy of firmware/
FIRMWARE = Path(os.environ.get("ZUML_TEST_FIRMWARE") or ROOT / "firmware")
LIBRARY = FIRMWARE / "build" / "host" / "libzuml_host.so"

TASKS = {"charge": 0, "discharge": 1, "train": 2}
NONE = -1
OFF, CURRENT, VOLTAGE_CHARGE, VOLTAGE_DISCHARGE = range(4)
EV_PHASE_START, EV_PHASE_END, EV_PAUSE, EV_RESUME, EV_MUSIC, EV_LIGHT, EV_FINISH = range(2, 9)
START_ERRORS = {1: "record", 2: "INPUT current", 3: "C needs capacity", 4: "INPUT voltage",
                5: "S needs series", 6: "repetitions", 7: "no template"}


class ZcEvent(ctypes.Structure):
    _fields_ = [(name, ctypes.c_uint8) for name in ("kind", "section", "index", "repetition", "cycle_pass",
                                                     "offset", "reason", "reason_offset", "arg")] + \
               [("time_ms", ctypes.c_uint32), ("mah_in_x1000", ctypes.c_uint32), ("mah_out_x1000", ctypes.c_uint32)]


class HalOutput(ctypes.Structure):
    _fields_ = [("kind", ctypes.c_uint8), ("current_ua", ctypes.c_int32), ("voltage_uv", ctypes.c_int32)]


EVENT_SINK = ctypes.CFUNCTYPE(None, ctypes.POINTER(ZcEvent))


def load(path: Path = LIBRARY) -> ctypes.CDLL:
    lib = ctypes.CDLL(str(path))
    i32, u8, u16 = ctypes.c_int32, ctypes.c_uint8, ctypes.c_uint16
    lib.zh_start.argtypes = [ctypes.c_char_p, u16, ctypes.POINTER(ZcStart), ctypes.POINTER(ZcBoard)]
    lib.zh_start.restype = u8
    lib.zh_control.argtypes = [i32, i32, i32, ctypes.POINTER(HalOutput)]
    lib.zh_control.restype = u8
    lib.zh_measure.argtypes = [i32, i32, i32, i32, i32]
    lib.zh_measure.restype = u8
    lib.zh_set_event_sink.argtypes = [EVENT_SINK]
    lib.zh_validate.argtypes = [ctypes.c_char_p, u16]
    lib.zh_validate.restype = u16
    lib.zh_chemistry_end_uv.argtypes = [u8]
    lib.zh_chemistry_end_uv.restype = i32
    lib.zh_event_text.argtypes = [ctypes.POINTER(ZcEvent), ctypes.c_char_p]
    lib.zh_event_text.restype = u8
    lib.zh_phase_counts.argtypes = [ctypes.POINTER(ctypes.c_int64), ctypes.POINTER(ctypes.c_int64)]
    lib.zh_set_template.argtypes = [u8, ctypes.c_char_p]
    return lib


def _fixed(x: float, scale: float) -> int:
    return max(-2**31, min(2**31 - 1, round(x * scale)))


@dataclass
class Phase:
    """What both interpreters report per phase, in ticks and canonical reason texts."""

    section: str
    index: int
    repetition: int
    cycle_pass: int
    offset: int
    start_tick: int
    end_tick: int
    reason: str
    mah_in: float
    mah_out: float


@dataclass
class Run:
    start_error: str | None
    phases: list[Phase]
    signals: list[tuple]             # (kind, tick, offset, detail) of pause, resume, music, light
    end_reason: str


class Script:
    """Readings from a script instead of the battery model, fed alike to both interpreters: after its
    n-th step (n from 1) the pack reads ``volts(n)`` and ``temps(n)``, and the heat sink that the next
    tick's control sees reads ``sink(n)`` (n = 0: the values at the phase start). The power stage
    gives whatever current is asked; ``currents`` records it tick by tick, so a decision that differs
    for one tick (trickle on or off, a pause) shows even when the charge counts stay within 1 mAh."""

    def __init__(self, volts, temps=lambda n: 25.0, sink=lambda n: 25.0, cv_current_a: float = 0.5):
        self.volts, self.temps, self.sink, self.cv_current_a = volts, temps, sink, cv_current_a
        self.steps = 0
        self.currents: list[float] = []

    def scripted(self, pack, charger):
        self.steps, self.currents = 0, []
        return _ScriptedPack(self, pack), _ScriptedStage(self, charger)


class _ScriptedPack:
    def __init__(self, script: Script, pack):
        self._script, self._pack = script, pack

    def __getattr__(self, name):            # chem, soc, ...: the real pack's
        return getattr(self._pack, name)

    @property
    def voltage(self) -> float:
        return self._script.volts(self._script.steps)

    @property
    def temp_c(self) -> float:
        return self._script.temps(self._script.steps)

    def open_circuit_voltage(self) -> float:
        return self.voltage

    def current_for_voltage(self, v: float, dt: float) -> float:
        return self._script.cv_current_a if v > self.voltage else -self._script.cv_current_a

    def step(self, i: float, dt: float) -> float:
        self._script.steps += 1
        self._script.currents.append(round(i, 6))
        return self.voltage


class _ScriptedStage:
    def __init__(self, script: Script, charger):
        self._script, self._charger = script, charger

    def __getattr__(self, name):            # limits, clip_reason, ...: the real charger's
        return getattr(self._charger, name)

    @property
    def heatsink_c(self) -> float:
        return self._script.sink(self._script.steps)

    def step(self, i: float, v: float, dt: float) -> float:
        return self.heatsink_c

    def limit_current(self, i: float, v: float) -> float:
        return i


def limit_reason(limit_s: float) -> str:
    return f"limit: simulation stopped after {limit_s / 3600:g}h"


def python_run(record: bytes, params: StartParams, setup: BatterySetup, tick_s: float, limit_s: float,
               measurement: Measurement = Measurement(), script: Script | None = None) -> Run:
    sim = prepare(record, params, setup, tick_s=tick_s, measurement=measurement)
    it = sim.interpreter
    if script is not None:
        it.pack, it.charger = script.scripted(it.pack, it.charger)
    it.limit_s = limit_s
    it.run()
    tick = lambda s: round(s / tick_s)  # noqa: E731
    phases = [Phase(p.section, p.index, p.repetition, p.cycle_pass, p.offset, tick(p.start_s), tick(p.end_s),
                    p.reason, p.mah_in, p.mah_out) for p in it.phases]
    signals = [(e.kind, tick(e.time_s), e.offset if e.kind in ("music", "light") else -1, e.detail)
               for e in it.events if e.kind in ("pause", "resume", "music", "light")]
    return Run(None, phases, signals, it.end_reason)


def start_error_category(message: str) -> str:
    """The reference's StartError message as the core's start error."""
    for needle, category in (("give the current", "INPUT current"), ("current in C", "C needs capacity"),
                             ("give the voltage", "INPUT voltage"), ("per cell (S)", "S needs series"),
                             ("repetition", "repetitions"), ("does not exist on this charger", "no template")):
        if needle in message:
            return category
    raise AssertionError(f"a start error the core does not know: {message}")


class CoreRunner:
    def __init__(self, lib: ctypes.CDLL):
        self.lib = lib
        self._out = HalOutput()
        self._text = ctypes.create_string_buffer(80)
        self._sink = EVENT_SINK(lambda e: self._event(e.contents))
        lib.zh_set_event_sink(self._sink)
        for number, template in factory_templates().items():     # the simulator's charger's table
            lib.zh_set_template(number, template_bytes(template))

    def run(self, record: bytes, params: StartParams, setup: BatterySetup, tick_s: float, limit_s: float,
            measurement: Measurement = Measurement(), script: Script | None = None) -> Run:
        # The core gets the values as entered and applies the start template itself; the models are
        # built from the values after it (a start Python refuses has none: the core must refuse it too).
        try:
            _, _, pack, charger = models(record, params, setup)
        except StartError:
            pack = charger = None
        if script is not None and pack is not None:
            pack, charger = script.scripted(pack, charger)
        p = params
        start = ZcStart(TASKS[p.task], p.repetitions,
                        NONE if p.capacity_mah is None else round(p.capacity_mah),
                        NONE if p.current_a is None else _fixed(p.current_a, 1e6),
                        NONE if p.voltage_v is None else _fixed(p.voltage_v, 1e6), p.series or 0, int(p.sensor),
                        p.template or 0)
        tick_ms = round(tick_s * 1000)
        lim = load_charger(setup.charger)
        board = ZcBoard(_fixed(lim.max_charge_a, 1e6), _fixed(lim.max_discharge_a, 1e6),
                        _fixed(pack.chem.discharge_end_v, 1e6) if pack else 0, tick_ms,
                        round(lim.dpeak_window_s), round(lim.dpeak_holdoff_s))
        lib = self.lib
        err = lib.zh_start(record, len(record), ctypes.byref(start), ctypes.byref(board))
        if err:
            return Run(START_ERRORS[err], [], [], "")
        assert pack is not None, "the core started a run the reference refused"
        self._record = record
        self._phases: list[Phase] = []
        self._signals: list[tuple] = []
        self._end = ""
        self._tick_ms = tick_ms
        rng = random.Random(measurement.seed)
        gauss = rng.gauss
        noise, lsb = measurement.noise_v, measurement.lsb_v
        dt = tick_s
        limit_ticks = -(-limit_s // tick_s)
        out = self._out
        out_ref = ctypes.byref(out)
        control, measure = lib.zh_control, lib.zh_measure
        cfv, step, hs_step, limit = pack.current_for_voltage, pack.step, charger.step, charger.limit_current
        ticks = 0
        while True:
            state = control(_fixed(charger.heatsink_c, 1e6), _fixed(pack.voltage, 1e6), _fixed(pack.temp_c, 1e6),
                            out_ref)
            if state == 0:
                break
            kind = out.kind
            if kind == CURRENT:
                i = out.current_ua / 1e6
            elif kind == OFF:
                i = 0.0
            else:
                i = cfv(out.voltage_uv / 1e6, dt)
                i_max = out.current_ua / 1e6
                if kind == VOLTAGE_CHARGE:
                    i = i_max if i > i_max else (0.0 if i < 0.0 else i)
                else:
                    i = -i_max if i < -i_max else (0.0 if i > 0.0 else i)
            if i:
                i = limit(i, pack.voltage)
            v = step(i, dt)
            hs = hs_step(i, v, dt)
            if noise:
                v += gauss(0.0, noise)
            if lsb:
                v = round(v / lsb) * lsb
            ocv = pack.open_circuit_voltage() if state == 2 else 0.0
            running = measure(_fixed(v, 1e6), _fixed(i, 1e6), _fixed(pack.temp_c, 1e6), _fixed(hs, 1e6),
                              _fixed(ocv, 1e6))
            ticks += 1
            if running == 2 and ticks >= limit_ticks:
                cut = self._phases[-1]
                cut.end_tick, cut.reason = ticks, limit_reason(limit_s)
                cut.mah_in, cut.mah_out = self._phase_mah()
                self._end = limit_reason(limit_s)
                break
        return Run(None, self._phases, self._signals, self._end)

    def _phase_mah(self) -> tuple[float, float]:
        # a phase the harness cut off reports what the core counted so far
        q_in, q_out = ctypes.c_int64(), ctypes.c_int64()
        self.lib.zh_phase_counts(ctypes.byref(q_in), ctypes.byref(q_out))
        return q_in.value / 3.6e9, q_out.value / 3.6e9

    def _reason(self, e: ZcEvent) -> str:
        """The core's own text for the end (the device reports it; it must be Python's, byte for byte)."""
        n = self.lib.zh_event_text(ctypes.byref(e), self._text)
        return self._text.raw[:n].decode("ascii")

    def _event(self, e: ZcEvent) -> None:
        tick = e.time_ms // self._tick_ms
        if e.kind == EV_PHASE_START:
            section = "charge" if e.section else "discharge"
            self._phases.append(Phase(section, e.index, e.repetition, e.cycle_pass, e.offset, tick, -1, "",
                                      0.0, 0.0))
        elif e.kind == EV_PHASE_END:
            phase = self._phases[-1]
            phase.end_tick = tick
            phase.reason = self._reason(e)
            phase.mah_in, phase.mah_out = e.mah_in_x1000 / 1000, e.mah_out_x1000 / 1000
        elif e.kind == EV_FINISH:
            self._end = self._reason(e)
        else:
            name = {EV_PAUSE: "pause", EV_RESUME: "resume", EV_MUSIC: "music", EV_LIGHT: "light"}.get(e.kind)
            if name:
                self._signals.append((name, tick, e.offset if name in ("music", "light") else -1, self._reason(e)))
