"""zuml ports / slots / flash / backup / restore / run / stop / monitor / passport / virtual-charger."""
from __future__ import annotations

import argparse
import csv
import functools
import os
import queue
import signal
import sys
import threading
import time

from ..device import messages as msg
from ..device.client import DEFAULT_BAUD, ChargerClient, check_image
from ..device.errors import DeviceError, DeviceLinkError, ImageTooLarge
from ..device.passport import WRITABLE, Passport, PassportError
from ..lang.decoder import decode_record
from ..lang.eeprom import ImageError, Slot, records, used_bytes
from ..lang.record import DecodeError
from .common import CliError, check_start_options, out, read_bytes, write_bytes
from .lang_commands import compile_file


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser("ports", help="list serial ports (and how to get a virtual charger)")
    p.set_defaults(run=cmd_ports)

    p = _with_port(sub.add_parser("slots", help="list the macros in a charger's EEPROM"))
    p.set_defaults(run=cmd_slots)

    p = _with_port(sub.add_parser("flash", help="write a macro to the charger (replace by name, or append)"))
    p.add_argument("file", metavar="FILE", help="a .zuml macro or a compiled .bin record")
    p.add_argument("--slot", type=int, metavar="N", help="replace slot N (N = the slot count appends)")
    p.set_defaults(run=cmd_flash)

    p = _with_port(sub.add_parser("backup", help="save the charger's whole EEPROM image"))
    p.add_argument("-o", "--output", required=True, metavar="image.bin")
    p.set_defaults(run=cmd_backup)

    p = _with_port(sub.add_parser("restore", help="write a saved EEPROM image back to the charger"))
    p.add_argument("file", metavar="image.bin")
    p.set_defaults(run=cmd_restore)

    p = _with_port(sub.add_parser("run", help="start the macro in a slot"))
    p.add_argument("--slot", type=int, required=True, metavar="N")
    p.add_argument("--task", choices=msg.TASKS, default="charge")
    p.add_argument("--cycles", type=int, default=1, metavar="N", help="training: discharge+charge N times")
    p.add_argument("--capacity", type=float, metavar="MAH", help="capacity entered at start")
    p.add_argument("--current", type=float, metavar="A", help="current entered at start (INPUT)")
    p.add_argument("--voltage", type=float, metavar="V", help="voltage entered at start (INPUT)")
    p.add_argument("--series", type=int, metavar="N", help="cells in series entered at start")
    p.add_argument("--no-sensor", action="store_true", help="no battery temperature sensor connected")
    p.set_defaults(run=cmd_run)

    p = _with_port(sub.add_parser("stop", help="stop the running macro"))
    p.set_defaults(run=cmd_stop)

    p = _with_port(sub.add_parser("monitor", help="print telemetry and events as they come (Ctrl+C ends)"))
    p.add_argument("--csv", metavar="OUT.csv", help="also write every line to a CSV file")
    p.add_argument("--seconds", type=float, metavar="S", help="end after S seconds")
    p.add_argument("--rate", type=int, metavar="HZ", help="telemetry rate to set, 1..50")
    p.add_argument("--until-end", action="store_true", help="end when the running macro finishes")
    p.set_defaults(run=cmd_monitor)

    p = _with_port(sub.add_parser("passport", help="read (or write fields of) the battery's passport"))
    p.add_argument("--write", action="append", default=[], metavar="FIELD=VALUE",
                   help=f"set a field ({', '.join(WRITABLE)}); may be repeated")
    p.set_defaults(run=cmd_passport)

    p = sub.add_parser("virtual-charger", help="run a simulated charger behind a serial port (pty) or TCP")
    p.add_argument("--battery", default="NiMh:2000:4", metavar="CHEM:MAH:CELLS|battery:NAME",
                   help="the simulated pack (default NiMh:2000:4)")
    p.add_argument("--speed", type=float, default=1.0, metavar="X", help="real time x X (1..100000)")
    p.add_argument("--eeprom", metavar="FILE", help="load the EEPROM from FILE and save every commit there")
    p.add_argument("--eeprom-size", type=int, default=1024, metavar="BYTES")
    p.add_argument("--tcp", metavar="HOST:PORT", help="listen on TCP (socket://HOST:PORT) instead of a pty")
    p.add_argument("--baud", type=int, default=DEFAULT_BAUD, help="pace the line at this rate (0: unpaced)")
    p.add_argument("--ber", type=float, default=0.0, metavar="P", help="bit error rate, both directions")
    p.add_argument("--drop", type=float, default=0.0, metavar="P", help="probability a received byte is lost")
    p.add_argument("--disconnect-after", type=int, metavar="N", help="close the link after N bytes received")
    p.add_argument("--eeprom-write-ms", type=float, default=0.0, metavar="MS", help="write time per EEPROM byte")
    p.add_argument("--seed", type=int, help="seed for the faults and the measurement noise")
    p.add_argument("--soc", type=float, default=0.0, metavar="F", help="initial state of charge 0..1 (default 0)")
    p.add_argument("--ambient", type=float, default=25.0, metavar="C")
    p.add_argument("--no-sensor", action="store_true", help="no battery temperature sensor")
    p.add_argument("--passport", default="match", metavar="TYPE",
                   help="the battery passport's chemistry (default: the battery's; 'none': no passport)")
    p.set_defaults(run=cmd_virtual_charger)


def _with_port(p: argparse.ArgumentParser) -> argparse.ArgumentParser:
    p.add_argument("--port", default=os.environ.get("ZUML_PORT"), required="ZUML_PORT" not in os.environ,
                   metavar="PORT", help="serial port, e.g. /dev/ttyUSB0, COM3, socket://HOST:PORT "
                                        "(default: $ZUML_PORT)")
    p.add_argument("--baud", type=int, default=DEFAULT_BAUD)
    p.add_argument("--timeout", type=float, metavar="S", help="seconds per request attempt (default: from the baud)")
    return p


def _device_errors(fn):
    """Every device failure becomes one line on stderr and a non-zero exit."""
    @functools.wraps(fn)
    def run(args: argparse.Namespace) -> int:
        try:
            return fn(args)
        except DeviceError as exc:
            raise CliError(f"the charger refused: {exc}", 1) from None
        except DeviceLinkError as exc:
            raise CliError(str(exc), 1) from None
        except ImageError as exc:
            raise CliError(f"EEPROM image: {exc}", 1) from None
        except PassportError as exc:
            raise CliError(f"passport: {exc}", 2) from None
    return run


def _connect(args: argparse.Namespace) -> ChargerClient:
    if not args.port:
        raise CliError("give the port: --port /dev/ttyUSB0 (see `zuml ports`)")
    return ChargerClient(args.port, args.baud, args.timeout)


def _chemistry(slot: Slot) -> str:
    if not slot.decoded:
        return "?"
    from ..lang.opcodes import AKK_TYPE
    from ..sim.program import Program
    akk = Program(slot.record).intro.declarations.get(AKK_TYPE.code, 0)
    return AKK_TYPE.operands[0].kind.format(akk)


def cmd_ports(args: argparse.Namespace) -> int:
    from ..device.ports import list_ports
    found = list_ports(include_virtual=False)
    if not found:
        out("no serial ports found")
    for p in found:
        out(p.label())
    out("virtual - a simulated charger: run `zuml virtual-charger` and use the port it prints")
    return 0


@_device_errors
def cmd_slots(args: argparse.Namespace) -> int:
    with _connect(args) as client:
        image = client.read_image()
    found = _slots_or_error(image)
    out(f"{'#':>3}  {'offset':>6}  {'size':>4}  {'name':<16}  {'chemistry':<9}  check")
    for s in found:
        check = "ok" if s.ok else f"BAD ({s.error.message})"
        out(f"{s.index:>3}  {s.offset:>6}  {len(s.record):>4}  {s.name:<16}  {_chemistry(s):<9}  {check}")
    used = used_bytes(image)
    out(f"{len(found)} macro(s); free {len(image) - used} of {len(image)} bytes")
    return 0


def _slots_or_error(image: bytes) -> list[Slot]:
    from ..lang.eeprom import slots
    try:
        return slots(image)
    except ImageError as exc:
        raise CliError(f"the charger's record list is broken ({exc}); `zuml restore` a backup", 1) from None


def _record(path: str) -> bytes:
    if not path.lower().endswith(".bin"):
        return compile_file(path)
    data = read_bytes(path)
    try:
        decode_record(data)
    except DecodeError as exc:
        hint = " (a whole EEPROM image? use `zuml restore`)" if len(data) > 255 else ""
        raise CliError(f"{path}: not a valid record: byte {exc.offset}: {exc.message}{hint}", 1) from None
    return data


@_device_errors
def cmd_flash(args: argparse.Namespace) -> int:
    from ..device.flashing import ImageFull, SlotOutOfRange, merge_record
    record = _record(args.file)
    name = decode_record(record).macro.name
    with _connect(args) as client:
        current = client.read_image()
        _slots_or_error(current)
        try:
            merged = merge_record(current, record, args.slot)
        except SlotOutOfRange as exc:
            raise CliError(f"--slot {args.slot}: the charger has slots 0..{exc.count - 1}"
                           f" ({exc.count} appends)", 1) from None
        except ImageFull as exc:
            raise CliError(f"{name} does not fit: {exc}", 1) from None
        result = client.write_image(merged.image, current=current)
    out(f"{name}: {merged.action}; {result.changed} byte(s) written, verified")
    return 0


@_device_errors
def cmd_backup(args: argparse.Namespace) -> int:
    with _connect(args) as client:
        image = client.read_image()
    write_bytes(args.output, image)
    try:
        count = f"{len(records(image))} macro(s)"
    except ImageError:
        count = "a broken record list"
    out(f"saved {len(image)} bytes ({count}) to {args.output}")
    return 0


@_device_errors
def cmd_restore(args: argparse.Namespace) -> int:
    image = read_bytes(args.file)
    check_image(image)
    with _connect(args) as client:
        if len(image) > client.info.eeprom_size:
            raise ImageTooLarge(len(image), client.info.eeprom_size)
        result = client.write_image(image, validate=False)
    out(f"restored {args.file}: {result.changed} byte(s) written, verified")
    return 0


@_device_errors
def cmd_run(args: argparse.Namespace) -> int:
    check_start_options(args, amps_max=65.5)    # START carries mA and mV as u16
    with _connect(args) as client:
        try:
            name = client.start(args.slot, args.task, args.cycles, args.capacity, args.current, args.voltage,
                                args.series, not args.no_sensor)
        except DeviceError as exc:
            raise CliError(f"the charger refused to start slot {args.slot}: {exc}", 1) from None
    out(f"started slot {args.slot} ({name}): {args.task}")
    return 0


@_device_errors
def cmd_stop(args: argparse.Namespace) -> int:
    with _connect(args) as client:
        state = client.stop()
    out(f"stopped ({state})")
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
    if args.rate is not None and not 1 <= args.rate <= 50:
        raise CliError("--rate must be 1 to 50 Hz")
    fh = None
    if args.csv:
        try:
            fh = open(args.csv, "w", encoding="utf-8", newline="")
        except OSError as exc:
            raise CliError(f"{args.csv}: cannot write: {exc.strerror or exc}") from None
    writer = csv.writer(fh, lineterminator="\n") if fh else None
    if writer:
        writer.writerow(CSV_COLUMNS)
    client = None
    try:
        client = _connect(args)
        feed = client.subscribe()
        if args.rate:
            client.set_telemetry_rate(args.rate)
        if args.until_end and client.status().state in ("idle", "finished"):
            out("nothing is running")
            return 0
        end = time.monotonic() + args.seconds if args.seconds is not None else None
        flushed = time.monotonic()
        while True:
            now = time.monotonic()
            if end is not None and now >= end:
                break
            if writer and now - flushed >= 0.5:
                fh.flush()
                flushed = now
            try:
                kind, item = feed.get(timeout=0.2 if end is None else max(0.01, min(0.2, end - now)))
            except queue.Empty:
                continue
            if kind == "disconnected":
                raise item
            if kind == "telemetry":
                out(telemetry_line(item))
                if writer:
                    writer.writerow((f"{item.time_s:.1f}", int(item.running), int(item.paused), item.section,
                                     item.repetition, item.cycle, item.phase, item.run, f"{item.voltage_v:.3f}",
                                     f"{item.current_a:.3f}", "" if item.temp_c is None else f"{item.temp_c:.2f}",
                                     "" if item.heatsink_c is None else f"{item.heatsink_c:.2f}",
                                     f"{item.mah_in:.1f}", f"{item.mah_out:.1f}", ""))
            else:
                out(event_line(item))
                if writer:
                    writer.writerow((f"{item.time_s:.1f}", "", "", item.section, item.repetition, "", item.index,
                                     "", "", "", "", "", "", "", f"{item.kind}: {item.detail}".rstrip(": ")))
                if args.until_end and item.kind == "finish":
                    break
            sys.stdout.flush()
        if client.missed_events:
            out(f"note: {len(client.missed_events)} event(s) were lost on the line")
    except KeyboardInterrupt:
        pass
    finally:
        if client is not None:
            client.close()
        if fh:
            fh.close()
    return 0


@_device_errors
def cmd_passport(args: argparse.Namespace) -> int:
    writes = []
    for item in args.write:
        field, sep, value = item.partition("=")
        if not sep:
            raise CliError(f"--write {item}: write FIELD=VALUE ({', '.join(WRITABLE)})")
        Passport().with_field(field, value)          # a bad field or value fails before the port opens
        writes.append((field, value))
    with _connect(args) as client:
        for field, value in writes:
            client.passport_write(field, value)
        p = client.passport_read()
    out(f"serial   {p.serial}")
    out(f"vendor   {p.vendor}")
    out(f"type     {p.type_name} ({p.type})")
    out(f"err      {p.err}")
    out(f"crit     {p.crit}")
    out(f"v_limit  {p.v_limit} V" + ("  (not set)" if not p.v_limit else ""))
    out(f"a_limit  {p.a_limit} A" + ("  (not set)" if not p.a_limit else ""))
    out(f"temp     {p.temp} C")
    return 0


def cmd_virtual_charger(args: argparse.Namespace) -> int:
    from ..device.transport import serve_pty, serve_tcp
    from ..device.virtual_charger import DeviceSetupError, Faults, VirtualCharger
    try:
        faults = Faults(args.ber, args.drop, args.disconnect_after)
        device = VirtualCharger(args.battery, speed=args.speed, eeprom_path=args.eeprom,
                                eeprom_size=args.eeprom_size, faults=faults, eeprom_write_ms=args.eeprom_write_ms,
                                soc=args.soc, ambient_c=args.ambient, sensor=not args.no_sensor,
                                passport=args.passport, seed=args.seed)
    except DeviceSetupError as exc:
        raise CliError(str(exc)) from None
    baud = args.baud or None
    stop_requested = threading.Event()

    def on_signal(signum, frame):
        stop_requested.set()

    old = {s: signal.signal(s, on_signal) for s in (signal.SIGINT, signal.SIGTERM)}
    try:
        try:
            if args.tcp or os.name != "posix":
                host, _, port = (args.tcp or "127.0.0.1:0").rpartition(":")
                try:
                    where, stop = serve_tcp(device, host.strip("[]") or "127.0.0.1", int(port), baud)
                except ValueError:
                    raise CliError(f"--tcp {args.tcp}: write HOST:PORT, e.g. 127.0.0.1:7777") from None
            else:
                where, stop = serve_pty(device, baud)
        except OSError as exc:
            raise CliError(f"cannot open the virtual charger's port: {exc.strerror or exc}", 1) from None
        sys.stdout.write(where + "\n")
        sys.stdout.flush()
        sys.stderr.write(f"virtual charger: {device.model}, battery {device.battery}, speed x{device.speed:g}, "
                         f"passport {'none' if device.chip is None else device.chip.passport.type_name}; "
                         "Ctrl+C ends\n")
        sys.stderr.flush()
        try:
            while not stop_requested.wait(0.5):
                pass
        finally:
            stop()
            device.close()
    finally:
        for s, handler in old.items():
            signal.signal(s, handler)
    return 0
