"""Walks a record's byte code the way the charger's firmware does: a program
counter over the bytes, one ``read_instruction`` at a time. It yields what the
interpreter must do next (run a phase, play a melody, ...) and never looks at
text or the AST; the record is validated by the decoder before it runs.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Iterator

from ..domain.units import MAH_PER_AH
from ..lang import opcodes as ops
from ..lang.decoder import decode_record
from ..lang.opcodes import Op, Role
from ..lang.operands import CAPACITY_AUTO, CAPACITY_INPUT
from ..lang.record import HEADER_SIZE, Instruction, read_instruction
from ..domain.tasks import TASKS
from ..i18n import _


@dataclass(frozen=True)
class PhaseCode:
    """The instructions of one phase as stored: its action(s) and conditions."""

    section: str                  # "discharge" | "charge"
    index: int                    # 1-based position of this FAZE in its section's text
    offset: int                   # byte offset of the FAZE opcode (links back to the source)
    actions: tuple[Instruction, ...]
    conditions: tuple[Instruction, ...]
    repetition: int               # training repetition, 1-based
    cycle_pass: int = 0           # pass of the enclosing CYCLE, 1-based; 0 outside a cycle


@dataclass(frozen=True)
class CommandStep:
    op: Op
    raws: tuple[int, ...]
    offset: int


@dataclass(frozen=True)
class DefaultDischarge:
    """An empty discharge section: the firmware discharges at 0.1 A to the chemistry's end voltage."""

    repetition: int
    offset: int                   # the empty section's DISCHARGE_SECTION byte


@dataclass(frozen=True)
class SectionStart:
    section: str
    repetition: int


@dataclass
class Introduction:
    declarations: dict[int, int] = field(default_factory=dict)      # opcode -> raw (AKK_TYPE, SERIES, ...)
    conditions: dict[int, Instruction] = field(default_factory=dict)  # macro-wide: Tc>, Tc<, tm>

    def capacity_ah(self, entered_mah: float | None) -> float | None:
        """The capacity C units refer to: the macro's CAPACITY, else (INPUT, AUTO or none) the
        one entered at start; None when neither is known."""
        cap = self.declarations.get(ops.CAPACITY.code)
        if cap is not None and cap not in (CAPACITY_INPUT, CAPACITY_AUTO):
            return cap / MAH_PER_AH
        return entered_mah / MAH_PER_AH if entered_mah else None

    def series(self, entered: int | None) -> int | None:
        """The cell count S units refer to: the macro's SERIES, else the one entered at start."""
        return self.declarations.get(ops.SERIES.code) or entered


class Program:
    def __init__(self, record: bytes):
        decode_record(record)          # raises DecodeError: never run bytes the compiler could not produce
        self.record = bytes(record)
        self.end = len(self.record) - 1
        self.name = self.record[HEADER_SIZE:self.record[1] - 1].decode("ascii")
        self.intro, self.discharge_at = self._introduction()
        self.between_at = self._after_section(self.discharge_at)
        self.charge_at = self.record[2]
        self.conclusion_at = self.record[3]

    def _read(self, pc: int) -> Instruction:
        return read_instruction(self.record, pc, self.end)

    def _introduction(self) -> tuple[Introduction, int]:
        intro = Introduction()
        pc = self.record[1]
        while True:
            ins = self._read(pc)
            if ins.op is ops.DISCHARGE_SECTION:
                return intro, pc + ins.size
            if ins.op.role is Role.CONDITION:
                intro.conditions[ins.op.code] = ins
            else:
                intro.declarations[ins.op.code] = ins.raws[0]
            pc += ins.size

    def _after_section(self, pc: int) -> int:
        """The byte after the END_SECTION that closes the section starting at ``pc``."""
        while True:
            ins = self._read(pc)
            pc += ins.size
            if ins.op is ops.END_SECTION:
                return pc

    def _commands(self, pc: int, until: ops.Op) -> Iterator[CommandStep]:
        while True:
            ins = self._read(pc)
            if ins.op is until:
                return
            yield CommandStep(ins.op, ins.raws, ins.offset)
            pc += ins.size

    def conclusion_steps(self) -> Iterator[CommandStep]:
        return self._commands(self.conclusion_at, ops.END_MACRO)

    def steps(self, task: str, repetitions: int = 1) -> Iterator[object]:
        """What the firmware does for a task, in order. Training repeats discharge+charge.

        Commands between the two sections run right after the discharge section, as the firmware
        reads on from it (discharge and training); a charge-only run jumps to the charge section
        (header byte 2) and skips them."""
        if task not in TASKS:
            raise ValueError(_("task must be one of {tasks}").format(tasks=', '.join(TASKS)))
        reps = repetitions if task == "train" else 1
        for rep in range(1, reps + 1):
            if task in ("discharge", "train"):
                yield SectionStart("discharge", rep)
                ran = yield from self._section(self.discharge_at, "discharge", rep)
                if not ran:
                    yield DefaultDischarge(rep, self.discharge_at - 1)
                yield from self._commands(self.between_at, ops.CHARGE_SECTION)
            if task in ("charge", "train"):
                yield SectionStart("charge", rep)
                yield from self._section(self.charge_at, "charge", rep)
        yield from self.conclusion_steps()

    def _section(self, pc: int, section: str, rep: int) -> Iterator[object]:
        """Runs one section from ``pc``; returns whether any phase ran."""
        faze_index = 0
        ran = False
        loop: list[int] = []            # [remaining, pc after CYCLE, pass, first faze index]
        while True:
            ins = self._read(pc)
            op = ins.op
            pc += ins.size
            if op is ops.END_SECTION:
                return ran
            if op is ops.CYCLE:
                loop = [ins.raws[0], pc, 1, faze_index]
            elif op is ops.END_CYCLE:
                loop[0] -= 1
                if loop[0] > 0:
                    pc, loop[2], faze_index = loop[1], loop[2] + 1, loop[3]
                else:
                    loop = []
            elif op is ops.FAZE:
                faze_index += 1
                actions, conditions = [], []
                start = ins.offset
                while True:
                    inner = self._read(pc)
                    pc += inner.size
                    if inner.op is ops.END_FAZE:
                        break
                    (actions if inner.op.role is Role.ACTION else conditions).append(inner)
                ran = True
                yield PhaseCode(section, faze_index, start, tuple(actions), tuple(conditions), rep,
                                loop[2] if loop else 0)
            else:
                yield CommandStep(op, ins.raws, ins.offset)
