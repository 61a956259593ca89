"""Text -> diagnostics and bytes: the one entry point the CLI, editor and tests use."""
from __future__ import annotations

from dataclasses import dataclass, field

from .ast import Macro, Span
from .builder import build
from .checker import Finding, check
from .diagnostics import Diagnostic, Severity, sort_key
from .parser import SyntaxProblem, parse_raw
from .record import MAX_RECORD, Encoded, encode
from ..i18n import _


@dataclass
class CompileResult:
    macro: Macro | None
    diagnostics: list[Diagnostic] = field(default_factory=list)
    encoded: Encoded | None = None

    @property
    def ok(self) -> bool:
        return self.encoded is not None

    @property
    def record(self) -> bytes:
        if self.encoded is None:
            raise ValueError(_("the macro has errors; there are no bytes"))
        return self.encoded.record

    @property
    def errors(self) -> list[Diagnostic]:
        return [d for d in self.diagnostics if d.is_error]

    @property
    def warnings(self) -> list[Diagnostic]:
        """The warnings only: notes are not counted as warnings anywhere."""
        return [d for d in self.diagnostics if d.is_warning]


def node_span(macro: Macro, node: object) -> Span:
    if node == "name":
        return macro.name_span or Span(1, 1, 1, 1)
    span = getattr(node, "span", None)
    return span or macro.span or Span(1, 1, 1, 1)


def to_diagnostic(macro: Macro, finding: Finding) -> Diagnostic:
    span = node_span(macro, finding.node)
    return Diagnostic(finding.severity, span.line, span.column, (span.end_line, span.end_column),
                      finding.code, finding.message, finding.hint)


def compile_source(text: str, *, charger=None, unsafe_ok: bool = False) -> CompileResult:
    """Never raises for any text: problems come back as diagnostics. ``charger``: the charger model's
    ``sim.charger_model.ChargerLimits`` when known (the lint then warns where it clips a current).

    ``unsafe_ok``: the safety lint's errors (E3xx) still show but no longer withhold the bytes
    (the user's explicit override, ``--force-unsafe``)."""
    try:
        raw = parse_raw(text)
    except SyntaxProblem as problem:
        return CompileResult(None, [problem.diagnostic])
    if len(raw.statements) >= MAX_RECORD:
        # The parser stops here (every statement takes a byte or more): refused before the build
        # and checks, which would take long on a file of thousands of lines.
        at = raw.statements[MAX_RECORD - 1].span
        return CompileResult(None, [Diagnostic(Severity.ERROR, at.line, at.column, (at.end_line, at.end_column),
                                               "E160", _("The macro has {max_record} statements or more; each takes a "
                                                         "byte or more and a record holds at most {max_record}").format(
                                                       max_record=MAX_RECORD),
                                               _("this is where it stops fitting: shorten the macro or split it"))])
    macro, diagnostics = build(raw)
    from .lint import lint   # the lint reads the checked AST; imported here to keep layers one-way
    findings = check(macro)
    # Safety warnings only make sense for a macro that could be stored.
    safety: list[Finding] = []
    if not any(d.is_error for d in diagnostics) and not any(f.severity is Severity.ERROR for f in findings):
        safety = lint(macro, charger)
    diagnostics += [to_diagnostic(macro, f) for f in findings]
    blocking = any(d.is_error for d in diagnostics) or \
        (not unsafe_ok and any(f.severity is Severity.ERROR for f in safety))
    diagnostics += [to_diagnostic(macro, f) for f in safety]
    diagnostics.sort(key=sort_key)
    encoded = None if blocking else encode(macro)
    return CompileResult(macro, diagnostics, encoded)
