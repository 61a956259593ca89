"""zuml fit and zuml compare: the battery model against a real log."""
from __future__ import annotations

import argparse

from ..file_errors import FileReadError
from ..logs import LogFormatError
from ..lang.record import DecodeError
from ..sim.batteries import BatteryFileError, save_battery
from ..domain.chemistry import load_chemistry
from ..logs import Log
from ..sim.curve import DIRECTIONS, Curve, CurveError, log_directions, read_curve_and_log
from ..sim.fit import guess_series
from ..sim.fit_cells import fit_cells
from ..sim.fit_cells_report import cell_lines
from ..sim.fit_discharge import fit_curve
from ..sim.fit_checks import withheld
from ..sim.fit_predict import predict_own, prediction_line, trust_words
from ..sim.fit_report import figure_lines, param_lines, resistance_words
from ..sim.interpreter import StartError
from ..sim.simulate import BatterySetup, model_chemistry
from .common import CliError, check_start_options, out, out_json
from .sim_commands import _record
from ..i18n import _


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("fit", help=_("fit a chemistry's battery model to a real charge or discharge log"))
    p.add_argument("log", metavar="LOG", help=_("a charger log (any format `zuml log info` reads) or a curve CSV"))
    p.add_argument("--direction", choices=DIRECTIONS, help=_("fit the log's charge or its discharge (default: "
                                                             "its charge where it holds one, else its discharge)"))
    p.add_argument("--chemistry", metavar="C", help=_("Pb, NiCd, NiMh, LiPo, LiIon or LiFe (default: the battery "
                                                      "type the log names, where it names one)"))
    p.add_argument("--cells", type=int, metavar="N",
                   help=_("cells in series (default: the log's balance taps, else from its highest voltage)"))
    p.add_argument("--save", metavar="NAME", help=_("save the fitted battery under this name"))
    p.add_argument("--json", action="store_true", help=_("print one JSON object"))
    p.set_defaults(run=cmd_fit)
    c = sub.add_parser("compare", help=_("simulate a macro from a real log's start and compare the two"))
    c.add_argument("log", metavar="LOG")
    c.add_argument("macro", metavar="MACRO", help=_("a .zuml macro or a compiled .bin record"))
    c.add_argument("--direction", choices=DIRECTIONS, help=_("compare the macro's charge with the log's charge, or "
                                                             "its discharge with the log's discharge (default: as "
                                                             "for fit)"))
    c.add_argument("--chemistry", metavar="C", help=_("battery model (default: the macro's AKK_TYPE)"))
    c.add_argument("--battery", metavar="NAME", help=_("a saved fitted battery instead of the default model"))
    c.add_argument("--cells", type=int, metavar="N")
    c.add_argument("--capacity", type=float, metavar="MAH",
                   help=_("default: the saved battery's, else what the log's charge implies (the charge it put in, "
                           "over the part of the capacity it filled)"))
    c.add_argument("--json", action="store_true")
    c.set_defaults(run=cmd_compare)


def _curve(path: str, direction: str | None = None) -> tuple[Curve, Log | None]:
    try:
        return read_curve_and_log(path, direction)
    except (FileReadError, LogFormatError, CurveError) as exc:
        raise CliError(str(exc)) from None


def _other_direction(log: Log | None, curve: Curve) -> str | None:
    """The direction the log also holds, besides the one read (a cycle log holds both; a curve CSV one)."""
    held = log_directions(log) if log is not None else []
    return next((d for d in held if d != curve.direction), None)


def _chemistry(name: str) -> str:
    try:
        return load_chemistry(name).name
    except KeyError as exc:
        raise CliError(str(exc.args[0])) from None


def _cells(args: argparse.Namespace, curve: Curve, chemistry: str) -> int:
    if args.cells is not None and not 1 <= args.cells <= 255:
        raise CliError(_("--cells must be 1 to 255"))
    return args.cells or guess_series(curve, chemistry)


def _log_chemistry(args: argparse.Namespace, curve: Curve) -> str:
    if args.chemistry:
        return _chemistry(args.chemistry)
    try:
        return load_chemistry(curve.chemistry).name
    except KeyError:
        named = _(" (it names '{chemistry}')").format(chemistry=curve.chemistry) if curve.chemistry else ""
        raise CliError(_("{log}: the log does not name a modelled chemistry{named}: give --chemistry").format(
                log=args.log, named=named)) from None


def cmd_fit(args: argparse.Namespace) -> int:
    curve, log = _curve(args.log, args.direction)
    chemistry = _log_chemistry(args, curve)
    series = _cells(args, curve, chemistry)
    try:
        result = fit_curve(curve, chemistry, series)
        cells = fit_cells(result)
    except CurveError as exc:           # too short a charge once cut into the fit's steps
        raise CliError(str(exc)) from None
    saved = None
    if args.save:
        try:
            saved = save_battery(args.save, result.battery, args.log, cells=cells.saved() if cells else None)
        except (BatteryFileError, OSError) as exc:
            raise CliError(str(exc)) from None
    prediction = predict_own(result)
    if args.json:
        hidden = withheld(result.figures)       # not results: null, with the reason in "coverage" / "heat"
        out_json({"params": {k: None if k in hidden else v for k, v in result.params.items()},
                  "withheld": sorted(hidden), **result.figures, "own_program": prediction,
                  "cell_fit": cells.report() if cells else None})
        return 0
    header = (_("{log}: {chemistry} {series}S, {samples} samples, {minutes:.0f} min of charge")
              if curve.direction == "charge" else
              _("{log}: {chemistry} {series}S, {samples} samples, {minutes:.0f} min of discharge"))
    out(header.format(log=args.log, chemistry=chemistry, series=series, samples=len(curve.t),
                      minutes=curve.t[-1] / 60))
    _mention_other(args, log, curve)
    for line in param_lines(result.params, result.battery, result.figures):
        out(f"  {line}")
    for line in figure_lines(result.figures):
        out(line)
    if prediction is not None:
        out(prediction_line(prediction))
        if trust_words(prediction):
            out(trust_words(prediction))
    for line in cell_lines(cells.report()) if cells else ():
        out(line)
    if saved:
        out(_("saved as {save!r} ({saved})").format(save=args.save, saved=saved))
    return 0


def cmd_compare(args: argparse.Namespace) -> int:
    from ..sim.batteries import load_battery
    from ..sim.compare import compare
    from ..sim.measured_r import measure_curve

    check_start_options(args)
    curve, log = _curve(args.log, args.direction)
    record = _record(args.macro)
    try:
        named = load_battery(args.battery) if args.battery else None
    except BatteryFileError as exc:
        raise CliError(str(exc)) from None
    try:
        chemistry = named.chem.name if named else (_chemistry(args.chemistry) if args.chemistry else None)
        # The cell count is guessed with the model that will run: the macro's AKK_TYPE where none is given.
        series = args.cells or (named.series if named else None) or guess_series(
            curve, chemistry or model_chemistry(record, BatterySetup()))
        capacity = args.capacity or (named.capacity_mah if named else None)
        # The default model takes the pack's resistance from the log's rests, as it takes its start.
        measured = None if named else measure_curve(log, curve, series)
        result = compare(curve, record, chemistry, series, capacity, args.battery, measured_r=measured)
    except CurveError as exc:           # the log is no charge: nothing about the macro
        raise CliError(str(exc)) from None
    except (StartError, ValueError, DecodeError) as exc:
        raise CliError(f"{args.macro}: {exc}", 1) from None
    if args.json:
        out_json(result.report)
        return 0
    sim = result.sim
    out(_("{log}: {chemistry} {series}S, {capacity} mAh, {current} A from the log, {model}").format(
            log=args.log, chemistry=sim.chemistry, series=sim.series, capacity=f"{sim.capacity_mah:.0f}",
            current=f"{sim.interpreter.params.current_a:g}",       # the log's CC current, as INPUT
            model=_("battery {name!r}").format(name=args.battery) if args.battery else
            ", ".join(filter(None, (_("default model"), resistance_words(result.report))))))
    _mention_other(args, log, curve)
    for line in figure_lines(result.report):
        out(line)
    return 0


def _mention_other(args: argparse.Namespace, log: Log | None, curve: Curve) -> None:
    """On a cycle log read without --direction: the other direction is there, each on its own."""
    other = None if args.direction else _other_direction(log, curve)
    if other == "discharge":
        out(_("the log also holds a discharge: --direction discharge takes it"))
    elif other == "charge":
        out(_("the log also holds a charge: --direction charge takes it"))
