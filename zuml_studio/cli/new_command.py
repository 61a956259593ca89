"""zuml new: a macro from a few answers (the wizard's logic, zuml_studio/wizard.py)."""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

from ..lang.compiler import compile_source
from ..recovery import atomic_write
from ..domain.chemistry import chemistry_names
from ..wizard import Answers, WizardError, new_macro
from .common import CliError, out
from ..i18n import _


def _rate(text: str) -> float:
    value = text[:-1] if text.upper().endswith("C") else text
    try:
        return float(value)
    except ValueError:
        raise argparse.ArgumentTypeError(_("{text!r} is not a charge rate such as 1C or 0.5C").format(
                text=text)) from None


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("new", help=_("write a new macro for a chemistry, pack and charge rate"))
    p.add_argument("--chemistry", required=True, choices=chemistry_names(), type=_chemistry, metavar="NAME",
                   help=_("one of {chemistry_names}").format(chemistry_names=', '.join(chemistry_names())))
    p.add_argument("--series", type=int, required=True, metavar="N", help=_("cells in series"))
    p.add_argument("--capacity", type=int, required=True, metavar="MAH")
    p.add_argument("--rate", type=_rate, metavar="XC", help=_("charge rate, e.g. 1C (default per chemistry)"))
    p.add_argument("--sensor", action="store_true", help=_("a battery temperature sensor is fitted"))
    p.add_argument("-o", "--output", metavar="FILE", help=_("write here instead of printing"))
    p.set_defaults(run=cmd_new)


def _chemistry(text: str) -> str:
    for name in chemistry_names():
        if name.lower() == text.lower():
            return name
    return text


def cmd_new(args: argparse.Namespace) -> int:
    try:
        text = new_macro(Answers(args.chemistry, args.series, args.capacity, args.rate, args.sensor))
    except WizardError as exc:
        raise CliError(str(exc)) from None
    result = compile_source(text)
    for d in result.diagnostics:       # the wizard's output is tested clean; say so if that ever breaks
        sys.stderr.write(d.render(args.output or "<new>") + "\n")
    if args.output:
        try:
            atomic_write(Path(args.output), text.encode("utf-8"))
        except OSError as exc:
            raise CliError(_("{output}: cannot write: {error}").format(
                    output=args.output, error=exc.strerror or exc)) from None
        out(_("{output}: {name}, {n_record} bytes").format(
                output=args.output, name=result.macro.name, n_record=len(result.record)) if result.ok else args.output)
    else:
        sys.stdout.write(text)
    return 0 if result.ok else 1
