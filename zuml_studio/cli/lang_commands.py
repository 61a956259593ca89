"""zuml check / compile / decompile / image."""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

from ..lang.compiler import CompileResult, compile_source
from ..lang.decoder import decode_record
from ..lang.eeprom import DEFAULT_SIZE, ImageError, extract, pack, slots
from ..lang.formatter import format_macro
from ..lang.listing import format_listing, listing_rows
from ..lang.opcodes import AKK_TYPE
from ..lang.record import DecodeError
from .common import (CliError, add_force_unsafe, is_macro_text, out, read_bytes, read_text, refuse_unsafe,
                     write_bytes)
from ..i18n import _, ngettext


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("check", help=_("check macros and print their errors and warnings"))
    p.add_argument("files", nargs="+", metavar="FILE")
    p.add_argument("--no-hints", action="store_true", help=_("print only the diagnostic lines"))
    p.add_argument("--charger", metavar="MODEL", help=_("also warn where this charger model (e.g. imax_b6) will not "
                                                        "give a current the macro asks"))
    p.set_defaults(run=cmd_check)

    p = sub.add_parser("compile", help=_("compile a macro to its byte record"))
    p.add_argument("file", metavar="FILE")
    p.add_argument("-o", "--output", metavar="OUT.bin")
    p.add_argument("--hex", action="store_true", help=_("print the record as hex on one line"))
    p.add_argument("--listing", action="store_true", help=_("print a dis-style listing"))
    p.set_defaults(run=cmd_compile)

    p = sub.add_parser("decompile", help=_("print the canonical text of a byte record"))
    p.add_argument("file", metavar="FILE.bin")
    p.set_defaults(run=cmd_decompile)

    p = sub.add_parser("image", help=_("pack records into an EEPROM image, or list one"))
    p.add_argument("files", nargs="+", metavar="FILE", help=_(".zuml or .bin files, or the image with --list"))
    p.add_argument("-o", "--output", metavar="eeprom.bin")
    p.add_argument("--size", type=int, default=DEFAULT_SIZE,
                   help=_("EEPROM size in bytes (default {default_size})").format(default_size=DEFAULT_SIZE))
    p.add_argument("--list", action="store_true", help=_("list the records in an image"))
    p.add_argument("--extract", type=int, metavar="N", help=_("write slot N of the image to -o"))
    add_force_unsafe(p)
    p.set_defaults(run=cmd_image)


def _report(path: str, result: CompileResult, hints: bool = True, stream=None) -> None:
    stream = stream or sys.stdout       # the one main() guards, not the one there was at import
    for d in result.diagnostics:
        text = d.render(path)
        stream.write((text if hints else text.split("\n")[0]) + "\n")


def cmd_check(args: argparse.Namespace) -> int:
    charger = None
    if args.charger:
        from ..sim.charger_model import load_charger
        try:
            charger = load_charger(args.charger)
        except KeyError as exc:
            raise CliError(str(exc.args[0])) from None
    failed = False
    for path in args.files:
        result = compile_source(read_text(path), charger=charger)
        _report(path, result, not args.no_hints)
        _summary(path, result)
        failed = failed or not result.ok
    return 1 if failed else 0


def _summary(path: str, result: CompileResult) -> None:
    """``FILE: 2 errors, 1 warning`` (``, 1 note`` where there are notes) on stderr, after a file's
    diagnostics (none for a clean file)."""
    errors, warnings = len(result.errors), len(result.warnings)
    notes = len(result.diagnostics) - errors - warnings
    if not result.diagnostics:
        return
    line = _("{path}: {errors}, {warnings}").format(
        path=path, errors=ngettext("{n} error", "{n} errors", errors).format(n=errors),
        warnings=ngettext("{n} warning", "{n} warnings", warnings).format(n=warnings))
    if notes:
        line += ", " + ngettext("{n} note", "{n} notes", notes).format(n=notes)
    sys.stderr.write(line + "\n")


def compile_file(path: str, unsafe_ok: bool = False) -> bytes:
    """A .zuml file's record; errors are printed and raise CliError(exit 1). ``unsafe_ok``: the
    safety lint's errors do not stop it (the caller runs ``safety.judge`` on the bytes)."""
    result = compile_source(read_text(path), unsafe_ok=unsafe_ok)
    if not result.ok:
        _report(path, result, stream=sys.stderr)
        safety_only = all(d.code.startswith("E3") for d in result.errors)
        errors = ngettext("{n} error", "{n} errors", len(result.errors)).format(n=len(result.errors))
        if safety_only:
            raise CliError(_("{path}: {errors}; nothing written (safety errors only: --force-unsafe writes it "
                             "anyway)").format(path=path, errors=errors), 1)
        raise CliError(_("{path}: {errors}; nothing written").format(path=path, errors=errors), 1)
    return result.record


def cmd_compile(args: argparse.Namespace) -> int:
    result = compile_source(read_text(args.file))
    _report(args.file, result, stream=sys.stderr)
    if not result.ok:
        n_errors = len(result.errors)
        raise CliError(ngettext("{file}: {n_errors} error; nothing written",
                                "{file}: {n_errors} errors; nothing written", n_errors).format(
                file=args.file, n_errors=n_errors), 1)
    enc = result.encoded
    if args.hex:
        out(enc.record.hex(" "))
    if args.listing:
        out(format_listing(listing_rows(enc.record, enc.instructions, enc.nodes)))
    target = args.output or (None if args.hex or args.listing else str(Path(args.file).with_suffix(".bin")))
    if target:
        write_bytes(target, enc.record)
        if not (args.hex or args.listing):
            out(_("{target}: {n_record} bytes").format(target=target, n_record=len(enc.record)))
    return 0


def _decode(path: str, data: bytes):
    try:
        return decode_record(data)
    except DecodeError as exc:
        if is_macro_text(data):
            raise CliError(_("{path}: a macro's text, not a compiled record: `zuml compile {path}` makes "
                             "one").format(path=path), 1) from None
        raise CliError(_("{path}: not a valid ZUML record: byte {offset}: {message}").format(
                path=path, offset=exc.offset, message=exc.message), 1) from None


def cmd_decompile(args: argparse.Namespace) -> int:
    decoded = _decode(args.file, read_bytes(args.file))
    sys.stdout.write(format_macro(decoded.macro))
    return 0


def _record_of(path: str, force: bool) -> bytes:
    from ..safety import judge
    if path.lower().endswith(".bin"):
        data = read_bytes(path)
        _decode(path, data)
    else:
        data = compile_file(path, unsafe_ok=force)
    refuse_unsafe(list(judge(data).errors), force, path)
    return data


def cmd_image(args: argparse.Namespace) -> int:
    if args.list or args.extract is not None:
        if len(args.files) != 1:
            raise CliError(_("give exactly one image file"))
        image = read_bytes(args.files[0])
        if args.extract is not None and not args.output:
            raise CliError(_("--extract needs -o FILE.bin"))
        try:
            if args.extract is not None:
                record = extract(image, args.extract)
                write_bytes(args.output, record)
                out(_("{output}: slot {slot} ({name}), {n_record} bytes").format(
                        output=args.output, slot=args.extract, name=slots(image)[args.extract].name,
                        n_record=len(record)))
                return 0
            found = slots(image)
        except ImageError as exc:
            if is_macro_text(image):
                raise CliError(_("{path}: a macro's text, not an EEPROM image: `zuml image {path} -o eeprom.bin` "
                                 "packs one").format(path=args.files[0]), 1) from None
            raise CliError(f"{args.files[0]}: {exc}", 1) from None
        return _list(args.files[0], image, found)
    if not args.output:
        raise CliError(_("image needs -o eeprom.bin (or --list IMAGE)"))
    if not 16 <= args.size <= 1 << 20:
        raise CliError(_("--size {size} is not an EEPROM size (16 bytes to 1 MiB)").format(size=args.size))
    records = [_record_of(path, args.force_unsafe) for path in args.files]
    try:
        image = pack(records, args.size)
    except ImageError as exc:
        raise CliError(str(exc), 1) from None
    write_bytes(args.output, image)
    used = sum(len(r) for r in records)
    out(ngettext("{output}: {count} record, {used} of {size} bytes used, {free} free",
                 "{output}: {count} records, {used} of {size} bytes used, {free} free", len(records)).format(
            output=args.output, count=len(records), used=used, size=args.size, free=args.size - used))
    return 0


def _list(path: str, image: bytes, found) -> int:
    """The records in an image judged as ``zuml slots`` judges a charger's (the factory start templates
    and no battery passport: offline, the image is all there is)."""
    from ..safety import judge
    out(f"{'slot':>4}  {'offset':>6}  {'size':>4}  {'name':<16}  {'type':<6}  check")
    bad = 0
    for slot in found:
        if slot.ok:
            akk = slot.decoded.macro.declared(AKK_TYPE)
            kind = AKK_TYPE.operands[0].kind.format(akk.args[0].raw) if akk else "-"
            check = judge(slot.record).check()
            out(f"{slot.index:>4}  {slot.offset:>6}  {len(slot.record):>4}  {slot.name:<16}  {kind:<6}  {check}")
        else:
            bad += 1
            out(_("{index:>4}  {offset:>6}  {n_record:>4}  {value:<16}  {value:<6}  BAD: byte {offset2}: "
                  "{message}").format(
                    index=slot.index, offset=slot.offset, n_record=len(slot.record), value='?',
                    offset2=slot.error.offset, message=slot.error.message))
    used = sum(len(s.record) for s in found)
    out(ngettext("{count} record, {used} of {size} bytes used, {free} free",
                 "{count} records, {used} of {size} bytes used, {free} free", len(found)).format(
            count=len(found), used=used, size=len(image), free=len(image) - used))
    return 1 if bad else 0
