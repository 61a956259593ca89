"""The charger's interpreter, emulated: runs a record's byte code tick by tick
against a battery pack and a power stage (docs/zuml-2.0.md §3).

No wall-clock time and no I/O: ``advance(n)`` runs at most n ticks and returns;
the simulator calls it until the macro ends, the virtual charger calls it in
real time. What it measured goes to ``log`` (one sample per tick) and ``events``.
"""
from __future__ import annotations

import random
from dataclasses import dataclass, field, replace
from typing import Iterator, Mapping

from ..domain import end_reasons
from ..domain.end_reasons import EndCode, EndReason, read
from ..domain.units import AS_PER_MAH, SECONDS_PER_HOUR
from ..lang import opcodes as ops
from ..lang.formatter import format_args
from ..lang.opcodes import canonical_text
from ..lang.operands import CURRENT, INPUT_U16, VOLTAGE, absolute_value
from .battery import Pack
from .charger_model import BalanceWindow, Charger
from ..domain.chemistry import load_chemistry
from .delta_peak import DeltaPeakDetector
from .program import CommandStep, DefaultDischarge, PhaseCode, Program, SectionStart
from ..domain.samples import SampleLog
from ..domain.start_templates import StartTemplate, apply_template, chosen_template, factory_templates
from ..errors import ZumlError
from ..i18n import _

# Defaults of docs/zuml-2.0.md §3. A macro's IF(Tc>x), IF(Tc<x) and IF(T>x) replace the matching default; dT/dt and
# the 1.5 x capacity guard cannot be written in ZUML and always apply.
DEFAULT_TC_PAUSE = 70
DEFAULT_TC_CONTINUE = 60
DEFAULT_T_MAX = 60.0
DEFAULT_DTDT_C_PER_MIN = 1.0
DEFAULT_CAPACITY_FACTOR = 1.5
DEFAULT_DISCHARGE_A = 0.1
# dT/dt as cheali-charger measures it: the temperature change over a 60 s window, not before 2 min.
DTDT_WINDOW_S = 60.0
HOLDING_V = 0.05            # a CV phase within this of its voltage holds it: the B6 balances there (engine.c)
DTDT_HOLDOFF_S = 120.0
# Not a charger rule: a simulation of a macro that never ends stops here, and says so. The
# charger sets no limit of its own (cheali's time limit defaults to unlimited; tm and tf are
# u32 tenths of a second, 119 304 h), so the bound is the simulator's: 1000 h holds a 10-cycle
# training of a 10 Ah pack at 0.1C (~200 h) five times over, at 30 bytes a tick (~108 MB at 1 s).
DEFAULT_LIMIT_S = 1000 * SECONDS_PER_HOUR

_CC, _CV, _PULSE, _TRICKLE = range(4)
# The conditions' codes as plain ints, from the one opcode table: the hot loop compares them every tick.
_T_GT, _V_LT, _V_GT, _I_LT, _TF_GT, _DPEAK_GT = (op.code for op in (ops.IF_T_GT, ops.IF_V_LT, ops.IF_V_GT,
                                                                   ops.IF_I_LT, ops.IF_TF_GT, ops.IF_DPEAK_GT))
# tm, tf: a charge they end is checked against the pack's state (timer before full)
_TIMERS = (ops.IF_TM_GT.code, _TF_GT)
# A pack the model holds at this state of charge or more is full: a timer ending a charge there did
# not cut it short, and the dT/dt default ending it there is the normal end of a fast nickel charge.
FULL_SOC = 0.95
AKK_NAMES = {code: name for name, code in ops.AKK_TYPE.operands[0].kind.names.items()}


class StartError(ZumlError):
    """The macro cannot start with these parameters (an INPUT value not given, ...)."""


@dataclass(frozen=True)
class StartParams:
    """What the user enters at start on the charger."""

    task: str = "charge"                # charge | discharge | train
    repetitions: int = 1                # training: discharge+charge this many times
    capacity_mah: float | None = None   # for CAPACITY=INPUT/absent and currents in C
    current_a: float | None = None      # for INPUT currents; limits a CONSTANT_V phase
    voltage_v: float | None = None      # for INPUT voltages
    series: int | None = None           # for SERIES absent and voltages in S
    sensor: bool = True                 # battery temperature sensor connected
    template: int | None = None         # start template chosen at start (a macro's START_SHABLON wins)


@dataclass(frozen=True)
class Measurement:
    """The charger's ADC: gaussian noise and quantisation of the pack voltage, seeded."""

    noise_v: float = 0.0
    lsb_v: float = 0.0
    seed: int = 1


@dataclass
class Event:
    time_s: float
    kind: str              # section | phase_start | phase_end | pause | resume | music | light | finish
    section: str = ""
    index: int = 0
    repetition: int = 0
    offset: int = -1
    detail: str = ""


@dataclass
class PhaseResult:
    section: str
    index: int
    repetition: int
    cycle_pass: int
    offset: int
    start_s: float
    end_s: float = 0.0
    reason: str = ""
    mah_in: float = 0.0
    mah_out: float = 0.0
    v_end: float = 0.0
    temp_end: float = 0.0
    soc_end: float = 0.0   # the model's state of charge (a simulator can know it; a charger cannot)
    run: int = 0           # sequential number of the phase in this run, 1-based
    pauses: list = field(default_factory=list)   # [start_s, end_s] of each heat-sink pause in this phase
    clip_asked_a: float = 0.0      # the first current the charger's limits cut: what the macro asked ...
    clip_given_a: float = 0.0      # ... what the charger gave ...
    clip_limit: str = ""           # ... and which limit ("5 W discharge limit"); "" when never cut
    clipped_s: float = 0.0         # how long the limits cut the current in this phase
    timer_before_full: bool = False   # a charge ended by a timer (tf or tm) before the pack was full
    cells_end: tuple = ()          # each cell's voltage at the end (a pack of more than one cell)
    bled_s: tuple = ()             # how long the balancer bled each cell in this phase, s

    @property
    def by_default(self) -> bool:
        """Ended by one of the charger's default safety conditions (or its balancer), not by the macro's own."""
        return read(self.reason).by_default

    @property
    def full_by_dtdt(self) -> bool:
        """A charge the dT/dt default ended once the pack was full. ZUML cannot write dT/dt; with a
        sensor the charger always watches it (docs/zuml-2.0.md §3), and a nickel pack charged at about 1C warms
        by 1 °C/min as it becomes full, minutes before its -dV (the dT/dt method): the charger's
        normal end of a fast charge, not something the user must act on."""
        return (self.section == "charge" and read(self.reason).code is EndCode.DEFAULT_DTDT
                and self.soc_end >= FULL_SOC)

    @property
    def warns(self) -> bool:
        """Worth a warning sign: a default ended it (other than the dT/dt of a full pack), or a
        timer cut a charge before the pack was full."""
        return (self.by_default and not self.full_by_dtdt) or self.timer_before_full

    @property
    def paused_s(self) -> float:
        return sum(end - start for start, end in self.pauses)

    @property
    def clip_text(self) -> str:
        """'asked 2.00 A, charger gave 1.00 A: 5 W discharge limit', or ''."""
        if not self.clip_limit:
            return ""
        return _("asked {asked} A, charger gave {given} A: {limit}").format(
            asked=f"{abs(self.clip_asked_a):.2f}", given=f"{abs(self.clip_given_a):.2f}", limit=self.clip_limit)

    @property
    def notes(self) -> list[str]:
        """What a phase row must say besides its end reason."""
        out = []
        if self.timer_before_full:
            out.append(_("timer before full: {mah} mAh put in").format(mah=f"{self.mah_in:.0f}"))
        if self.pauses:
            out.append(_("heat-sink pause {n}x, {minutes} min").format(n=len(self.pauses),
                                                                        minutes=f"{self.paused_s / 60:.0f}"))
        if self.clip_limit:
            out.append(self.clip_text)
        # Under half a minute would read "0 min": a phase that ends seconds after another says nothing.
        bled = [(k, s) for k, s in enumerate(self.bled_s, 1) if s >= 30.0]
        if bled:
            out.append(_("balancer: {cells}").format(cells=", ".join(
                _("cell {k} {minutes} min").format(k=k, minutes=f"{s / 60:.0f}") for k, s in bled)))
        return out


@dataclass
class _Active:
    """A phase being run, its byte code turned into numbers once at its start."""

    result: PhaseResult
    mode: int
    charging: bool
    i_set: float = 0.0              # signed A
    v_set: float = 0.0              # pack V
    i_max: float = 0.0
    pulse: tuple = ()
    trickle: tuple = ()
    trickle_on: bool = True
    conditions: list = field(default_factory=list)     # (code, threshold, reason)
    own_t: bool = False
    detector: DeltaPeakDetector | None = None
    dpeak: tuple | None = None                          # (threshold, reason)
    t_phase: float = 0.0
    q_in: float = 0.0                                   # A·s
    q_out: float = 0.0
    measured_v: float = 0.0
    dtdt_t0: float = 0.0
    dtdt_next: float = DTDT_WINDOW_S
    default_end_v: float | None = None                  # empty discharge section
    by_timer: bool = False                              # ended by IF(tf>x) or IF(tm>x)
    bled_ticks: list = field(default_factory=list)      # per cell: ticks the balancer bled it
    window: BalanceWindow = field(default_factory=BalanceWindow)   # the balancer's, across runs of ticks


class Interpreter:
    def __init__(self, record: bytes, params: StartParams, pack: Pack, charger: Charger, *,
                 tick_s: float = 1.0, measurement: Measurement = Measurement(),
                 limit_s: float = DEFAULT_LIMIT_S, templates: Mapping[int, StartTemplate] | None = None):
        """``templates``: the charger's start templates (default: the factory table)."""
        self.program = Program(record)
        self.params = with_template(self.program, params, templates)
        self.pack = pack
        self.charger = charger
        self.tick_s = float(tick_s)
        self.limit_s = limit_s
        self.measurement = measurement
        self._rng = random.Random(measurement.seed)
        self._per_cell = pack.per_cell and pack.series > 1
        self.log = SampleLog(pack.series, self._per_cell)
        # The balancer works on a pack whose cells the model holds apart (identical cells: nothing to
        # bleed, and each cell is the pack's voltage / N, which the macro's own end governs).
        spec = charger.limits.balancer
        self._balancer = spec if spec and self._per_cell and pack.chem.name in spec.ceiling_v else None
        self.events: list[Event] = []
        self.phases: list[PhaseResult] = []
        self.time_s = 0.0
        self.q_in = 0.0                     # A·s, whole run
        self.q_out = 0.0
        self.paused = False
        self.finished = False
        self.end_reason = ""
        self._stop_reason = ""              # IF(tm>x) STOP_MACRO fired: the conclusion runs, then this ends it
        self._resolve_start()
        self._steps: Iterator[object] = self.program.steps(self.params.task, self.params.repetitions)
        self._active: _Active | None = None
        self._section = ""
        self._repetition = 0

    # -- start-up: what the introduction and the start parameters decide -------------------
    def _resolve_start(self) -> None:
        decl = self.program.intro.declarations
        p = self.params
        self.capacity_ah = self.program.intro.capacity_ah(p.capacity_mah)
        self.series = self.program.intro.series(p.series)
        self.akk_type = decl.get(ops.AKK_TYPE.code, 0)
        cond = self.program.intro.conditions
        tc_gt, tc_lt, tm_gt = ops.IF_TC_GT.code, ops.IF_TC_LT.code, ops.IF_TM_GT.code
        self.tc_pause = cond[tc_gt].raws[0] if tc_gt in cond else DEFAULT_TC_PAUSE
        self.tc_continue = cond[tc_lt].raws[0] if tc_lt in cond else DEFAULT_TC_CONTINUE
        self.tm_stop = (cond[tm_gt].raws[0] / 10.0, _reason(cond[tm_gt])) if tm_gt in cond else None
        if p.repetitions < 1:
            raise StartError(_("training needs at least 1 repetition"))
        # As the charger asks for every INPUT value at start: a missing one is an error now, not mid-run.
        for step in self.program.steps(p.task):
            for ins in (step.actions + step.conditions) if isinstance(step, PhaseCode) else ():
                for operand, raw in zip(ins.op.operands, ins.raws):
                    if operand.kind is CURRENT:
                        self.current(raw)
                    elif operand.kind is VOLTAGE:
                        self.voltage(raw)

    def current(self, raw: int) -> float:
        amps = absolute_value(raw, self.params.current_a, self.capacity_ah)
        if amps is not None:
            return round(amps, 6)   # the charger's fixed point: 1 µA
        raise StartError(_("the macro takes a current at start (INPUT): give the current") if raw == INPUT_U16
                         else _("a current in C needs the capacity: declare CAPACITY or give it at start"))

    def voltage(self, raw: int) -> float:
        volts = absolute_value(raw, self.params.voltage_v, self.series)
        if volts is not None:
            return round(volts, 6)  # the charger's fixed point: 1 µV
        raise StartError(_("the macro takes a voltage at start (INPUT): give the voltage") if raw == INPUT_U16
                         else _("a voltage per cell (S) needs the cell count: declare SERIES or give it at start"))

    # -- running ----------------------------------------------------------------------------
    def stop(self, reason: EndReason = end_reasons.STOPPED) -> None:
        if self._active:
            self._end_phase(self._active, reason)
        self._finish(reason)

    def run(self) -> None:
        """To the end of the macro (or the simulation limit)."""
        while not self.finished:
            self.advance(1 << 30)

    def advance(self, max_ticks: int) -> bool:
        """Run at most ``max_ticks`` ticks; returns False once the macro has ended."""
        left = max_ticks
        while left > 0 and not self.finished:
            if self._active is None and not self._next_phase():
                break
            left -= self._ticks(self._active, min(left, self.log.room))
            self.log.seal_if_full()
        if self.finished:
            self.log.seal()
        return not self.finished

    def _next_phase(self) -> bool:
        for step in self._steps:
            if isinstance(step, SectionStart):
                self._section, self._repetition = step.section, step.repetition
                self._event("section", section=step.section, repetition=step.repetition)
            elif isinstance(step, CommandStep):
                kind = "music" if step.op is ops.MUSIC else "light"
                self._event(kind, offset=step.offset,
                            detail=canonical_text(step.op, format_args(step.op, step.raws)))
            elif isinstance(step, (PhaseCode, DefaultDischarge)):
                self._active = self._start_phase(step)
                return True
        self._finish(self._stop_reason or end_reasons.END_OF_MACRO)
        return False

    def _start_phase(self, code: PhaseCode | DefaultDischarge) -> _Active:
        if isinstance(code, DefaultDischarge):
            result = PhaseResult("discharge", 0, code.repetition, 0, code.offset, self.time_s)
        else:
            result = PhaseResult(code.section, code.index, code.repetition, code.cycle_pass, code.offset,
                                 self.time_s)
        result.run = len(self.phases) + 1
        self.phases.append(result)
        charging = result.section == "charge"
        if self.paused:
            result.pauses.append([self.time_s, self.time_s])
        if isinstance(code, DefaultDischarge):
            end_v = self._chemistry_end_v()
            active = _Active(result, _CC, False, i_set=-DEFAULT_DISCHARGE_A, default_end_v=end_v * (self.series or 1))
            active.conditions.append((_V_LT, active.default_end_v,
                                      EndReason(EndCode.DEFAULT_EMPTY_DISCHARGE, end_v=end_v)))
        else:
            active = self._compile(code, result, charging)
        if self._per_cell:
            active.bled_ticks = [0] * self.pack.series
        active.dtdt_t0 = self.pack.temp_c
        active.measured_v = self.pack.voltage
        self._event("phase_start", section=result.section, index=result.index, repetition=result.repetition,
                    offset=result.offset)
        return active

    def _chemistry_end_v(self) -> float:
        name = AKK_NAMES.get(self.akk_type, "UNDEF")
        try:
            return load_chemistry(name).discharge_end_v
        except KeyError:
            # No defaults for Undef/LiS/New: the battery model's own chemistry stands in.
            return self.pack.chem.discharge_end_v

    def _compile(self, code: PhaseCode, result: PhaseResult, charging: bool) -> _Active:
        by_op = {a.op: a for a in code.actions}
        sign = 1.0 if charging else -1.0
        limits = self.charger.limits
        if ops.CHARGE_EX in by_op:
            tch, ich, tdis, idis, tv = by_op[ops.CHARGE_EX].raws
            active = _Active(result, _PULSE, True, pulse=(float(tch), self.current(ich), float(tdis),
                                                          self.current(idis), tv))
        elif ops.TRICKLE in by_op:
            i, v1, v2 = by_op[ops.TRICKLE].raws
            active = _Active(result, _TRICKLE, True, trickle=(self.current(i), self.voltage(v1), self.voltage(v2)))
        elif ops.CONSTANT_I in by_op and ops.CONSTANT_V in by_op:
            # CC-CV: the voltage is held with the current limited to CONSTANT_I, in either direction.
            i = self.current(by_op[ops.CONSTANT_I].raws[0])
            active = _Active(result, _CV, charging, v_set=self.voltage(by_op[ops.CONSTANT_V].raws[0]), i_max=i)
        elif ops.CONSTANT_V in by_op:
            fallback = limits.max_charge_a if charging else limits.max_discharge_a
            i_max = self.params.current_a if self.params.current_a else fallback
            active = _Active(result, _CV, charging, v_set=self.voltage(by_op[ops.CONSTANT_V].raws[0]), i_max=i_max)
        else:
            active = _Active(result, _CC, charging, i_set=sign * self.current(by_op[ops.CONSTANT_I].raws[0]))
        for ins in code.conditions:
            c = ins.op.code
            raw = ins.raws[0]
            reason = _reason(ins)
            if c == _T_GT:
                active.own_t = True
                threshold = float(raw)
            elif c in (_V_LT, _V_GT, _DPEAK_GT):
                threshold = self.voltage(raw)
            elif c == _I_LT:
                threshold = self.current(raw)
            else:   # IF(tf>x): tenths of a second
                threshold = raw / 10.0
            if c == _DPEAK_GT:
                active.detector = DeltaPeakDetector(limits.dpeak_window_s, limits.dpeak_holdoff_s)
                active.dpeak = (threshold, reason)
            else:
                active.conditions.append((c, threshold, reason))
        return active

    def _ticks(self, a: _Active, max_ticks: int) -> int:
        """The hot loop: one phase, at most max_ticks ticks. Returns the ticks run."""
        pack, charger, log = self.pack, self.charger, self.log
        dt = self.tick_s
        step, hs_step, limit = pack.step, charger.step, charger.limit_current
        cfv = pack.current_for_voltage
        mode = a.mode
        sensor = self.params.sensor
        noise, lsb = self.measurement.noise_v, self.measurement.lsb_v
        gauss = self._rng.gauss
        conds = a.conditions
        detector = a.detector
        dpeak = a.dpeak
        # Rounded to µA·s (and the count to nA·s below): 1.5 × 0.3 Ah is 1619.9999999999998 A·s in
        # floats, and 36 × 0.3 A·s sums to a hair over 10.8; the charger's integer count is exact.
        cap_limit = (round(DEFAULT_CAPACITY_FACTOR * self.capacity_ah * SECONDS_PER_HOUR, 6) if self.capacity_ah
                     else None)
        check_defaults = a.result.section == "charge"
        t_max_default = not a.own_t
        tm_stop = self.tm_stop
        section_code = 1 if a.result.section == "charge" else 0
        ceiling = self._balancer if section_code else None
        bleeder = ceiling if ceiling is not None and (ceiling.during == "charge" or mode == _CV) else None
        ceiling_v = ceiling.ceiling_v[pack.chem.name] if ceiling is not None else None
        per_cell = self._per_cell
        chem_name = pack.chem.name
        window = a.window
        mask = window.mask
        bled = a.bled_ticks
        run_no = a.result.run
        pauses = a.result.pauses
        ticks = 0
        while ticks < max_ticks:
            ticks += 1
            hs = charger.heatsink_c
            if per_cell:
                # decided on the cells' last readings, bleeding over this tick
                if bleeder is not None and not self.paused:
                    mask = bleeder.window(window, pack.cell_voltages, dt, mode == _CV and a.charging and
                                          pack.voltage >= a.v_set - HOLDING_V, chem_name)
                else:
                    mask = window.mask = 0
                pack.set_bleed(mask, bleeder)
            if self.paused:
                if hs < self.tc_continue:
                    self.paused = False
                    pauses[-1][1] = self.time_s
                    self._event("resume", detail=f"Tc<{self.tc_continue}")
                i = 0.0
            elif hs > self.tc_pause:
                self.paused = True
                pauses.append([self.time_s, self.time_s])
                self._event("pause", detail=f"Tc>{self.tc_pause}")
                i = 0.0
            elif mode == _CC:
                i = a.i_set
            elif mode == _CV:
                i = cfv(a.v_set, dt)
                if a.charging:
                    i = a.i_max if i > a.i_max else (0.0 if i < 0.0 else i)
                else:
                    i = -a.i_max if i < -a.i_max else (0.0 if i > 0.0 else i)
            elif mode == _TRICKLE:
                ti, v1, v2 = a.trickle
                if a.trickle_on and a.measured_v >= v2:
                    a.trickle_on = False
                elif not a.trickle_on and a.measured_v <= v1:
                    a.trickle_on = True
                i = ti if a.trickle_on else 0.0
            else:
                tch, ich, tdis, idis, _ = a.pulse
                i = ich if a.t_phase % (tch + tdis) < tch else -idis
            own = (0.0 if mode == _CV else i) if i > 0.0 else -1.0   # the held end's share (ceiling_reason)
            if ceiling_v is not None and i > 0.0:
                i = pack.current_for_ceiling(i, ceiling_v, dt)
            if i:
                asked = i
                i = limit(i, pack.voltage)
                if i != asked:
                    self._clipped(a, asked, i)
            v = step(i, dt)
            hs = hs_step(i, v, dt)
            self.time_s += dt
            if not self.paused:
                a.t_phase += dt
            if i > 0.0:
                a.q_in += i * dt
                self.q_in += i * dt
            else:
                a.q_out -= i * dt
                self.q_out -= i * dt
            if noise:
                v += gauss(0.0, noise)
            if lsb:
                v = round(v / lsb) * lsb
            v = round(v, 6)     # measured to 1 µV, as the firmware's fixed point: no decision on float dust
            if mode == _PULSE:
                v = self._pulse_measurement(a, v)
            a.measured_v = v
            temp = pack.temp_c
            log.append(self.time_s, section_code, run_no, v, i, temp, hs, self.q_in / AS_PER_MAH,
                       self.q_out / AS_PER_MAH)
            if per_cell:
                log.append_cells(pack.cell_voltages, mask)
                if mask:
                    for k in range(len(bled)):
                        if mask >> k & 1:
                            bled[k] += 1
            # -- end conditions: the macro's own first, then the defaults ------------------
            reason = None
            for c, x, text in conds:
                if (c == _V_GT and v > x) or (c == _V_LT and v < x) or (c == _TF_GT and a.t_phase > x) or \
                        (c == _I_LT and round(abs(i), 6) < x and not self.paused) or \
                        (c == _T_GT and sensor and temp > x):
                    reason = text
                    a.by_timer = c == _TF_GT
                    break
            if reason is None and detector is not None and not self.paused:
                if detector.update(a.t_phase, v) > dpeak[0]:
                    reason = dpeak[1]
            if reason is None and ceiling is not None:
                reason = ceiling.ceiling_reason(chem_name, pack.cell_voltages, i, own, pack.bleed_a)
            if reason is None:
                if sensor:
                    if t_max_default and temp > DEFAULT_T_MAX:
                        reason = EndReason(EndCode.DEFAULT_T, limit_c=DEFAULT_T_MAX)
                    elif check_defaults and a.t_phase >= a.dtdt_next:
                        rate = (temp - a.dtdt_t0) * 60.0 / DTDT_WINDOW_S
                        a.dtdt_t0, a.dtdt_next = temp, a.dtdt_next + DTDT_WINDOW_S
                        if a.t_phase > DTDT_HOLDOFF_S and rate > DEFAULT_DTDT_C_PER_MIN:
                            reason = EndReason(EndCode.DEFAULT_DTDT, rate=DEFAULT_DTDT_C_PER_MIN)
                elif check_defaults and cap_limit is not None and round(a.q_in, 9) > cap_limit:
                    reason = EndReason(EndCode.DEFAULT_CAPACITY, factor=DEFAULT_CAPACITY_FACTOR)
            if reason is None and tm_stop is not None and self.time_s > tm_stop[0]:
                # STOP_MACRO: the remaining phases and sections are skipped; the conclusion still runs.
                a.by_timer = True
                self._end_phase(a, tm_stop[1])
                self._stop_reason = tm_stop[1]
                self._steps = self.program.conclusion_steps()
                return ticks
            if reason is None and self.time_s >= self.limit_s:
                reason = EndReason(EndCode.SIM_LIMIT, hours=self.limit_s / SECONDS_PER_HOUR)
                self._end_phase(a, reason)
                self._finish(reason)
                return ticks
            if reason is not None:
                self._end_phase(a, reason)
                return ticks
        return ticks

    def _clipped(self, a: _Active, asked: float, given: float) -> None:
        r = a.result
        if not r.clip_limit:
            r.clip_asked_a, r.clip_given_a = asked, given
            r.clip_limit = self.charger.clip_reason(asked, self.pack.voltage)
        r.clipped_s += self.tick_s

    def _pulse_measurement(self, a: _Active, v: float) -> float:
        """CHARGE_EX measures once a period, at the point tV chooses; in between the last reading holds."""
        tch, _, tdis, _, tv = a.pulse
        period = tch + tdis
        at = a.t_phase % period
        if tv == 1 and at == tch % period:
            return v                                         # end of the charge pulse
        if tv == 2 and at == 0.0:
            return v                                         # end of the discharge pulse
        if tv == 0 and at == 0.0:
            return self.pack.open_circuit_voltage()          # power stage off
        return a.measured_v

    def _end_phase(self, a: _Active, reason: EndReason) -> None:
        r = a.result
        r.end_s = self.time_s
        r.reason = reason
        r.mah_in = a.q_in / AS_PER_MAH
        r.mah_out = a.q_out / AS_PER_MAH
        r.v_end = a.measured_v
        r.temp_end = self.pack.temp_c
        r.soc_end = self.pack.soc
        if self._per_cell:
            self.pack.set_bleed(0, None)     # the balancer stops with the phase
            r.bled_s = tuple(n * self.tick_s for n in a.bled_ticks)
        series = self.pack.series
        if series > 1:
            r.cells_end = (tuple(self.pack.cell_voltages) if self._per_cell
                           else (self.pack.voltage / series,) * series)
        if r.pauses and self.paused:
            r.pauses[-1][1] = self.time_s
        r.timer_before_full = bool(a.by_timer and r.section == "charge" and r.soc_end < FULL_SOC)
        self._active = None
        self._event("phase_end", section=r.section, index=r.index, repetition=r.repetition, offset=r.offset,
                    detail=reason)

    def _finish(self, reason: EndReason) -> None:
        if not self.finished:
            self.finished = True
            self.end_reason = reason
            self._event("finish", detail=reason)

    def _event(self, kind: str, **fields) -> None:
        self.events.append(Event(self.time_s, kind, **fields))


def with_template(program: Program, params: StartParams,
                  templates: Mapping[int, StartTemplate] | None = None) -> StartParams:
    """The start values after the start template (the macro's START_SHABLON=n, else the one chosen at
    start); StartError when the charger has no such template."""
    number = chosen_template(program.intro.declarations.get(ops.START_SHABLON.code), params.template)
    if number is None:
        return params
    table = factory_templates() if templates is None else templates
    template = table.get(number)
    if template is None:
        stored = ", ".join(str(n) for n in sorted(table)) or "none"
        how = f"START_SHABLON={number}" if ops.START_SHABLON.code in program.intro.declarations else "chosen at start"
        raise StartError(_("start template {number} ({how}) does not exist on this charger (templates: "
                           "{stored})").format(
                number=number, how=how, stored=stored))
    return replace(apply_template(params, template), template=number)


def _reason(ins) -> EndReason:
    """A condition's end reason: its canonical text."""
    return end_reasons.condition(canonical_text(ins.op, format_args(ins.op, ins.raws)))

