"""zuml simulate."""
from __future__ import annotations

import argparse
import math
import sys

from ..recovery import atomic_text_file
from ..sim.batteries import BatteryFileError
from ..sim.battery import AMBIENT_MAX_C, AMBIENT_MIN_C
from ..sim.interpreter import Measurement, StartError, StartParams
from ..sim.reasons import end_advice, shown_reason
from ..sim.engine import missing_text as engine_missing_text
from ..sim.simulate import ENGINES, SPREAD_MAX_PCT, BatterySetup, EngineError, SimResult, parse_spread, simulate
from ..sim.start_check import start_warnings
from ..domain.start_templates import TEMPLATE_COUNT
from .common import CliError, check_start_options, out, out_json, read_bytes
from .lang_commands import compile_file
from ..i18n import _, ngettext


MAX_MEASUREMENT_MV = 1000.0        # noise sigma or ADC step: a volt is already no measurement
MIN_ADC_LSB_MV = 0.001             # the simulator measures to 1 µV; 4e-320 overflowed V / step


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("simulate", help=_("run a macro's byte code against a battery model"))
    p.add_argument("file", metavar="FILE", help=_("a .zuml macro or a compiled .bin record"))
    p.add_argument("--task", choices=("charge", "discharge", "train"), default="charge")
    p.add_argument("--cycles", type=int, default=1, metavar="N", help=_("training: discharge+charge N times"))
    p.add_argument("--capacity", type=float, metavar="MAH", help=_("capacity entered at start"))
    p.add_argument("--current", type=float, metavar="A", help=_("current entered at start (INPUT)"))
    p.add_argument("--voltage", type=float, metavar="V", help=_("voltage entered at start (INPUT)"))
    p.add_argument("--series", type=int, metavar="N", help=_("cells in series entered at start"))
    p.add_argument("--template", type=int, metavar="N", help=_("start with the charger's start template N (the factory "
                                                               "table; a macro's START_SHABLON wins)"))
    p.add_argument("--soc", type=float, metavar="0..1",
                   help=_("initial state of charge (default: empty for charge, full for discharge and training)"))
    p.add_argument("--ambient", type=float, default=25.0, metavar="C")
    p.add_argument("--no-sensor", action="store_true", help=_("no battery temperature sensor connected"))
    p.add_argument("--model", metavar="CHEMISTRY", help=_("battery model (default: the macro's AKK_TYPE)"))
    p.add_argument("--battery", metavar="NAME", help=_("a saved fitted battery (zuml fit --save): its model, "
                                                       "capacity and cells unless given"))
    p.add_argument("--tick", type=float, default=1.0, metavar="S", help=_("interpreter tick (default 1 s)"))
    p.add_argument("--noise", type=float, default=0.0, metavar="MV", help=_("voltage measurement noise, sigma"))
    p.add_argument("--adc-lsb", type=float, default=0.0, metavar="MV", help=_("voltage ADC step"))
    p.add_argument("--seed", type=int, default=1, metavar="N",
                   help=_("seed of the measurement noise and of the cell spread (default 1)"))
    p.add_argument("--charger", default="imax_b6", metavar="MODEL",
                   help=_("the charger model: its limits, heat sink and balancer (default imax_b6)"))
    p.add_argument("--cell-spread", metavar="CAP,R,SOC",
                   help=_("cells unequal: each cell's capacity and resistance drawn within ± CAP and R %% of the "
                          "pack's, its start state within ± SOC points"))
    p.add_argument("--weak-cell", metavar="PCT[@K]", help=_("cell K (default: the last) with PCT %% less capacity"))
    p.add_argument("--engine", choices=ENGINES, default="auto",
                   help=_("auto: the C engine when it can run the simulation, else the Python interpreter (the "
                          "reference); c: the C engine or an error saying why not; python: the reference"))
    p.add_argument("--csv", metavar="OUT.csv", help=_("write every sample"))
    p.add_argument("--json", action="store_true", help=_("print one JSON object instead of the table"))
    p.set_defaults(run=cmd_simulate)


def _record(path: str) -> bytes:
    return read_bytes(path) if path.lower().endswith(".bin") else compile_file(path)


def _check(args: argparse.Namespace) -> None:
    if args.soc is not None and not 0.0 <= args.soc <= 1.0:
        raise CliError(_("--soc is a fraction from 0 to 1"))
    check_start_options(args)
    if not 0.05 <= args.tick <= 60:
        raise CliError(_("--tick must be 0.05 to 60 seconds"))
    if not AMBIENT_MIN_C <= args.ambient <= AMBIENT_MAX_C:
        raise CliError(_("--ambient must be {low:g} to {high:g} °C").format(low=AMBIENT_MIN_C, high=AMBIENT_MAX_C))
    for name in ("noise", "adc_lsb"):
        if not 0.0 <= getattr(args, name) <= MAX_MEASUREMENT_MV:
            raise CliError(_("--{name} must be 0 to {top:g} mV").format(name=name.replace("_", "-"),
                                                                        top=MAX_MEASUREMENT_MV))
    if 0.0 < args.adc_lsb < MIN_ADC_LSB_MV:
        raise CliError(_("--adc-lsb must be 0 (none) or at least {low:g} mV").format(low=MIN_ADC_LSB_MV))
    if args.template is not None and not 1 <= args.template <= TEMPLATE_COUNT:
        raise CliError(_("--template must be 1 to {template_count}").format(template_count=TEMPLATE_COUNT))


def _spread(text: str | None) -> tuple[float, float, float] | None:
    """--cell-spread CAP,R,SOC: three percentages, each 0..50."""
    if text is None:
        return None
    try:
        return parse_spread(text)
    except ValueError:
        raise CliError(_("--cell-spread takes CAP,R,SOC: three percentages from 0 to {top:g}, e.g. 3,10,2").format(
            top=max(SPREAD_MAX_PCT))) from None


def weak_cell(text: str | None) -> dict:
    """--weak-cell PCT[@K]: BatterySetup's weak_cell_pct and weak_cell."""
    if text is None:
        return {}
    pct, _at, cell = text.partition("@")
    try:
        value, k = float(pct), int(cell) if cell else None
    except ValueError:
        value, k = math.nan, None
    if not 0.0 < value < 100.0 or (k is not None and k < 1):
        raise CliError(_("--weak-cell takes PCT or PCT@K: more than 0 and less than 100 percent less capacity, "
                         "K the cell from 1 (default: the last)"))
    return {"weak_cell_pct": value, "weak_cell": k}


def cmd_simulate(args: argparse.Namespace) -> int:
    _check(args)
    record = _record(args.file)
    params = StartParams(args.task, args.cycles, args.capacity, args.current, args.voltage, args.series,
                         not args.no_sensor, args.template)
    setup = BatterySetup(args.model, args.soc, args.ambient, charger=args.charger, battery=args.battery,
                         cell_spread=_spread(args.cell_spread), seed=args.seed, **weak_cell(args.weak_cell))
    measurement = Measurement(args.noise / 1000.0, args.adc_lsb / 1000.0, args.seed)
    try:
        result = simulate(record, params, setup, tick_s=args.tick, measurement=measurement, engine=args.engine)
    except EngineError as exc:
        raise CliError(_("--engine c: {why}").format(why=exc), 1) from None
    except StartError as exc:
        raise CliError(f"{args.file}: {exc}", 1) from None
    except KeyError as exc:
        raise CliError(str(exc.args[0]), 1) from None
    except BatteryFileError as exc:
        raise CliError(str(exc)) from None
    if args.csv:
        try:
            with atomic_text_file(args.csv) as fh:
                result.log.write_csv(fh)
        except OSError as exc:
            raise CliError(_("{csv}: cannot write: {error}").format(csv=args.csv, error=exc.strerror or exc)) from None
    if result.engine_note == engine_missing_text():
        sys.stderr.write(_("zuml: note: {why}; the Python interpreter ran\n").format(why=result.engine_note))
    warnings = start_warnings(record, params, result.interpreter.charger.limits)
    if args.json:
        out_json({**result.to_json(), "warnings": warnings})
    else:
        for text in warnings:
            out(_("warning: {text}").format(text=text))
        _table(args, result)
    return 0


def hms(seconds: float) -> str:
    s = int(round(seconds))
    return f"{s // 3600}:{s % 3600 // 60:02d}:{s % 60:02d}"


def _table(args: argparse.Namespace, result: SimResult) -> None:
    p = result.interpreter.params
    out(ngettext("{name}: {task}{repetitions}, {chemistry} model {capacity_mah:g} mAh x {series} cell, "
                 "{ambient:g} °C, sensor {sensor}",
                 "{name}: {task}{repetitions}, {chemistry} model {capacity_mah:g} mAh x {series} cells, "
                 "{ambient:g} °C, sensor {sensor}", result.series).format(
            name=result.interpreter.program.name, task=p.task,
            repetitions=f' x{p.repetitions}' if p.task == 'train' else '', chemistry=result.chemistry,
            capacity_mah=result.capacity_mah, series=result.series, ambient=args.ambient,
            sensor=_("on") if p.sensor else _("off")))
    # Column titles are translated; each column is as wide as the longest of its title and values.
    titles = ["#", _("section"), _("phase"), _("start"), _("end"), _("reason"), _("in mAh"), _("out mAh"),
              _("V end"), _("T end")]
    rows = [[str(ph.run), ph.section, str(ph.index) if ph.index else "dflt", hms(ph.start_s), hms(ph.end_s),
             shown_reason(ph.reason), f"{ph.mah_in:.1f}", f"{ph.mah_out:.1f}", f"{ph.v_end:.3f}", f"{ph.temp_end:.1f}",
             ("⚠ " if ph.timer_before_full else "") + "; ".join(ph.notes)] for ph in result.phases]
    least = [3, 9, 5, 8, 8, 0, 8, 8, 7, 6]
    width = [max([len(title), least[i]] + [len(row[i]) for row in rows]) for i, title in enumerate(titles)]
    left = {1, 5}                                  # section and reason read from the left, the rest are numbers

    def line(cells: list[str]) -> str:
        parts = [f"{c:<{width[i]}}" if i in left else f"{c:>{width[i]}}" for i, c in enumerate(cells[:10])]
        return (f"{parts[0]}  {parts[1]} {parts[2]}  " + "  ".join(parts[3:]) + f"  {cells[10]}").rstrip()
    out(line(titles + [_("notes")]))
    for row in rows:
        out(line(row))
    t = result.totals()
    out(_("total {duration}, in {charge_in:.1f} mAh, out {charge_out:.1f} mAh; end: {end}").format(
            duration=hms(t['duration_s']), charge_in=t['mah_in'], charge_out=t['mah_out'], end=shown_reason(t['end'])))
    if p.task == "train":
        for rep in result.repetitions():
            out(_("repetition {repetition}: discharged {discharged:.1f} mAh (measured capacity), charged "
                  "{charged:.1f} mAh").format(
                    repetition=rep['repetition'], discharged=rep['discharged_mah'], charged=rep['charged_mah']))
    for ph in result.phases:
        if ph.cells_end and result.interpreter.pack.per_cell:
            low, high = min(ph.cells_end), max(ph.cells_end)
            out(_("phase {run} ({section}): cells at the end {low:.3f} V (cell {low_cell}) to {high:.3f} V "
                  "(cell {high_cell})").format(run=ph.run, section=ph.section, low=low,
                                               low_cell=ph.cells_end.index(low) + 1, high=high,
                                               high_cell=ph.cells_end.index(high) + 1))
    for ph in result.phases:
        if ph.full_by_dtdt:
            out(_("note: phase {run} ({section}) ended by {reason}: {advice}").format(
                    run=ph.run, section=ph.section, reason=shown_reason(ph.reason), advice=end_advice(ph)))
        elif ph.by_default:
            out(_("⚠ phase {run} ({section}) ended by {reason}, not by a condition of the macro: {advice}").format(
                    run=ph.run, section=ph.section, reason=shown_reason(ph.reason), advice=end_advice(ph)))
        if ph.timer_before_full:
            out(_("⚠ phase {run} ({section}): timer before full: {reason} ended it with {mah_in:.0f} mAh put in, "
                  "the pack at {soc:.0f} %: {advice}").format(
                    run=ph.run, section=ph.section, reason=shown_reason(ph.reason), mah_in=ph.mah_in,
                    soc=ph.soc_end * 100, advice=end_advice(ph)))
