"""The typed syntax tree of a macro. The same tree comes from text (with spans)
and from byte code (with byte offsets), so every later stage has one input."""
from __future__ import annotations

from dataclasses import dataclass, field

from .opcodes import Op


@dataclass(frozen=True)
class Span:
    """1-based, end exclusive, as lark reports tokens."""

    line: int
    column: int
    end_line: int
    end_column: int

    @staticmethod
    def cover(a: "Span", b: "Span") -> "Span":
        return Span(a.line, a.column, b.end_line, b.end_column)


@dataclass
class Arg:
    raw: int                       # the stored operand value: the truth, what the charger sees
    span: Span | None = None
    text: str | None = None        # as written, when it came from text


@dataclass
class Statement:
    op: Op
    args: list[Arg]
    span: Span | None = None
    offset: int | None = None      # byte offset of its opcode in the record

    def raws(self) -> tuple[int, ...]:
        return tuple(a.raw for a in self.args)


@dataclass
class Phase:
    statements: list[Statement]
    span: Span | None = None
    end_span: Span | None = None
    offset: int | None = None
    incomplete: bool = False       # a statement in it had an error and was left out


@dataclass
class Cycle:
    count: Arg
    items: list["Phase | Statement | Cycle"]
    span: Span | None = None
    end_span: Span | None = None
    offset: int | None = None


Item = "Phase | Cycle | Statement"


@dataclass
class Section:
    kind: str                      # "discharge" | "charge"
    items: list                    # Phase | Cycle | Statement
    span: Span | None = None
    end_span: Span | None = None
    present: bool = True           # False: absent from the text, emitted empty

    def phases(self) -> list[Phase]:
        out: list[Phase] = []
        for item in self.items:
            if isinstance(item, Phase):
                out.append(item)
            elif isinstance(item, Cycle):
                out.extend(i for i in item.items if isinstance(i, Phase))
        return out


@dataclass
class Macro:
    name: str
    intro: list[Statement] = field(default_factory=list)
    discharge: Section = field(default_factory=lambda: Section("discharge", [], present=False))
    charge: Section = field(default_factory=lambda: Section("charge", [], present=False))
    conclusion: list[Statement] = field(default_factory=list)
    name_span: Span | None = None
    span: Span | None = None
    end_span: Span | None = None
    between: list[Statement] = field(default_factory=list)     # commands between the two sections

    def sections(self) -> tuple[Section, Section]:
        return (self.discharge, self.charge)

    def declared(self, op: Op) -> Statement | None:
        return next((s for s in self.intro if s.op is op), None)
