"""AST -> canonical text: upper-case keywords, two-space indents, one statement a line."""
from __future__ import annotations

from .ast import Cycle, Macro, Phase, Section, Statement
from .opcodes import Op, canonical_text

INDENT = "  "


def format_args(op: Op, raws: tuple[int, ...]) -> list[str]:
    """Operand texts; an optional trailing operand at its default is left out."""
    texts = [o.kind.format(r) for o, r in zip(op.operands, raws)]
    if op.operands and op.operands[-1].default is not None and raws[-1] == op.operands[-1].default:
        texts.pop()
    return texts


def format_statement(st: Statement) -> str:
    return canonical_text(st.op, format_args(st.op, st.raws()))


def format_macro(macro: Macro) -> str:
    lines = [f"MACRO {macro.name}"]
    lines += [INDENT + format_statement(s) for s in macro.intro]
    shown = [s for s in macro.sections() if s.present or s.items]
    if macro.between:
        shown = list(macro.sections())   # commands between the sections need both (empty ones store the same bytes)
    elif macro.conclusion and not shown:
        shown = [macro.charge]   # a conclusion must follow a section; an empty one stores the same bytes
    for section in shown:
        _section(section, lines)
        if section.kind == "discharge":
            lines += [INDENT + format_statement(s) for s in macro.between]
    lines += [INDENT + format_statement(s) for s in macro.conclusion]
    lines.append("END_MACRO")
    return "\n".join(lines) + "\n"


def _section(section: Section, lines: list[str]) -> None:
    lines.append(INDENT + ("DISCHARGE_SECTION" if section.kind == "discharge" else "CHARGE_SECTION"))
    _items(section.items, 2, lines)
    lines.append(INDENT + "END_SECTION")


def _items(items: list, depth: int, lines: list[str]) -> None:
    pad = INDENT * depth
    for item in items:
        if isinstance(item, Phase):
            lines.append(pad + "FAZE")
            lines += [pad + INDENT + format_statement(s) for s in item.statements]
            lines.append(pad + "END_FAZE")
        elif isinstance(item, Cycle):
            lines.append(f"{pad}CYCLE({item.count.raw})")
            _items(item.items, depth + 1, lines)
            lines.append(pad + "END_CYCLE")
        else:
            lines.append(pad + format_statement(item))
