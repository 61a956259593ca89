"""zuml log info / zuml log export: a charger's log file, read by ``zuml_studio.logs``."""
from __future__ import annotations

import argparse
from pathlib import Path

from ..logs import FORMATS, Log, LogFormatError, csv_import, read_log
from ..logs.export import write_csv, write_record_sets
from ..logs.model import charge_check_text, out_of_range_text, time_order_text
from ..logs.summary import summarize
from ..recovery import atomic_text_file
from ..file_errors import FileReadError, read_file_bytes
from .common import CliError, out, out_json
from .sim_commands import hms
from ..i18n import _, ngettext


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("log", help=_("read a charger's log file: summary, CSV export"))
    logsub = p.add_subparsers(dest="log_command", required=True, metavar="ACTION")
    formats = [f.name for f in FORMATS]
    info = logsub.add_parser("info", help=_("what the log holds: charger, samples, ranges, charge, phases"))
    info.add_argument("file", metavar="FILE")
    info.add_argument("--json", action="store_true", help=_("print one JSON object"))
    info.add_argument("--format", choices=formats, help=_("read as this format (default: recognised from the bytes)"))
    info.add_argument("--columns", metavar="SPEC", help=_("a CSV's columns in order, role:unit or - (instead of the "
                                                          "guess): time:s,voltage:V,current:mA,charge:mAh"))
    info.set_defaults(run=cmd_info)
    export = logsub.add_parser("export", help=_("one CSV row per sample, SI units, charge current positive"))
    export.add_argument("file", metavar="FILE")
    export.add_argument("-o", "--output", required=True, metavar="OUT.csv")
    export.add_argument("--format", choices=formats, help=_("read as this format (default: recognised from the bytes)"))
    export.add_argument("--columns", metavar="SPEC", help=_("a CSV's columns in order, role:unit or - (instead of "
                                                            "the guess): time:s,voltage:V,current:mA,charge:mAh"))
    export.add_argument("--dataexplorer", action="store_true",
                        help=_("DataExplorer-style record sets: a '### RECORDSET' block per phase, each from time 0"))
    export.set_defaults(run=cmd_export)


def load(path: str, fmt: str | None, columns: str | None = None) -> Log:
    try:
        data = read_file_bytes(path, pipes=False)
    except FileReadError as exc:
        raise CliError(str(exc)) from None
    if columns is not None:
        return _load_csv(path, data, columns)
    try:
        return read_log(data, path, fmt)
    except LogFormatError as exc:
        if fmt:          # the user chose the format: the reason is about reading it as that one
            raise CliError(_("{path}: read as {format} (--format): {reason}; without --format the format is "
                             "recognised from the bytes").format(path=path, format=fmt, reason=exc), 1) from None
        raise CliError(f"{path}: {exc}", 1) from None


def _load_csv(path: str, data: bytes, columns: str) -> Log:
    """A CSV read with the columns the user gave (``--columns``) instead of the guessed ones."""
    try:
        return csv_import.read_as(data, columns)
    except LogFormatError as exc:
        raise CliError(_("{path}: --columns: {reason}").format(path=path, reason=exc), 1) from None


def cmd_info(args: argparse.Namespace) -> int:
    info = summarize(load(args.file, args.format, args.columns))
    if args.json:
        out_json(info, ensure_ascii=False)
        return 0
    _num = lambda v, fmt: "–" if v is None else format(v, fmt)
    out(f"{args.file}: {info['format']}, {info['device']}")
    if "csv_columns" in info:
        out(_("  columns      {spec} (--columns changes them)").format(spec=info["csv_columns"]))
    for line in info.get("csv_assumed", ()):
        out(_("  assumed      {what}").format(what=line))
    if info.get("record_sets"):
        sets = info["record_sets"]
        out(ngettext("  record sets  {n}: {names}", "  record sets  {n}: {names}", len(sets)).format(
                n=len(sets), names="; ".join(name or "–" for name in sets)))
    if info.get("started"):
        out(_("  recorded     {when} (the log's own time stamp)").format(when=info["started"]))
    out(_("  samples      {samples} ({bad} bad records), {duration}").format(
            samples=info['samples'], bad=info['bad_records'], duration=hms(info['duration_s'])))
    if "out_of_range" in info:
        out("  " + out_of_range_text(info["out_of_range"]))
    if "time_order" in info:
        out("  " + time_order_text(info["time_order"]))
    voltage = _("  voltage      {low} to {high} V").format(
            low=_num(info['v_min'], '.3f'), high=_num(info['v_max'], '.3f'))
    if info["cells"]:
        voltage += ngettext(", {n} cell", ", {n} cells", info["cells"]).format(n=info["cells"])
    out(voltage)
    out(_("  current      up to {current} A").format(current=_num(info['i_max_a'], '.3f')))
    out(_("  charge       in {charge_in} mAh, out {charge_out} mAh").format(
            charge_in=_num(info['charge_in_mah'], '.0f'), charge_out=_num(info['charge_out_mah'], '.0f')))
    if "charge_check" in info:
        out("  " + charge_check_text(info["charge_check"]))
    if info["t_max_c"] is not None:
        out(_("  temperature  {low:.1f} to {high:.1f} °C").format(low=info['t_min_c'], high=info['t_max_c']))
    else:
        out(_("  temperature  no temperature in this log"))
    out(_("  phases       {n}").format(n=len(info['phases'])))
    for p in info["phases"]:
        out(f"    {p['state']:<10} {hms(p['start_s'])} – {hms(p['end_s'])}")
    return 0


def cmd_export(args: argparse.Namespace) -> int:
    log = load(args.file, args.format, args.columns)
    try:
        with atomic_text_file(args.output) as fh:       # a failure leaves an older export whole
            rows = write_record_sets(log, fh, Path(args.file).name) if args.dataexplorer else write_csv(log, fh)
    except OSError as exc:
        raise CliError(_("{output}: cannot write: {error}").format(
                output=args.output, error=exc.strerror or exc)) from None
    out(_("wrote {rows} rows to {output}").format(rows=rows, output=args.output))
    return 0
