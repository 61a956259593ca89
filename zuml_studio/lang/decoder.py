"""Bytes -> macro, total: any byte string gives a Decoded or a DecodeError with
the offset and what was expected. Never another exception, never a loop that
does not advance (every instruction read moves the program counter forward)."""
from __future__ import annotations

from dataclasses import dataclass

from . import opcodes as ops
from .ast import Arg, Cycle, Macro, Phase, Section, Statement
from .checker import check, name_problem
from .diagnostics import Severity
from .opcodes import Role
from .record import (HEADER_SIZE, MAX_NAME, MIN_RECORD, DecodeError, Instruction, check_byte,
                     read_instruction)
from ..i18n import _, ngettext


@dataclass(frozen=True)
class Decoded:
    macro: Macro
    instructions: tuple[Instruction, ...]
    record: bytes


class _Reader:
    def __init__(self, data: bytes, start: int, end: int):
        self.data, self.pc, self.end = data, start, end
        self.instructions: list[Instruction] = []

    def peek(self) -> Instruction:
        return read_instruction(self.data, self.pc, self.end)

    def take(self) -> Instruction:
        ins = self.peek()
        self.pc += ins.size
        self.instructions.append(ins)
        return ins

    def expect(self, op: ops.Op, where: str) -> Instruction:
        ins = self.take()
        if ins.op is not op:
            raise DecodeError(ins.offset, _("expected {keyword} ({code}) {where}, found {found}").format(
                    keyword=op.keyword, code=op.code, where=where, found=ins.op.keyword))
        return ins


def _statement(ins: Instruction) -> Statement:
    return Statement(ins.op, [Arg(r) for r in ins.raws], offset=ins.offset)


def _header(data: bytes) -> tuple[int, str, int]:
    if not data:
        raise DecodeError(0, _("no bytes: a record starts with its length"))
    length = data[0]
    if length < MIN_RECORD:
        raise DecodeError(0, _("record length {length} is below the minimum {min_record}").format(
                length=length, min_record=MIN_RECORD))
    if len(data) < length:
        raise DecodeError(len(data), _("the record says {length} bytes but only {n_data} are there").format(
                length=length, n_data=len(data)))
    if len(data) > length:
        extra = len(data) - length
        raise DecodeError(length, ngettext("{n_data} byte follows the record's end at {length} (an EEPROM image? use "
                                           "the image commands)",
                                           "{n_data} bytes follow the record's end at {length} (an EEPROM image? use "
                                           "the image commands)", extra).format(n_data=extra, length=length))
    expected = check_byte(data[:length - 1])
    if data[length - 1] != expected:
        raise DecodeError(length - 1, _("check byte is 0x{data:02x}, expected 0x{expected:02x}").format(
                data=data[length - 1], expected=expected))
    zero = data.find(0, HEADER_SIZE, min(length - 1, HEADER_SIZE + MAX_NAME + 1))
    if zero < 0:
        raise DecodeError(HEADER_SIZE, _("the name has no terminating 0 within {max_name} characters").format(
                max_name=MAX_NAME))
    name = data[HEADER_SIZE:zero].decode("latin-1")
    problem = name_problem(name)
    if problem:
        raise DecodeError(HEADER_SIZE, problem[1])
    start = zero + 1
    if data[1] != start:
        raise DecodeError(1, _("program start offset is {data}, expected {start} (right after the name)").format(
                data=data[1], start=start))
    return length, name, start


def decode_record(data: bytes) -> Decoded:
    """Raises only DecodeError."""
    data = bytes(data)
    length, name, start = _header(data)
    r = _Reader(data, start, length - 1)
    macro = Macro(name)
    while r.peek().op is not ops.DISCHARGE_SECTION:
        ins = r.take()
        if ins.op.role is Role.STRUCTURE:
            raise DecodeError(ins.offset, _("expected DISCHARGE_SECTION (3), found {keyword}").format(
                    keyword=ins.op.keyword))
        macro.intro.append(_statement(ins))
    r.take()
    macro.discharge = _section(r, "discharge")
    while r.peek().op.role is not Role.STRUCTURE:
        macro.between.append(_statement(r.take()))
    r.expect(ops.CHARGE_SECTION, _("after the discharge section"))
    if data[2] != r.pc:
        raise DecodeError(2, _("charge section offset is {data}, expected {pc}").format(data=data[2], pc=r.pc))
    macro.charge = _section(r, "charge")
    if data[3] != r.pc:
        raise DecodeError(3, _("conclusion offset is {data}, expected {pc}").format(data=data[3], pc=r.pc))
    while True:
        ins = r.take()
        if ins.op is ops.END_MACRO:
            break
        if ins.op.role is Role.STRUCTURE:
            raise DecodeError(ins.offset, _("{keyword} cannot follow the charge section").format(
                    keyword=ins.op.keyword))
        macro.conclusion.append(_statement(ins))
    if r.pc != length - 1:
        raise DecodeError(r.pc, _("END_MACRO at {pc} but the program runs on to {length}").format(
                pc=r.pc - 1, length=length - 2))
    for finding in check(macro):
        if finding.severity is Severity.ERROR:
            raise DecodeError(_offset(finding.node, start), finding.message)
    return Decoded(macro, tuple(r.instructions), data)


def _section(r: _Reader, kind: str) -> Section:
    items: list = []
    stack: list[list] = [items]
    open_blocks: list[Cycle | Phase] = []
    while True:
        ins = r.take()
        op = ins.op
        if op is ops.END_SECTION:
            if open_blocks:
                block = open_blocks[-1]
                closer = "END_FAZE" if isinstance(block, Phase) else "END_CYCLE"
                raise DecodeError(ins.offset, _("{closer} expected before END_SECTION (block at {offset})").format(
                        closer=closer, offset=block.offset))
            return Section(kind, items, present=bool(items))
        in_phase = bool(open_blocks) and isinstance(open_blocks[-1], Phase)
        if op is ops.FAZE:
            if in_phase:
                raise DecodeError(ins.offset, _("FAZE inside a phase: END_FAZE expected first"))
            phase = Phase([], offset=ins.offset)
            stack[-1].append(phase)
            open_blocks.append(phase)
        elif op is ops.END_FAZE:
            if not in_phase:
                raise DecodeError(ins.offset, _("END_FAZE without FAZE"))
            open_blocks.pop()
        elif op is ops.CYCLE:
            if in_phase:
                raise DecodeError(ins.offset, _("CYCLE inside a phase: END_FAZE expected first"))
            cycle = Cycle(Arg(ins.raws[0]), [], offset=ins.offset)
            stack[-1].append(cycle)
            stack.append(cycle.items)
            open_blocks.append(cycle)
        elif op is ops.END_CYCLE:
            if not open_blocks or in_phase:
                raise DecodeError(ins.offset, _("END_CYCLE without CYCLE") if not open_blocks
                                  else _("END_FAZE expected before END_CYCLE"))
            open_blocks.pop()
            stack.pop()
        elif op.role is Role.STRUCTURE:
            raise DecodeError(ins.offset, _("{keyword} cannot stand inside a section").format(keyword=op.keyword))
        elif in_phase:
            open_blocks[-1].statements.append(_statement(ins))
        else:
            stack[-1].append(_statement(ins))


def _offset(node: object, default: int) -> int:
    offset = getattr(node, "offset", None)
    return default if offset is None else offset
