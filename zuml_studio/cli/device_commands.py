"""zuml ports / slots / flash / backup / restore / run / stop / monitor / passport / virtual-charger / replay."""
from __future__ import annotations

import argparse
import contextlib
import functools
import os
import queue
import signal
import sys
import threading
import time
from typing import Iterator

from ..protocol import messages as msg
from ..device.zuml.client import DEFAULT_BAUD, ChargerClient, DeviceInfo, check_image
from ..streams.drivers import AUTO, DRIVERS, LISTEN, ZUML
from ..device.errors import (CommitUncertain, CommitUnverified, DeviceError, DeviceLinkError, ImageTooLarge,
                             NotACharger)
from ..protocol.passport import FACTORY_WRITABLE, WRITABLE, Passport, PassportError, fitness_warnings, printable
from ..lang.decoder import decode_record
from ..lang.eeprom import ImageError, Slot, records, slots, used_bytes
from ..lang.record import DecodeError
from .common import CliError, add_force_unsafe, check_start_options, out, read_bytes, refuse_unsafe, write_bytes
from .lang_commands import compile_file
from ..i18n import _, ngettext


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("ports", help=_("list serial ports (and how to get a virtual charger)"))
    p.set_defaults(run=cmd_ports)

    p = _with_programmer(sub.add_parser("slots", help=_("list the macros in a charger's EEPROM")))
    p.set_defaults(run=cmd_slots)

    p = _with_programmer(sub.add_parser("flash", help=_("write macros to the charger (each replaces the one of its "
                                                        "name, or is appended)")))
    p.add_argument("file", metavar="FILE", nargs="+", help=_("a .zuml macro or a compiled .bin record"))
    p.add_argument("--slot", type=int, metavar="N", help=_("replace slot N (N = the slot count appends); one FILE"))
    add_force_unsafe(p)
    p.set_defaults(run=cmd_flash)

    p = _with_programmer(sub.add_parser("backup", help=_("save the charger's whole EEPROM image")))
    p.add_argument("-o", "--output", required=True, metavar="image.bin")
    p.set_defaults(run=cmd_backup)

    p = _with_programmer(sub.add_parser("restore", help=_("write a saved EEPROM image back to the charger")))
    p.add_argument("file", metavar="image.bin")
    add_force_unsafe(p)
    p.set_defaults(run=cmd_restore)

    p = _with_port(sub.add_parser("run", help=_("start the macro in a slot")))
    p.add_argument("--slot", type=int, required=True, metavar="N")
    p.add_argument("--task", choices=msg.TASKS, default="charge")
    p.add_argument("--cycles", type=int, default=1, metavar="N", help=_("training: discharge+charge N times"))
    p.add_argument("--capacity", type=float, metavar="MAH", help=_("capacity entered at start"))
    p.add_argument("--current", type=float, metavar="A", help=_("current entered at start (INPUT)"))
    p.add_argument("--voltage", type=float, metavar="V", help=_("voltage entered at start (INPUT)"))
    p.add_argument("--series", type=int, metavar="N", help=_("cells in series entered at start"))
    p.add_argument("--no-sensor", action="store_true", help=_("no battery temperature sensor connected"))
    add_force_unsafe(p)
    p.set_defaults(run=cmd_run)

    p = _with_port(sub.add_parser("stop", help=_("stop the running macro")))
    p.set_defaults(run=cmd_stop)

    p = _with_port(sub.add_parser("monitor", help=_("print telemetry and events as they come (Ctrl+C ends)")))
    p.add_argument("--driver", default=ZUML, metavar="NAME",
                   help=_("the charger's protocol: {zuml} (ours, default), auto (detect a monitor-only charger), "
                          "or one of {drivers}").format(zuml=ZUML, drivers=', '.join(DRIVERS)))
    p.add_argument("--csv", metavar="OUT.csv", help=_("also write every line to a CSV file"))
    p.add_argument("--seconds", type=float, metavar="S", help=_("end after S seconds"))
    p.add_argument("--samples", type=int, metavar="N", help=_("end after N samples (with --seconds: whichever "
                                                               "comes first)"))
    p.add_argument("--rate", type=int, metavar="HZ", help=_("telemetry rate to set, 1..50"))
    p.add_argument("--until-end", action="store_true", help=_("end when the running macro finishes"))
    p.set_defaults(run=cmd_monitor)

    p = _with_port(sub.add_parser("passport", help=_("read (or write fields of) the battery's passport")))
    p.add_argument("--write", action="append", default=[], metavar="FIELD=VALUE",
                   help=_("set a field ({writable}; a factory battery also {items}); may be repeated").format(
                           writable=', '.join(WRITABLE),
                           items=', '.join(f for f in FACTORY_WRITABLE if f not in WRITABLE)))
    p.set_defaults(run=cmd_passport)

    p = sub.add_parser("virtual-charger", help=_("run a simulated charger behind a serial port (pty) or TCP"))
    p.add_argument("--battery", default="NiMh:2000:4", metavar="CHEM:MAH:CELLS|battery:NAME",
                   help=_("the simulated pack (default NiMh:2000:4)"))
    p.add_argument("--speed", type=float, default=1.0, metavar="X", help=_("real time x X (1..100000)"))
    p.add_argument("--eeprom", metavar="FILE", help=_("load the EEPROM from FILE and save every commit there"))
    p.add_argument("--eeprom-size", type=int, default=1024, metavar="BYTES")
    p.add_argument("--tcp", metavar="HOST:PORT", help=_("listen on TCP (socket://HOST:PORT) instead of a pty"))
    p.add_argument("--baud", type=int, default=DEFAULT_BAUD, help=_("pace the line at this rate (0: unpaced)"))
    p.add_argument("--ber", type=float, default=0.0, metavar="P", help=_("bit error rate, both directions"))
    p.add_argument("--drop", type=float, default=0.0, metavar="P", help=_("probability a received byte is lost"))
    p.add_argument("--disconnect-after", type=int, metavar="N", help=_("close the link after N bytes received"))
    p.add_argument("--eeprom-write-ms", type=float, default=0.0, metavar="MS", help=_("write time per EEPROM byte"))
    p.add_argument("--seed", type=int, help=_("seed for the faults and the measurement noise"))
    p.add_argument("--soc", type=float, default=0.0, metavar="F", help=_("initial state of charge 0..1 (default 0)"))
    p.add_argument("--ambient", type=float, default=25.0, metavar="C")
    p.add_argument("--no-sensor", action="store_true", help=_("no battery temperature sensor"))
    p.add_argument("--cell-spread", metavar="CAP,R,SOC",
                   help=_("cells unequal: capacity and resistance within ± CAP and R %% of the pack's, start state "
                          "within ± SOC points (drawn with --seed)"))
    p.add_argument("--weak-cell", metavar="PCT[@K]", help=_("cell K (default: the last) with PCT %% less capacity"))
    p.add_argument("--passport", default="match", metavar="TYPE",
                   help=_("the battery passport's chemistry (default: the battery's; 'none': no passport)"))
    p.add_argument("--passport-factory", action="store_true",
                   help=_("a factory battery: its passport lets the charger write serial, vendor, type, v_limit "
                          "(default: a production battery, only err and crit)"))
    p.set_defaults(run=cmd_virtual_charger)

    p = sub.add_parser("replay", help=_("play a charger recording onto a serial port (pty) at its recorded pace"))
    p.add_argument("file", metavar="FILE", help=_("raw $ lines, {..} frames, Ultramat frames, a HID report dump, "
                                                  "or an iCharger DUO/X .txt log"))
    p.add_argument("--speed", type=float, default=1.0, metavar="N", help=_("recorded pace x N (default 1)"))
    p.add_argument("--as", dest="as_format", choices=tuple(DRIVERS), metavar="FORMAT",
                   help=_("read FILE as this driver's stream ({drivers}; default: recognise it)").format(
                           drivers=', '.join(DRIVERS)))
    p.set_defaults(run=cmd_replay)


def _with_port(p: argparse.ArgumentParser) -> argparse.ArgumentParser:
    p.add_argument("--port", default=os.environ.get("ZUML_PORT"), required="ZUML_PORT" not in os.environ,
                   metavar="PORT", help=_("serial port, e.g. /dev/ttyUSB0, COM3, socket://HOST:PORT (default: "
                                          "$ZUML_PORT)"))
    return _link_options(p)


def _with_programmer(p: argparse.ArgumentParser) -> argparse.ArgumentParser:
    """--port, or --programmer: an iMAX B6 with the ZUML firmware reached through its ISP programmer (avrdude)."""
    p.add_argument("--port", metavar="PORT",
                   help=_("serial port, e.g. /dev/ttyUSB0, COM3, socket://HOST:PORT (default: $ZUML_PORT); with "
                          "--programmer, the programmer's port (avrdude -P), for serial programmers"))
    p.add_argument("--programmer", metavar="ID",
                   help=_("reach an iMAX B6 with the ZUML firmware through its ISP programmer instead: avrdude's "
                          "programmer id (-c), e.g. usbasp; the battery must be disconnected"))
    return _link_options(p)


def _link_options(p: argparse.ArgumentParser) -> argparse.ArgumentParser:
    p.add_argument("--baud", type=int, metavar="B",
                   help=_("default {default_baud} for a ZUML charger, the charger's own for the other drivers").format(
                           default_baud=DEFAULT_BAUD))
    p.add_argument("--timeout", type=float, metavar="S", help=_("seconds per request attempt (default: from the baud)"))
    return p


def _device_errors(fn):
    """Every device failure becomes one line on stderr and a non-zero exit."""
    @functools.wraps(fn)
    def run(args: argparse.Namespace) -> int:
        try:
            return fn(args)
        except DeviceError as exc:
            raise CliError(_("the charger refused: {exc}").format(exc=exc), 1) from None
        except NotACharger as exc:        # most often a charger with its own firmware, which is only watched
            raise CliError(_("{exc}; a charger without ZUML firmware (cheali, iCharger, iMAX B6, Ultramat…), or a "
                             "B6 with it heard on its TX alone, is only monitored: zuml monitor --port {port} "
                             "--driver auto").format(
                    exc=exc, port=args.port), 1) from None
        except DeviceLinkError as exc:
            raise CliError(str(exc), 1) from None
        except ImageError as exc:
            raise CliError(_("EEPROM image: {exc}").format(exc=exc), 1) from None
        except PassportError as exc:
            raise CliError(f"passport: {exc}", 2) from None
    return run


# Seconds per request attempt: below a frame's time on the line nothing can answer; above a minute
# a dead line looks like a hang (inf overflowed the serial timeout, NaN disabled it).
MIN_TIMEOUT_S, MAX_TIMEOUT_S = 0.01, 60.0


def _connect(args: argparse.Namespace) -> ChargerClient:
    args.port = args.port or os.environ.get("ZUML_PORT")
    if not args.port:
        raise CliError(_("give the port: --port /dev/ttyUSB0 (see `zuml ports`)"))
    if args.timeout is not None and not MIN_TIMEOUT_S <= args.timeout <= MAX_TIMEOUT_S:
        raise CliError(_("--timeout must be {low:g} to {high:g} seconds").format(low=MIN_TIMEOUT_S, high=MAX_TIMEOUT_S))
    return ChargerClient(args.port, args.baud or DEFAULT_BAUD, args.timeout)


def _chemistry(slot: Slot) -> str:
    if not slot.decoded:
        return "?"
    from ..lang.opcodes import AKK_TYPE
    from ..sim.program import Program
    akk = Program(slot.record).intro.declarations.get(AKK_TYPE.code, 0)
    return AKK_TYPE.operands[0].kind.format(akk)


def cmd_ports(args: argparse.Namespace) -> int:
    from ..device.links.ports import list_ports
    found = list_ports(include_virtual=False)
    if not found:
        out(_("no serial ports found"))
    for p in found:
        out(p.label())
    out(_("virtual - a simulated charger: run `zuml virtual-charger` and use the port it prints"))
    return 0


@_device_errors
def cmd_slots(args: argparse.Namespace) -> int:
    if args.programmer:
        chip = _read_chip(args)
        image, found = chip.image, _slots_or_error(chip.image)
        checks = slot_checks(chip, found)
    else:
        with _connect(args) as client:
            image = client.read_image()
            found = _slots_or_error(image)
            checks = slot_checks(client, found)
    if not args.programmer:             # which charger; a B6 with a receive wire says cell 4 is not balanced
        out(_identity(client.info))
    out(f"{'#':>3}  {'offset':>6}  {'size':>4}  {'name':<16}  {'chemistry':<9}  check")
    for s, check in zip(found, checks):
        out(f"{s.index:>3}  {s.offset:>6}  {len(s.record):>4}  {s.name:<16}  {_chemistry(s):<9}  {check}")
    used = used_bytes(image)
    out(ngettext("{count} macro; free {free} of {size} bytes", "{count} macros; free {free} of {size} bytes",
                 len(found)).format(
            count=len(found), free=len(image) - used, size=len(image)))
    if args.programmer:
        out(_("start templates: {numbers}{note}").format(
            numbers=", ".join(map(str, chip.templates())) or _("none"),
            note="" if chip.templates_ready else _(" (the factory table: the firmware stores it at its next start)")))
        out(_("calibration: {state}").format(state=chip.calibration_problem() or _("valid")))
    return 0


def _progress(line: str) -> None:
    sys.stderr.write(line + "\n")
    sys.stderr.flush()


def _read_chip(args: argparse.Namespace):
    """The B6's EEPROM through its programmer (the ZUML image checked in its flash first)."""
    from ..device.install.isp_store import disconnect_warning, read_chip
    from .firmware_install_command import programmer
    sys.stderr.write(_("zuml: warning: {line}\n").format(line=disconnect_warning()))
    return read_chip(programmer(args), _progress)


def _write_chip(args: argparse.Namespace, chip, image: bytes) -> int:
    from ..device.install.isp_store import write_image
    from .firmware_install_command import programmer
    return write_image(programmer(args), chip, image, _progress)


def slot_checks(client: ChargerClient, found: list[Slot]) -> list[str]:
    """Each slot's check, judged on the bytes read back (never remembered): "ok", "BAD (why)" for a
    record that does not decode, "UNSAFE (codes)" for one the safety check refuses."""
    from ..safety import judge_slots
    return [f"BAD ({s.error.message})" if verdict is None else verdict.check()
            for s, verdict in zip(found, judge_slots(client, found))]


def _slots_or_error(image: bytes) -> list[Slot]:
    from ..lang.eeprom import slots
    try:
        return slots(image)
    except ImageError as exc:
        raise CliError(_("the charger's record list is broken ({exc}); `zuml restore` a backup").format(
                exc=exc), 1) from None


def _record(path: str, force: bool) -> bytes:
    if not path.lower().endswith(".bin"):
        return compile_file(path, unsafe_ok=force)
    data = read_bytes(path)
    try:
        decode_record(data)
    except DecodeError as exc:
        hint = _(" (a whole EEPROM image? use `zuml restore`)") if len(data) > 255 else ""
        raise CliError(_("{path}: not a valid record: byte {offset}: {message}{hint}").format(
                path=path, offset=exc.offset, message=exc.message, hint=hint), 1) from None
    return data


def _judged(records: list[tuple[str, bytes]], charger, force: bool) -> None:
    """Each record through the one safety check, against the charger's own templates (and passport)."""
    from ..safety import judge, named_template
    for path, record in records:
        verdict = judge(record, charger.passport_if_any(), templates=charger.templates_named([named_template(record)]),
                        charger_max_a=charger.info.max_charge_a)
        refuse_unsafe(list(verdict.errors), force, path)


def _merged(current: bytes, records: list[tuple[str, bytes]], slot: int | None):
    """The image with each record put in, in turn; the merges (what each did)."""
    from ..device.zuml.flashing import ImageFull, SlotOutOfRange, merge_record
    _slots_or_error(current)
    merges, image = [], current
    for __, record in records:
        try:
            merges.append(merge_record(image, record, slot))
        except SlotOutOfRange as exc:
            raise CliError(_("--slot {slot}: the charger has slots 0..{last} ({count} appends)").format(
                    slot=slot, last=exc.count - 1, count=exc.count), 1) from None
        except ImageFull as exc:
            raise CliError(_("{name} does not fit: {exc}").format(name=exc.name, exc=exc), 1) from None
        image = merges[-1].image
    return merges


def _flashed(merges, changed: int) -> None:
    """What changed per slot, then the bytes written (one line for one macro, as before)."""
    for merge in merges[:-1]:
        out(f"{merge.name}: {merge.action}")
    out(ngettext("{name}: {action}; {changed} byte written, verified",
                 "{name}: {action}; {changed} bytes written, verified", changed).format(
            name=merges[-1].name, action=merges[-1].action, changed=changed))


@_device_errors
def cmd_flash(args: argparse.Namespace) -> int:
    if args.slot is not None and len(args.file) > 1:
        raise CliError(_("--slot takes one FILE"))
    records = [(path, _record(path, args.force_unsafe)) for path in args.file]
    if args.programmer:
        chip = _read_chip(args)
        _judged(records, chip, args.force_unsafe)
        merges = _merged(chip.image, records, args.slot)
        _flashed(merges, _write_chip(args, chip, merges[-1].image))
        return 0
    with _connect(args) as client:
        _judged(records, client, args.force_unsafe)
        current = client.read_image()
        merges = _merged(current, records, args.slot)
        try:
            result = client.write_image(merges[-1].image, current=current)
        except (CommitUncertain, CommitUnverified) as exc:
            lost = exc
        else:
            _flashed(merges, result.changed)
            return 0
    _settle(args, lost, "; ".join(f"{merge.name}: {merge.action}" for merge in merges), client.info)
    return 0


SETTLE_TRIES = 5
SETTLE_PAUSE_S = 0.5


def _identity(info: DeviceInfo) -> str:
    return _("{model}, firmware {firmware}, {size} bytes of EEPROM").format(
            model=info.model, firmware=info.firmware, size=info.eeprom_size)


def _settle(args: argparse.Namespace, lost: CommitUncertain | CommitUnverified, done: str,
            flashed: DeviceInfo) -> None:
    """The link failed once COMMIT was out: say what is known, reconnect, read the EEPROM back and
    say what is there (returns only when it holds the new image and the charger is the one written
    to). IDENTIFY tells another model from the one flashed; two chargers of one model answer it alike,
    so the charger must also know the write's token, the host's random nonce (``client.committed``):
    a port that vanished may come back under its name as another unit. When it cannot be told, the
    write is "not verified"."""
    sys.stderr.write(_("zuml: warning: {lost}\n").format(lost=lost))
    sys.stderr.flush()
    for __ in range(SETTLE_TRIES):
        time.sleep(SETTLE_PAUSE_S)
        try:
            with _connect(args) as client:
                if client.info != flashed:
                    raise CliError(_("{port}: after reconnecting, another device answers there ({now}, not the "
                                     "{was} written to): nothing is known about the write; run `zuml slots` on that "
                                     "charger when it is back").format(
                            port=args.port, now=_identity(client.info), was=_identity(flashed)), 1)
                same = client.committed(lost)
                now = client.read_image()
        except DeviceLinkError:
            continue
        verdict = lost.settle(now)
        if verdict == "new" and same:
            out(_("{done}; verified after reconnecting").format(done=done))
            return
        if verdict == "new":
            why = (_("it does not know this write's token: another charger of the same model, or it restarted")
                   if same is False else _("this charger's firmware cannot tell (it does not take the host's "
                                           "nonce)"))
            raise CliError(_("{port}: after reconnecting, the charger that answers holds the new image, but it is "
                             "not verified to be the one written to ({why}); run `zuml slots` on the charger you "
                             "meant to write").format(port=args.port, why=why), 1)
        if verdict == "previous":
            raise CliError(_("reconnected and read back: the charger kept its previous image; nothing was "
                             "written, flash again"), 1)
        raise CliError(_("reconnected and read back: the EEPROM is neither the new image nor the previous one "
                         "(changed since by another program?); check it with `zuml slots`"), 1)
    known = (_("the charger confirmed the new image, unverified") if lost.holds == "new"
             else _("the charger holds either the new image or its previous one, never a mix"))
    raise CliError(_("could not reconnect to read it back: {known}; run `zuml slots` when it is back").format(
            known=known), 1)


@_device_errors
def cmd_backup(args: argparse.Namespace) -> int:
    if args.programmer:
        image = _read_chip(args).image
    else:
        with _connect(args) as client:
            image = client.read_image()
    write_bytes(args.output, image)
    try:
        found = len(records(image))
        count = ngettext("{n} macro", "{n} macros", found).format(n=found)
    except ImageError:
        count = _("a broken record list")
    out(_("saved {n_image} bytes ({count}) to {output}").format(n_image=len(image), count=count, output=args.output))
    return 0


@_device_errors
def cmd_restore(args: argparse.Namespace) -> int:
    from ..safety import judge_image, named_template
    image = read_bytes(args.file)
    check_image(image)
    if args.programmer:
        chip = _read_chip(args)
        if len(image) > chip.info.eeprom_size:
            raise ImageTooLarge(len(image), chip.info.eeprom_size)
        verdict = judge_image(image, templates=chip.templates_named(named_template(s.record) for s in slots(image)
                                                                     if s.ok))
        refuse_unsafe(list(verdict.errors), args.force_unsafe, args.file)
        changed = _write_chip(args, chip, image + b"\xff" * (chip.info.eeprom_size - len(image)))
        out(ngettext("restored {file}: {changed} byte written, verified",
                     "restored {file}: {changed} bytes written, verified", changed).format(file=args.file,
                                                                                         changed=changed))
        return 0
    with _connect(args) as client:
        if len(image) > client.info.eeprom_size:
            raise ImageTooLarge(len(image), client.info.eeprom_size)
        templates = client.templates_named(named_template(s.record) for s in slots(image) if s.ok)
        verdict = judge_image(image, client.passport_if_any(), templates=templates,
                              charger_max_a=client.info.max_charge_a)
        refuse_unsafe(list(verdict.errors), args.force_unsafe, args.file)
        try:
            result = client.write_image(image, validate=False)
        except (CommitUncertain, CommitUnverified) as exc:
            lost = exc
        else:
            out(ngettext("restored {file}: {changed} byte written, verified",
                         "restored {file}: {changed} bytes written, verified", result.changed).format(
                    file=args.file, changed=result.changed))
            return 0
    _settle(args, lost, f"restored {args.file}", client.info)
    return 0


@_device_errors
def cmd_run(args: argparse.Namespace) -> int:
    check_start_options(args, amps_max=65.5)    # START carries mA and mV as u16
    with _connect(args) as client:
        _check_start(client, args)
        try:
            name = client.start(args.slot, args.task, args.cycles, args.capacity, args.current, args.voltage,
                                args.series, not args.no_sensor)
        except DeviceError as exc:
            raise CliError(_("the charger refused to start slot {slot} ({code_name}): {exc}").format(
                    slot=args.slot, code_name=exc.code_name, exc=exc), 1) from None
    out(_("started slot {slot} ({name}): {task}").format(slot=args.slot, name=name, task=args.task))
    return 0


def _check_start(client: ChargerClient, args: argparse.Namespace) -> None:
    """The safety check on the slot's record with the values the charger will use (its start
    template's, when the macro names one); ``--force-unsafe`` prints the problems and goes ahead. A
    slot that is missing or does not decode is left to the charger's own refusal."""
    from ..safety import judge, named_template
    from ..sim.interpreter import StartParams
    try:
        found = slots(client.read_image())
    except ImageError:
        return
    if not 0 <= args.slot < len(found) or not found[args.slot].ok:
        return
    start = StartParams(args.task, args.cycles, args.capacity, args.current, args.voltage, args.series,
                        not args.no_sensor)
    record = found[args.slot].record
    verdict = judge(record, client.passport_if_any(), start, templates=client.templates_named([named_template(record)]),
                    charger_max_a=client.info.max_charge_a)
    refuse_unsafe(list(verdict.errors), args.force_unsafe,
                  _("slot {slot} ({name})").format(slot=args.slot, name=found[args.slot].name))


@_device_errors
def cmd_stop(args: argparse.Namespace) -> int:
    with _connect(args) as client:
        state = client.stop()
    out(_("stopped ({state})").format(state=state))
    return 0


def _hms(seconds: float) -> str:
    s = int(seconds)
    return f"{s // 3600}:{s % 3600 // 60:02d}:{s % 60:02d}"


def _temp(c: float | None) -> str:
    return "  --  " if c is None else f"{c:5.1f}"


def telemetry_line(t: msg.Telemetry) -> str:
    where = (f"{t.section:<9} {t.phase:>2}/{t.repetition}" if t.section
             else ("running     " if t.running else "idle        "))
    flag = " PAUSED" if t.paused else ""
    return (f"  {_hms(t.time_s):>9}  {where}  {t.voltage_v:7.3f} V  {t.current_a:+7.3f} A  "
            f"T {_temp(t.temp_c)} C  Tc {_temp(t.heatsink_c)} C  in {t.mah_in:8.1f} mAh  "
            f"out {t.mah_out:8.1f} mAh{flag}")


def event_line(e: msg.DeviceEvent) -> str:
    where = f" {e.section} {e.index}" if e.section and e.kind.startswith("phase") else \
        (f" {e.section}" if e.section else "")
    rep = f" (rep {e.repetition})" if e.kind.startswith("phase") else ""
    detail = f": {e.detail}" if e.detail else ""
    return f"* {_hms(e.time_s):>9}  {e.kind}{where}{rep}{detail}"


CSV_COLUMNS = ("time_s", "running", "paused", "section", "repetition", "cycle", "phase", "run", "voltage_v",
               "current_a", "temp_c", "heatsink_c", "mah_in", "mah_out", "event")


@_device_errors
def cmd_monitor(args: argparse.Namespace) -> int:
    if args.samples is not None and args.samples < 1:
        raise CliError(_("--samples must be at least 1"))
    if args.driver != ZUML:
        return _monitor_charger(args)
    if args.rate is not None and not 1 <= args.rate <= 50:
        raise CliError(_("--rate must be 1 to 50 Hz"))
    from .csv_sink import CsvSink
    sink = CsvSink(args.csv, CSV_COLUMNS) if args.csv else None
    client = None
    try:
        client = _connect(args)
        feed = client.subscribe()
        if args.rate:
            client.set_telemetry_rate(args.rate)
        if args.until_end and client.status().state in ("idle", "finished"):
            out(_("nothing is running"))
            return 0
        end = time.monotonic() + args.seconds if args.seconds is not None else None
        samples = 0
        for kind, item in _until(feed, end, sink.flush_if_due if sink else None):
            if kind == "disconnected":
                raise item
            if kind == "telemetry":
                out(telemetry_line(item))
                if sink:
                    sink.row((f"{item.time_s:.1f}", int(item.running), int(item.paused), item.section,
                              item.repetition, item.cycle, item.phase, item.run, f"{item.voltage_v:.3f}",
                              f"{item.current_a:.3f}", "" if item.temp_c is None else f"{item.temp_c:.2f}",
                              "" if item.heatsink_c is None else f"{item.heatsink_c:.2f}",
                              f"{item.mah_in:.1f}", f"{item.mah_out:.1f}", ""))
                samples += 1
                if samples == args.samples:
                    break
            else:
                out(event_line(item))
                if sink:
                    sink.row((f"{item.time_s:.1f}", "", "", item.section, item.repetition, "", item.index,
                              "", "", "", "", "", "", "", f"{item.kind}: {item.detail}".rstrip(": ")))
                if args.until_end and item.kind == "finish":
                    break
            sys.stdout.flush()
        if client.missed_events:
            out(ngettext("note: {n_missed_events} event was lost on the line",
                         "note: {n_missed_events} events were lost on the line", len(client.missed_events)).format(
                    n_missed_events=len(client.missed_events)))
    except KeyboardInterrupt:
        pass
    finally:
        if client is not None:
            client.close()
        if sink:
            sink.close()
    return 1 if sink and sink.failed else 0      # the failure was said on its line when it happened


@contextlib.contextmanager
def _stop_on_signal() -> Iterator[threading.Event]:
    """An event that SIGINT or SIGTERM sets while the block runs: a served port (replay, virtual
    charger) runs until then, and still closes cleanly."""
    stop_requested = threading.Event()
    old = {s: signal.signal(s, lambda signum, frame: stop_requested.set()) for s in (signal.SIGINT, signal.SIGTERM)}
    try:
        yield stop_requested
    finally:
        for s, handler in old.items():
            signal.signal(s, handler)


def _until(feed: queue.SimpleQueue, end: float | None, flush) -> Iterator[tuple[str, object]]:
    """What a reader thread queues, until ``end`` (``time.monotonic()``; None: until the caller
    stops); ``flush`` is called at least every 0.2 s, so a CSV reaches the disk while it runs."""
    while True:
        now = time.monotonic()
        if end is not None and now >= end:
            return
        if flush:
            flush()
        try:
            yield feed.get(timeout=0.2 if end is None else max(0.01, min(0.2, end - now)))
        except queue.Empty:
            continue


def _monitor_charger(args: argparse.Namespace) -> int:
    """A monitor-only charger: its samples as lines and, with --csv, the session CSV."""
    from ..device.links.monitor_link import MonitorLink
    from ..logs.session_log import SessionLog
    if args.driver not in (AUTO,) + tuple(DRIVERS):
        raise CliError(_("--driver {driver}: choose {zuml}, {auto} or one of {drivers}").format(
                driver=args.driver, zuml=ZUML, auto=AUTO, drivers=', '.join(DRIVERS)))
    if args.rate is not None or (args.until_end and args.driver != LISTEN):
        raise CliError(_("--rate and --until-end need a ZUML charger ({until_end} also with --driver {listen}); a "
                         "monitor-only charger sends at its own pace").format(until_end="--until-end", listen=LISTEN))
    if not args.port:
        raise CliError(_("give the port: --port /dev/ttyUSB0 (see `zuml ports`)"))
    log = None
    if args.csv:
        try:
            log = SessionLog(args.csv, threaded=False, cells=None)
        except OSError as exc:
            raise CliError(_("{csv}: cannot write: {error}").format(csv=args.csv, error=exc.strerror or exc)) from None
    feed: queue.SimpleQueue = queue.SimpleQueue()
    try:
        link = MonitorLink(args.port, args.driver, args.baud, on_sample=lambda t: feed.put(("sample", t)),
                           on_status=lambda s: feed.put(("status", s)),
                           on_closed=lambda e: feed.put(("closed", e)),
                           on_extra=lambda kind, item: feed.put((kind, item)))
    except DeviceLinkError as exc:
        if log:
            log.close()
        raise CliError(str(exc), 1) from None
    link.start()
    end = time.monotonic() + args.seconds if args.seconds is not None else None
    error = None
    samples = 0
    try:
        for kind, item in _until(feed, end, log.flush_if_due if log else None):
            if kind == "sample":
                out(telemetry_line(item) + _cells_text(item))
                if log:
                    log.add_telemetry(item)
                samples += 1
                if samples == args.samples:
                    break
            elif kind == "status":
                sys.stderr.write(f"{item}\n")
                sys.stderr.flush()
            elif kind == "event":
                out(event_line(item))
                if log:
                    log.add_event(item)
                if args.until_end and item.kind == "finish":
                    break
            elif kind == "lcd":
                out(lcd_line(item))
            else:
                error = item
                break
            sys.stdout.flush()
    except KeyboardInterrupt:
        pass
    finally:
        link.close()
        while True:                       # samples decoded before the link stopped still count
            try:
                kind, item = feed.get_nowait()
            except queue.Empty:
                break
            if kind == "sample" and samples != args.samples:
                out(telemetry_line(item) + _cells_text(item))
                if log:
                    log.add_telemetry(item)
                samples += 1
            elif kind == "closed" and error is None:
                error = item
        if log:
            log.close()
    name = link.driver.name if link.driver else _("no charger recognised")
    sys.stderr.write((ngettext("{name}: {samples} sample", "{name}: {samples} samples", samples)
                     + ngettext(", {bad} bad record\n", ", {bad} bad records\n", link.bad)).format(
            name=name, samples=samples, bad=link.bad))
    if error:
        raise CliError(error, 1)
    if link.driver is None and link.received == 0:
        sys.stderr.write(_("{port}: nothing arrived (a charger sends only while a program runs)\n").format(
                port=args.port))
    if log and log.error:             # the samples went on to the screen; the CSV stopped there
        sys.stderr.write(_("zuml: error: session CSV: {error}\n").format(error=log.error))
        return 1
    return 0


def lcd_line(lines: tuple[str, str]) -> str:
    """The charger's display as it heard it (the ZUML firmware's listen-only stream)."""
    return "LCD |{0:<16}|{1:<16}|".format(*lines)


def _cells_text(t: msg.Telemetry) -> str:
    """What a monitor-only charger adds to the line: its state and cells."""
    cells = ("  cells " + " ".join(f"{v:.3f}" for v in t.cells_v)) if t.cells_v else ""
    return f"  [{t.state}]{cells}" if t.state else cells


def cmd_replay(args: argparse.Namespace) -> int:
    from ..streams.drivers import CaptureError
    from ..virtual.replay import load_recording, serve_replay
    if not 0 < args.speed <= 100000:
        raise CliError(_("--speed must be more than 0 and at most 100000"))
    if os.name != "posix":
        raise CliError(_("zuml replay needs a pty (Linux, macOS)"))
    try:
        recording = load_recording(read_bytes(args.file), args.as_format)
    except CaptureError as exc:
        raise CliError(f"{args.file}: {exc}") from None
    with _stop_on_signal() as stop_requested:
        try:
            where, stop, device = serve_replay(recording, args.speed)
        except OSError as exc:
            raise CliError(_("cannot open a pty for the replay: {error}").format(
                    error=exc.strerror or exc), 1) from None
        sys.stdout.write(where + "\n")
        sys.stdout.flush()
        sys.stderr.write(ngettext("replay: {file} as {title}, {n_records} record over {duration_s:.0f} s, speed "
                                  "x{speed:g}; starts when a reader opens the port; Ctrl+C ends\n",
                                  "replay: {file} as {title}, {n_records} records over {duration_s:.0f} s, speed "
                                  "x{speed:g}; starts when a reader opens the port; Ctrl+C ends\n",
                                  len(recording.records)).format(
                file=args.file, title=_(DRIVERS[recording.driver].title), n_records=len(recording.records),
                duration_s=recording.duration_s, speed=args.speed))
        sys.stderr.flush()
        told = False
        try:
            while not stop_requested.wait(0.2):
                if device.finished.is_set() and not told:
                    sys.stderr.write(_("replay: end of the recording (the port stays open)\n"))
                    sys.stderr.flush()
                    told = True
        finally:
            stop()
    return 0


@_device_errors
def cmd_passport(args: argparse.Namespace) -> int:
    writes = []
    for item in args.write:
        field, sep, value = item.partition("=")
        if not sep:
            raise CliError(_("--write {item}: write FIELD=VALUE ({factory_writable})").format(
                    item=item, factory_writable=', '.join(FACTORY_WRITABLE)))
        Passport().with_field(field, value)          # a bad field or value fails before the port opens
        writes.append((field, value))
    with _connect(args) as client:
        for field, value in writes:
            try:
                client.passport_write(field, value)
            except DeviceError as exc:
                if exc.code != msg.ErrorCode.PASSPORT_ERROR:
                    raise
                raise CliError(_("passport: {field}: {message}").format(field=field, message=exc.message), 1) from None
        p = client.passport_read()
    out(f"serial   {printable(p.serial)}")
    out(f"vendor   {printable(p.vendor)}")
    out(_("type     {type_name} ({type})").format(type_name=p.type_name, type=p.type))
    warnings = fitness_warnings(p)
    out(f"err      {p.err}" + (_("  (warning: {warning})").format(warning=warnings[0]) if warnings else ""))
    out(f"crit     {p.crit}" + (_("  (not fit for use: the charger refuses to start)") if p.crit else ""))
    out(f"v_limit  {p.v_limit} V" + (_("  (not set)") if not p.v_limit else ""))
    out(f"a_limit  {p.a_limit} A" + (_("  (not set)") if not p.a_limit else ""))
    out(_("temp     {temp} C").format(temp=p.temp))
    if p.unprintable_fields:
        out(_("warning: the passport's {unprintable_fields} hold non-printable bytes (shown as \\xNN): a damaged "
              "or forged passport").format(unprintable_fields=' and '.join(p.unprintable_fields)))
    return 0


def cmd_virtual_charger(args: argparse.Namespace) -> int:
    from ..virtual.transport import serve_pty, serve_tcp
    from ..virtual.virtual_charger import BatterySpec, DeviceSetupError, Faults, VirtualCharger
    from ..sim.interpreter import StartError
    from ..sim.simulate import BatterySetup, pack_cells
    from .sim_commands import _spread, weak_cell
    try:
        faults = Faults(args.ber, args.drop, args.disconnect_after)
        cells = None
        if args.cell_spread or args.weak_cell:
            spec = BatterySpec.parse(args.battery)
            setup = BatterySetup(cell_spread=_spread(args.cell_spread), seed=1 if args.seed is None else args.seed,
                                 **weak_cell(args.weak_cell))
            cells = pack_cells(setup, spec.capacity_mah, spec.cells, args.soc, spec.file_cells())
        device = VirtualCharger(args.battery, speed=args.speed, eeprom_path=args.eeprom,
                                eeprom_size=args.eeprom_size, faults=faults, eeprom_write_ms=args.eeprom_write_ms,
                                soc=args.soc, ambient_c=args.ambient, sensor=not args.no_sensor,
                                passport=args.passport, seed=args.seed, passport_factory=args.passport_factory,
                                cells=cells)
    except (DeviceSetupError, StartError) as exc:
        raise CliError(str(exc)) from None
    baud = args.baud or None
    with _stop_on_signal() as stop_requested:
        try:
            if args.tcp or os.name != "posix":
                host, __, port = (args.tcp or "127.0.0.1:0").rpartition(":")
                try:
                    where, stop = serve_tcp(device, host.strip("[]") or "127.0.0.1", int(port), baud)
                except ValueError:
                    raise CliError(_("--tcp {tcp}: write HOST:PORT, e.g. 127.0.0.1:7777").format(
                            tcp=args.tcp)) from None
            else:
                where, stop = serve_pty(device, baud)
        except OSError as exc:
            raise CliError(_("cannot open the virtual charger's port: {error}").format(
                    error=exc.strerror or exc), 1) from None
        sys.stdout.write(where + "\n")
        sys.stdout.flush()
        sys.stderr.write(_("virtual charger: {model}, battery {battery}, speed x{speed:g}, passport {value}; "
                           "Ctrl+C ends\n").format(
                model=device.model, battery=device.battery, speed=device.speed,
                value='none' if device.chip is None else device.chip.passport.type_name))
        sys.stderr.flush()
        try:
            while not stop_requested.wait(0.5):
                pass
        finally:
            stop()
            device.close()
    return 0
