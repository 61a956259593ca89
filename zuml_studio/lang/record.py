"""The byte record (docs/zuml-2.0.md §2): one instruction codec, the encoder, the check byte.

``read_instruction`` is the only place that turns bytes into an instruction;
the decoder, the listing and the interpreter all call it.
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import reduce
from operator import xor

from . import opcodes as ops
from .ast import Cycle, Macro, Phase
from .opcodes import Op
from ..errors import ZumlError, error_text
from ..i18n import _, ngettext

HEADER_SIZE = 4
MAX_RECORD = 255
MIN_RECORD = 10
MAX_NAME = 16


class DecodeError(ZumlError):
    """Bytes that are not a valid record: where, and what was expected."""

    def __init__(self, offset: int, message: str):
        super().__init__(_("offset {offset}: {message}").format(offset=offset, message=message))
        self.offset = offset
        self.message = message

    def words(self, action: str = "") -> str:
        if action in ("flash", "restore"):
            return _("Nothing was written: the compiled macro does not decode ({error}).").format(error=error_text(self))
        return super().words(action)


class RecordTooLarge(ZumlError):
    def __init__(self, size: int, node: object):
        super().__init__(_("the macro needs {size} bytes; a record holds at most {max_record}").format(
            size=size, max_record=MAX_RECORD))
        self.size = size
        self.node = node


@dataclass(frozen=True)
class Instruction:
    offset: int
    op: Op
    raws: tuple[int, ...]
    size: int


def check_byte(data: bytes) -> int:
    """XOR of every byte given (docs/zuml-2.0.md §2 decision)."""
    return reduce(xor, data, 0)


def encode_operand(raw: int, size: int, signed: bool) -> bytes:
    return raw.to_bytes(size, "little", signed=signed)


def encode_instruction(op: Op, raws: tuple[int, ...]) -> bytes:
    out = bytearray([op.code])
    for operand, raw in zip(op.operands, raws):
        out += encode_operand(raw, operand.kind.size, operand.kind.signed)
    return bytes(out)


def read_instruction(data: bytes, pc: int, end: int) -> Instruction:
    """The instruction at ``pc``; ``end`` is where the program stops (the check byte)."""
    if pc >= end:
        raise DecodeError(pc, _("the program ends without END_MACRO"))
    code = data[pc]
    op = ops.BY_CODE.get(code)
    if op is None or not op.emitted:
        what = _("reserved for the header") if op else _("not a ZUML command")
        raise DecodeError(pc, _("byte 0x{code:02x} ({code}) is {what}").format(code=code, what=what))
    raws: list[int] = []
    at = pc + 1
    for operand in op.operands:
        kind = operand.kind
        if at + kind.size > end:
            raise DecodeError(at, ngettext("{keyword} needs {size} byte for {name}; the program ends first",
                                           "{keyword} needs {size} bytes for {name}; the program ends first",
                                           kind.size).format(
                    keyword=op.keyword, size=kind.size, name=operand.name))
        raw = int.from_bytes(data[at:at + kind.size], "little", signed=kind.signed)
        if not kind.raw_valid(raw, operand.lo, operand.hi):
            raise DecodeError(at, _("{keyword}: {name} = {raw} is out of range").format(
                    keyword=op.keyword, name=operand.name, raw=raw))
        raws.append(raw)
        at += kind.size
    return Instruction(pc, op, tuple(raws), at - pc)


def flatten(macro: Macro) -> list[tuple[Op, tuple[int, ...], object]]:
    """The macro as the instruction stream the charger reads, each with its AST node."""
    out: list[tuple[Op, tuple[int, ...], object]] = []

    def items(nodes) -> None:
        for node in nodes:
            if isinstance(node, Phase):
                out.append((ops.FAZE, (), node))
                out.extend((s.op, s.raws(), s) for s in node.statements)
                out.append((ops.END_FAZE, (), node))
            elif isinstance(node, Cycle):
                out.append((ops.CYCLE, (node.count.raw,), node))
                items(node.items)
                out.append((ops.END_CYCLE, (), node))
            else:
                out.append((node.op, node.raws(), node))

    out.extend((s.op, s.raws(), s) for s in macro.intro)
    out.append((ops.DISCHARGE_SECTION, (), macro.discharge))
    items(macro.discharge.items)
    out.append((ops.END_SECTION, (), macro.discharge))
    out.extend((s.op, s.raws(), s) for s in macro.between)
    out.append((ops.CHARGE_SECTION, (), macro.charge))
    items(macro.charge.items)
    out.append((ops.END_SECTION, (), macro.charge))
    out.extend((s.op, s.raws(), s) for s in macro.conclusion)
    out.append((ops.END_MACRO, (), macro))
    return out


@dataclass(frozen=True)
class Encoded:
    record: bytes
    instructions: tuple[Instruction, ...]
    nodes: tuple[object, ...]          # AST node of each instruction, same order


def encode(macro: Macro) -> Encoded:
    """AST -> record. The macro must have passed the checker (valid name and values)."""
    name = macro.name.encode("ascii")
    body = bytearray()
    start = HEADER_SIZE + len(name) + 1
    instructions: list[Instruction] = []
    nodes: list[object] = []
    charge_at = conclusion_at = 0
    charge_section_seen = 0
    for op, raws, node in flatten(macro):
        offset = start + len(body)
        chunk = encode_instruction(op, raws)
        body += chunk
        instructions.append(Instruction(offset, op, raws, len(chunk)))
        nodes.append(node)
        if op is ops.CHARGE_SECTION:
            charge_at, charge_section_seen = start + len(body), 1
        elif op is ops.END_SECTION and charge_section_seen:
            conclusion_at = start + len(body)
    length = start + len(body) + 1
    if length > MAX_RECORD:
        # Point at the first instruction that no longer fits before the check byte.
        culprit = next(n for i, n in zip(instructions, nodes) if i.offset + i.size > MAX_RECORD - 1)
        raise RecordTooLarge(length, culprit)
    record = bytearray([length, start, charge_at, conclusion_at]) + name + b"\0" + body
    record.append(check_byte(record))
    return Encoded(bytes(record), tuple(instructions), tuple(nodes))


def encoded_size(macro: Macro) -> int:
    return HEADER_SIZE + len(macro.name) + 1 + sum(op.size for op, _, _ in flatten(macro)) + 1
