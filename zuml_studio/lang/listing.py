"""A byte-code listing in the style of CPython's ``dis``: one row per field or
instruction with its offset, raw bytes, mnemonic, decoded operands and source line.
The CLI prints it; the editor's hex view shows the same rows."""
from __future__ import annotations

from dataclasses import dataclass

from . import opcodes as ops
from .ast import Span
from .formatter import format_args
from .record import HEADER_SIZE, Instruction, check_byte
from ..i18n import _

_CLOSERS = {ops.END_FAZE, ops.END_CYCLE, ops.END_SECTION, ops.END_MACRO}


def source_span(op: ops.Op, node: object) -> Span | None:
    """Where an instruction comes from: a closing instruction maps to its closing line."""
    if op in _CLOSERS:
        return getattr(node, "end_span", None)
    return getattr(node, "span", None)


@dataclass(frozen=True)
class Row:
    offset: int
    data: bytes
    kind: str               # "header" | "name" | "instruction" | "check"
    mnemonic: str
    detail: str
    line: int | None = None  # source line, when the record came from text
    node: object = None

    @property
    def hex(self) -> str:
        return self.data.hex(" ")


def listing_rows(record: bytes, instructions: tuple[Instruction, ...], nodes: tuple[object, ...] = ()) -> list[Row]:
    name_end = record[1]
    rows = [
        Row(0, record[0:1], "header", "LENGTH", _("{n} bytes").format(n=record[0])),
        Row(1, record[1:2], "header", "PROGRAM", _("program starts at {offset}").format(offset=record[1])),
        Row(2, record[2:3], "header", "CHARGE", _("charge section starts at {offset}").format(offset=record[2])),
        Row(3, record[3:4], "header", "CONCLUSION", _("conclusion starts at {offset}").format(offset=record[3])),
        Row(HEADER_SIZE, record[HEADER_SIZE:name_end], "name", "NAME",
            repr(record[HEADER_SIZE:name_end - 1].decode("latin-1"))),
    ]
    for i, ins in enumerate(instructions):
        node = nodes[i] if i < len(nodes) else None
        span = source_span(ins.op, node)
        detail = ", ".join(format_args(ins.op, ins.raws))
        if ins.op.condition:
            detail = f"{ins.op.condition.variables[0]}{ins.op.condition.comparison}{detail}" \
                     f" -> {ins.op.condition.outcome}"
        rows.append(Row(ins.offset, record[ins.offset:ins.offset + ins.size], "instruction",
                        ins.op.mnemonic, detail, span.line if span else None, node))
    last = len(record) - 1
    ok = _("ok") if check_byte(record[:last]) == record[last] else _("BAD")
    rows.append(Row(last, record[last:], "check", "CHECK", _("XOR of bytes 0..{last}: {ok}").format(
            last=last - 1, ok=ok)))
    return rows


def format_listing(rows: list[Row]) -> str:
    width = max(len(r.hex) for r in rows if r.kind != "name") + 1
    out = [f"{'line':>4}  {'off':>3}  {'bytes':<{width}} {'instruction':<18} operands"]
    for r in rows:
        line = str(r.line) if r.line else ""
        shown = r.hex if len(r.hex) <= width else r.hex[:width - 4] + " ..."
        out.append(f"{line:>4}  {r.offset:>3}  {shown:<{width}} {r.mnemonic:<18} {r.detail}".rstrip())
    return "\n".join(out)
