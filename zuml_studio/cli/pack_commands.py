"""zuml pack add/list/show/remove/import/export: the battery logbook (``zuml_studio.packs``)."""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

from ..packs.db import Logbook, LogbookError
from ..packs.register import PackError, add_pack, get_pack, list_packs, remove_pack
from ..packs.sessions import ImportResult, import_files
from ..packs.summary import DATED_MARK, capacity_note, capacity_text, dates_note, pack_summary, write_sessions_csv
from ..packs.text import printable
from .common import CliError, out, out_json
from ..i18n import _, ngettext

_BAR = 30


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("pack", help=_("the battery logbook: packs, their sessions, trends and health"))
    psub = p.add_subparsers(dest="pack_command", required=True, metavar="ACTION")
    add = psub.add_parser("add", help=_("add a pack to the register"))
    add.add_argument("name", metavar="NAME")
    add.add_argument("--chemistry", required=True, metavar="C", help=_("Pb, NiCd, NiMh, LiPo, LiIon or LiFe"))
    add.add_argument("--cells", required=True, type=int, metavar="N", help=_("cells in series"))
    add.add_argument("--capacity", required=True, type=float, metavar="MAH", help=_("rated capacity in mAh"))
    add.add_argument("--bought", metavar="YYYY-MM-DD", help=_("the date bought"))
    add.add_argument("--notes", default="", metavar="TEXT")
    add.add_argument("--serial", metavar="SERIAL", help=_("the battery passport's serial, if it has one"))
    add.set_defaults(run=cmd_add)
    lst = psub.add_parser("list", help=_("the packs, with their session count and health"))
    lst.add_argument("--json", action="store_true", help=_("print one JSON object"))
    lst.set_defaults(run=cmd_list)
    show = psub.add_parser("show", help=_("a pack: its sessions, trend and health verdict"))
    show.add_argument("name", metavar="NAME")
    show.add_argument("--json", action="store_true", help=_("print one JSON object"))
    show.set_defaults(run=cmd_show)
    rm = psub.add_parser("remove", help=_("remove a pack and its sessions from the register"))
    rm.add_argument("name", metavar="NAME")
    rm.set_defaults(run=cmd_remove)
    imp = psub.add_parser("import", help=_("import log files (folders: every file in them) as sessions of a pack"))
    imp.add_argument("paths", nargs="+", metavar="PATH")
    imp.add_argument("--pack", required=True, metavar="NAME")
    imp.add_argument("--force", action="store_true",
                     help=_("file logs whose chemistry or cells contradict the pack's too (marked, kept out of "
                            "the trend and health)"))
    imp.set_defaults(run=cmd_import)
    exp = psub.add_parser("export", help=_("a pack's sessions as CSV, one row per session"))
    exp.add_argument("name", metavar="NAME")
    exp.add_argument("-o", "--output", required=True, metavar="OUT.csv")
    exp.set_defaults(run=cmd_export)


def _book() -> Logbook:
    try:
        return Logbook()
    except LogbookError as exc:
        raise CliError(str(exc), 1) from None


def _pack(book: Logbook, name: str):
    try:
        return get_pack(book, name)
    except PackError as exc:
        raise CliError(str(exc), 1) from None


def cmd_add(args: argparse.Namespace) -> int:
    book = _book()
    try:
        pack = add_pack(book, args.name, args.chemistry, args.cells, args.capacity, bought=args.bought,
                        notes=args.notes, serial=args.serial)
    except (PackError, LogbookError) as exc:
        raise CliError(str(exc), 1) from None
    out(_("added pack {name!r}: {chemistry}, {cells} cells, {capacity:g} mAh").format(
            name=pack.name, chemistry=pack.chemistry, cells=pack.cells, capacity=pack.capacity_mah))
    return 0


def cmd_list(args: argparse.Namespace) -> int:
    book = _book()
    packs = [pack_summary(book, p) for p in list_packs(book)]
    if args.json:
        out_json({"packs": [{k: v for k, v in p.items() if k not in ("sessions", "trend")}
                            | {"sessions": len(p["sessions"])} for p in packs]}, ensure_ascii=False)
        return 0
    if not packs:
        out(_("no packs yet: `zuml pack add NAME --chemistry C --cells N --capacity MAH`"))
    for p in packs:
        out(_("{name}: {chemistry} {cells}S {capacity:g} mAh, {sessions}, {verdict}").format(
                name=printable(p["name"]), chemistry=p["chemistry"], cells=p["cells"], capacity=p["capacity_mah"],
                sessions=ngettext("{n} session", "{n} sessions", len(p["sessions"])).format(n=len(p["sessions"])),
                verdict=p["health"]["verdict"]))
    return 0


def cmd_show(args: argparse.Namespace) -> int:
    book = _book()
    info = pack_summary(book, _pack(book, args.name))
    if args.json:
        out_json(info, ensure_ascii=False)
        return 0
    _num = lambda v, fmt: "–" if v is None else format(v, fmt)
    out(_("{name}: {chemistry}, {cells} cells, {capacity:g} mAh rated").format(
            name=printable(info["name"]), chemistry=info["chemistry"], cells=info["cells"], capacity=info["capacity_mah"]))
    for key, label in (("bought", _("bought")), ("serial", _("serial")), ("notes", _("notes"))):
        if info[key]:
            out(f"  {label}: {printable(str(info[key]))}")
    out(_("  health: {verdict}").format(verdict=info["health"]["verdict"]))
    for reason in info["health"]["reasons"]:
        out(f"    {printable(reason)}")
    out(ngettext("  {n} session", "  {n} sessions", len(info["sessions"])).format(n=len(info["sessions"])))
    if info["sessions"]:
        out("    " + _("date        in mAh  out mAh  capacity  mΩ/cell  ΔV mV  T max  file"))
    for s in info["sessions"]:
        mark = DATED_MARK.get(s["recorded_from"], "?")
        out(f"    {s['recorded'][:10] + mark:<11}{_num(s['charge_in_mah'], '7.0f'):>7} {_num(s['charge_out_mah'], '8.0f'):>8}"
            f" {capacity_text(s):>9} {_num(s['resistance_mohm_per_cell'], '8.1f'):>8}"
            f" {_num(s['cell_deviation_mv'], '6.0f'):>6} {_num(s['t_max_c'], '6.1f'):>6}  {printable(s['file'])}")
    for note in (capacity_note(info["sessions"]), dates_note(info["sessions"])):
        if note:
            out("    " + printable(note))
    return 0


def cmd_remove(args: argparse.Namespace) -> int:
    book = _book()
    try:
        n = remove_pack(book, args.name)
    except (PackError, LogbookError) as exc:
        raise CliError(str(exc), 1) from None
    out(ngettext("removed pack {name!r} and its {n} session", "removed pack {name!r} and its {n} sessions",
                 n).format(name=args.name, n=n))
    return 0


def cmd_import(args: argparse.Namespace) -> int:
    book = _book()
    pack = _pack(book, args.pack)
    missing = [p for p in args.paths if not Path(p).exists()]
    if missing:
        raise CliError(_("{path}: no such file or folder").format(path=missing[0]), 1)
    bar = sys.stderr.isatty()
    added: list[ImportResult] = []

    def progress(done: int, total: int, result: ImportResult) -> None:
        if result.status == "added":
            added.append(result)
        if bar:
            filled = _BAR * done // total
            sys.stderr.write(f"\r[{'#' * filled}{'.' * (_BAR - filled)}] {done}/{total}")
            if done == total:
                sys.stderr.write("\n")
            sys.stderr.flush()
        label = {"added": _("added"), "known": _("known"), "error": _("skipped"),
                 "foreign": _("skipped")}[result.status]
        line = f"{label}: {printable(result.path)}" + (f": {printable(result.message)}" if result.message else "")
        if bar:
            sys.stderr.write("\r" + " " * (_BAR + 24) + "\r")
        out(line)

    try:
        results = import_files(book, pack, args.paths, progress, force=args.force)
    except LogbookError as exc:
        raise CliError(ngettext("{error} (the import stopped there; the {n} file added before it is kept)",
                                "{error} (the import stopped there; the {n} files added before it are kept)",
                                len(added)).format(error=exc, n=len(added)), 1) from None
    counts = {s: sum(r.status == s for r in results) for s in ("added", "known", "error", "foreign")}
    out(_("pack {name!r}: {added} added, {known} already known, {error} not read").format(name=pack.name, **counts))
    if counts["foreign"]:
        out(ngettext("{n} log skipped as another pack's (its reason above; --force files it)",
                     "{n} logs skipped as another pack's (their reasons above; --force files them)",
                     counts["foreign"]).format(n=counts["foreign"]))
    if counts["error"] and not counts["added"] and not counts["known"] and not counts["foreign"]:
        raise CliError(_("nothing imported: no file given is a log ZUML Studio reads (each one's reason above)"), 1)
    return 0


def cmd_export(args: argparse.Namespace) -> int:
    book = _book()
    pack = _pack(book, args.name)
    try:
        rows = write_sessions_csv(book, pack, args.output)
    except OSError as exc:
        raise CliError(_("{output}: cannot write: {error}").format(
                output=args.output, error=exc.strerror or exc)) from None
    out(_("wrote {rows} rows to {output}").format(rows=rows, output=args.output))
    return 0
