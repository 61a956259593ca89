"""docs/commands.md, generated from the opcode table (``python -m zuml_studio.lang.docgen``).
A test keeps the committed file equal to this output, so docs and compiler cannot drift."""
from __future__ import annotations

import sys

from .opcodes import OPCODES, Place


def operands_text(op) -> str:
    """The operands of a command in words: name, quantity, width, default."""
    if not op.operands:
        return "—"
    parts = []
    for o in op.operands:
        kind = o.kind
        width = f"{'i' if kind.signed else 'u'}{kind.size * 8}"
        optional = f", optional (default {kind.format(o.default)})" if o.default is not None else ""
        parts.append(f"`{o.name}`: {kind.what}, {width}{optional}")
    return "; ".join(parts)


def places_text(op) -> str:
    """Where a command may stand."""
    if not op.places:
        return "structure"
    return ", ".join(p.name.lower() for p in Place if p in op.places)


def commands_markdown() -> str:
    lines = [
        "# ZUML 2.0 commands",
        "",
        "Generated from `zuml_studio/lang/opcodes.py` by `python -m zuml_studio.lang.docgen`; do not edit by hand.",
        "Operands are stored little-endian right after the code byte. Where: intro = the introduction,",
        "phase = inside FAZE … END_FAZE, between = in a section outside phases, sections = between the",
        "discharge and the charge section (seed 000, byte layout item 8), conclusion = after the sections.",
        "",
        "| code | written | mnemonic | operands | where | what it does |",
        "|---:|---|---|---|---|---|",
    ]
    for op in OPCODES:
        written = op.signature().replace("|", "\\|")
        lines.append(f"| {op.code} | `{written}` | {op.mnemonic} | {operands_text(op)} | {places_text(op)} "
                     f"| {op.help_text} |")
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    sys.stdout.write(commands_markdown())
