"""A charger that does not exist: the simulator's interpreter behind the device protocol.

``VirtualCharger`` is the device logic only (no ports): it takes bytes with ``receive``
and hands out the bytes to send with ``read_output``. ``transport.serve_pty`` and
``transport.serve_tcp`` put it behind a real serial port (a pty) or a TCP socket
(pyserial ``socket://``); the GUI's built-in virtual charger and the tests use it
in-process, ``zuml virtual-charger`` in its own process.

What lives in the device:
- the EEPROM (default 1024 bytes, erased 0xFF; optionally a file, written atomically on
  every commit) and the write transaction: BEGIN copies it to a staging buffer, WRITE_STAGE
  changes only the staging buffer, COMMIT checks the CRC of the whole staged image and
  then copies the changed bytes. A transfer that breaks off or is abandoned never
  touches the EEPROM;
- a battery (``BatterySpec``: chemistry, capacity, cells) and the charger's power stage,
  both persistent across runs (the battery keeps its charge and heat, and relaxes while idle);
- the interpreter, advanced in real time × ``speed`` by the device thread in small chunks;
- the battery's passport chip (docs/zuml-2.0.md §4) with a live TEMP byte;
- the start templates (START_SHABLON=n), the factory table at first, kept in memory and changed
  with SET_TEMPLATE;
- telemetry at 1..50 Hz (coalesced: a slow host gets the newest), events (queued, never
  dropped while a host reads), and a replay cache that makes a repeated request harmless.
"""
from __future__ import annotations

import math
import random
import threading
import time
from collections import deque
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Sequence

from ..domain.end_reasons import EndCode, EndReason
from ..lang.eeprom import DEFAULT_SIZE, ImageError, slots
from ..sim.battery import AMBIENT_MAX_C, AMBIENT_MIN_C, ambient_error
from ..sim.cell_pack import CellSpec, build_pack
from ..sim.charger_model import Charger, load_charger
from ..domain.chemistry import chemistry_names, load_chemistry
from ..sim.interpreter import Interpreter, Measurement, StartError, StartParams, with_template
from ..sim.program import Program
from ..sim.simulate import start_values
from ..domain.start_templates import TemplateError, check_number, factory_templates
from ..protocol import messages as m
from ..protocol.crc import crc16
from ..protocol.frames import Frame, FrameParser, encode_frame
from ..errors import ZumlError
from ..protocol.passport import Passport, PassportError, akk_code
from .passport_chip import PassportChip, default_passport
from ..i18n import _, ngettext

FIRMWARE = "zuml-virtual 1.0"
MIN_SPEED, MAX_SPEED = 1.0, 100000.0
DEFAULT_TELEMETRY_HZ = 5
STEP_S = 0.01                  # the device thread's period (wall seconds)
MAX_TICKS_PER_STEP = 400       # interpreter ticks per chunk; the lock is released between chunks
MAX_EVENTS_KEPT = 100000       # events of the current run kept for GET_EVENT
MAX_EEPROM_WRITE_MS = 100.0    # per byte: a real EEPROM takes about 3.4 ms
MAX_QUEUED_FRAMES = 20000      # output frames queued while no host reads (then the oldest go)


class DeviceSetupError(ZumlError, ValueError):
    """A virtual charger that cannot be built as asked (bad battery spec, speed, EEPROM file)."""


@dataclass(frozen=True)
class BatterySpec:
    chemistry: str = "NiMh"
    capacity_mah: float = 2000.0
    cells: int = 4
    named: str | None = None      # a saved fitted battery (sim/batteries.py): its parameters replace the defaults

    def file_cells(self) -> list[CellSpec] | None:
        """A named battery's cells (None: identical cells)."""
        if not self.named:
            return None
        from ..sim.batteries import load_battery_cells
        return load_battery_cells(self.named)[1]

    def model(self):
        """The chemistry parameters the pack is built from."""
        if self.named:
            from ..sim.batteries import load_battery
            return load_battery(self.named).chem
        return load_chemistry(self.chemistry)

    @classmethod
    def parse(cls, text: str) -> "BatterySpec":
        """``CHEM:MAH:CELLS``, e.g. ``NiMh:2000:4`` (chemistry names as ``domain.chemistry``), or
        ``battery:NAME`` for a saved fitted battery."""
        if text.startswith("battery:"):
            from ..sim.batteries import BatteryFileError, load_battery
            try:
                named = load_battery(text[len("battery:"):])
            except BatteryFileError as exc:
                raise DeviceSetupError(str(exc)) from None
            return cls(named.chem.name, named.capacity_mah, named.series, text[len("battery:"):])
        parts = text.split(":")
        if len(parts) != 3:
            raise DeviceSetupError(_("battery '{text}': write CHEMISTRY:MAH:CELLS, e.g. NiMh:2000:4").format(text=text))
        try:
            chem = load_chemistry(parts[0]).name
        except KeyError:
            raise DeviceSetupError(_("battery '{text}': no model for '{parts}'; use one of {chemistry_names}").format(
                    text=text, parts=parts[0], chemistry_names=', '.join(chemistry_names()))) from None
        try:
            cap, cells = float(parts[1]), int(parts[2])
        except ValueError:
            raise DeviceSetupError(_("battery '{text}': capacity (mAh) and cells must be numbers").format(
                    text=text)) from None
        if not 1 < cap < 65535 or not 1 <= cells <= 255 or not math.isfinite(cap):
            raise DeviceSetupError(_("battery '{text}': capacity 2..65534 mAh, cells 1..255").format(text=text))
        return cls(chem, cap, cells)

    def __str__(self) -> str:
        return f"battery:{self.named}" if self.named else f"{self.chemistry}:{self.capacity_mah:g}:{self.cells}"


@dataclass(frozen=True)
class Faults:
    """Line faults the transports inject (for tests): per-bit error rate on bytes sent and
    received, per-byte loss on received bytes, and one disconnect after N received bytes."""

    ber: float = 0.0
    drop: float = 0.0
    disconnect_after: int | None = None

    def __post_init__(self):
        if not 0.0 <= self.ber <= 0.5 or not 0.0 <= self.drop <= 1.0:
            raise DeviceSetupError(_("ber must be 0..0.5 and drop 0..1"))
        if self.disconnect_after is not None and self.disconnect_after < 0:
            raise DeviceSetupError(_("disconnect-after must be >= 0"))


class _Run:
    """One START: the interpreter and what the device reports about it."""

    def __init__(self, slot: int, name: str, params: StartParams, interpreter: Interpreter, wall0: float):
        self.slot = slot
        self.name = name
        self.params = params
        self.interpreter = interpreter
        self.wall0 = wall0             # wall time that corresponds to macro time 0 (shifted on lag/speed)
        self.events: list[m.DeviceEvent] = []
        self.taken = 0                 # interpreter events already converted


class VirtualCharger:
    """The device: protocol handling, EEPROM, battery, interpreter, passport chip.

    ``battery``: a BatterySpec or "CHEM:MAH:CELLS"; ``speed``: real time × 1..100000;
    ``eeprom_path``: load from and persist every commit to this file; ``faults``: what the
    transports inject; ``eeprom_write_ms``: modelled write time per changed byte; ``soc``: the
    battery's initial state of charge; ``sensor``: a battery temperature sensor is connected;
    ``passport``: "match" (the battery's chemistry), a chemistry name, a Passport, or None/"none";
    ``passport_factory``: the battery's passport lets the charger write SERIAL, VENDOR, TYPE and V_LIMIT
    (off: a production battery, only ERR and CRIT are writable);
    ``seed``: faults, tokens and measurement noise; ``tick_s``: the interpreter's tick;
    ``cells``: the pack's unequal cells (`sim.cell_pack.CellSpec`, one per cell; default: a named
    battery's cells, else identical cells); the charger's balancer works on them."""

    def __init__(self, battery: BatterySpec | str = BatterySpec(), *, speed: float = 1.0,
                 eeprom_path: str | Path | None = None, eeprom_size: int = DEFAULT_SIZE,
                 faults: Faults = Faults(), eeprom_write_ms: float = 0.0, soc: float = 0.0,
                 ambient_c: float = 25.0, sensor: bool = True, passport: Passport | str | None = "match",
                 charger: str = "imax_b6", seed: int | None = None, tick_s: float = 1.0,
                 telemetry_hz: int = DEFAULT_TELEMETRY_HZ, passport_factory: bool = False,
                 cells: Sequence[CellSpec] | None = None):
        self.battery = BatterySpec.parse(battery) if isinstance(battery, str) else battery
        self.speed = self._check_speed(speed)
        if not 16 <= eeprom_size <= 65535:
            raise DeviceSetupError(_("an EEPROM of {size} bytes: choose 16 to 65535").format(size=eeprom_size))
        if not 0.0 <= soc <= 1.0:
            raise DeviceSetupError(_("state of charge {soc:g}: a fraction from 0 to 1").format(soc=soc))
        if not 0 <= eeprom_write_ms <= MAX_EEPROM_WRITE_MS:
            raise DeviceSetupError(_("EEPROM write time {ms:g} ms: choose 0 to {top:g}").format(
                ms=eeprom_write_ms, top=MAX_EEPROM_WRITE_MS))
        if not AMBIENT_MIN_C <= ambient_c <= AMBIENT_MAX_C:
            raise DeviceSetupError(ambient_error(ambient_c))
        if not 1 <= telemetry_hz <= 50:
            raise DeviceSetupError(_("telemetry rate must be 1..50 Hz"))
        self.faults = faults
        self.rng = random.Random(seed)
        self.tick_s = float(tick_s)
        self.sensor = bool(sensor)
        self.eeprom_write_s = eeprom_write_ms / 1000.0
        self.eeprom_path = Path(eeprom_path) if eeprom_path else None
        self.eeprom = self._load_eeprom(eeprom_size)
        try:
            self.limits = load_charger(charger)
        except KeyError as exc:
            raise DeviceSetupError(str(exc.args[0])) from None
        self.model = f"{self.limits.name} (virtual)"
        self.ambient_c = float(ambient_c)
        try:
            self.pack = build_pack(self.battery.model(), self.battery.capacity_mah, self.battery.cells, soc, ambient_c,
                                   cells if cells is not None else self.battery.file_cells())
        except ValueError as exc:
            raise DeviceSetupError(str(exc)) from None
        self.charger = Charger(self.limits, ambient_c)
        self.chip = self._make_chip(passport, passport_factory)
        self.templates = dict(factory_templates())
        self._measurement = Measurement(seed=seed if seed is not None else 1)

        self._lock = threading.RLock()           # run state, pack, charger
        self._eeprom_lock = threading.RLock()    # eeprom, staging
        self._rx_lock = threading.Lock()         # one receiver at a time
        self._out = threading.Condition()
        self._replies: deque[bytes] = deque()    # responses (first), then events, then telemetry
        self._events_out: deque[bytes] = deque()
        self._telemetry_out: bytes | None = None
        self._partial = b""
        self.dropped_frames = 0                  # only while nobody reads, past MAX_QUEUED_FRAMES

        self._parser = FrameParser(m.HOST_TYPES)
        self._last_request: tuple[int, int, bytes] | None = None
        self._last_response: bytes = b""
        self._staging: bytearray | None = None
        self._token = 0
        self._committed: tuple[int, int, int] | None = None   # token, crc, changed
        self._run: _Run | None = None
        self._device_seq = 0
        self.telemetry_hz = telemetry_hz
        self._t0 = time.monotonic()
        self._idle_wall = self._t0
        self._next_telemetry = self._t0
        self._thread: threading.Thread | None = None
        self._stop = threading.Event()
        self._links = 0
        self.commits = 0
        self.requests = 0
        self._disconnect_spent = False           # the disconnect fault fires once
        # Share of each 10 ms period the device thread may spend running the interpreter. An
        # in-process charger (the GUI's) may lower it to keep the GIL free for the GUI.
        self.max_busy = 0.8

    # -- set-up ------------------------------------------------------------------------
    @staticmethod
    def _check_speed(speed: float) -> float:
        speed = float(speed)
        if not MIN_SPEED <= speed <= MAX_SPEED:
            raise DeviceSetupError(_("speed x{speed:g}: choose {min_speed:g} to {max_speed:g}").format(
                    speed=speed, min_speed=MIN_SPEED, max_speed=MAX_SPEED))
        return speed

    def _load_eeprom(self, size: int) -> bytearray:
        image = bytearray(b"\xff" * size)
        if self.eeprom_path is not None and self.eeprom_path.exists():
            try:
                data = self.eeprom_path.read_bytes()
            except OSError as exc:
                raise DeviceSetupError(f"{self.eeprom_path}: {exc.strerror or exc}") from None
            if len(data) > size:
                raise DeviceSetupError(_("{eeprom_path}: {n_data} bytes; the EEPROM holds {size}").format(
                        eeprom_path=self.eeprom_path, n_data=len(data), size=size))
            image[:len(data)] = data
        return image

    def _make_chip(self, passport: Passport | str | None, factory: bool) -> PassportChip | None:
        if passport is None or (isinstance(passport, str) and passport.lower() == "none"):
            return None
        if isinstance(passport, str):
            chem = self.battery.chemistry if passport.lower() == "match" else passport
            try:
                code = akk_code(chem)
            except PassportError as exc:
                raise DeviceSetupError(f"passport: {exc}") from None
            base = default_passport(self.battery.chemistry, self.battery.capacity_mah, self.battery.cells)
            passport = Passport(base.serial, base.vendor, code, 0, 0, base.v_limit, base.a_limit, 25)
        return PassportChip(passport, lambda: self.pack.temp_c, factory=factory)

    # -- lifecycle -----------------------------------------------------------------------
    def start(self) -> None:
        """Start the device thread (idempotent)."""
        with self._lock:
            if self._thread is not None and self._thread.is_alive():
                return
            self._stop.clear()
            self._idle_wall = time.monotonic()
            self._thread = threading.Thread(target=self._loop, name="virtual-charger", daemon=True)
            self._thread.start()

    def close(self) -> None:
        """Stop the device thread; the device can be started again."""
        self._stop.set()
        thread = self._thread
        if thread is not None and thread is not threading.current_thread():
            thread.join(timeout=5)
        self._thread = None
        with self._out:
            self._out.notify_all()

    def reset_link(self) -> None:
        """A new host: fresh parser, no replay of the last answer, nothing stale to send."""
        with self._rx_lock:
            self._parser = FrameParser(m.HOST_TYPES)
            self._last_request = None
        self.clear_output()

    def attach(self) -> None:
        """A transport starts serving this device: fresh link state, device thread on.
        One transport at a time (a charger has one serial port)."""
        with self._lock:
            if self._links:
                raise DeviceSetupError(_("this virtual charger is already served on a port"))
            self._links += 1
        self.reset_link()
        self.start()

    def detach(self) -> None:
        with self._lock:
            self._links = max(0, self._links - 1)
            last = self._links == 0
        if last:
            self.close()

    def __enter__(self) -> "VirtualCharger":
        self.start()
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    def set_speed(self, speed: float) -> None:
        """Change real time × speed while running; the macro clock stays continuous."""
        speed = self._check_speed(speed)
        with self._lock:
            run = self._run
            if run is not None:
                now = time.monotonic()
                run.wall0 = now - run.interpreter.time_s / speed
            self.speed = speed

    # -- what tests and the GUI may look at ---------------------------------------------------
    @property
    def eeprom_image(self) -> bytes:
        with self._eeprom_lock:
            return bytes(self.eeprom)

    @property
    def staging_open(self) -> bool:
        return self._staging is not None

    @property
    def interpreter(self) -> Interpreter | None:
        run = self._run
        return run.interpreter if run else None

    @property
    def state(self) -> str:
        with self._lock:
            return self._state()

    def _state(self) -> str:
        run = self._run
        if run is None:
            return "idle"
        it = run.interpreter
        if it.finished:
            return "finished"
        return "paused" if it.paused else "running"

    @property
    def run_events(self) -> list[m.DeviceEvent]:
        with self._lock:
            return list(self._run.events) if self._run else []

    # -- bytes in -------------------------------------------------------------------------------
    def receive(self, data: bytes) -> None:
        """Bytes from the host (any split). Requests are answered through ``read_output``."""
        with self._rx_lock:
            self._take(self._parser.feed, data)

    def line_idle(self) -> None:
        """The transport saw no bytes for a while: an incomplete frame will not complete."""
        with self._rx_lock:
            if self._parser.pending:
                self._take(lambda _: self._parser.flush_stale(), b"")

    @property
    def rx_pending(self) -> int:
        return self._parser.pending

    def _take(self, parse, data: bytes) -> None:
        p = self._parser
        garbage = p.bad_frames + p.skipped
        frames = parse(data)
        if p.bad_frames + p.skipped != garbage:
            # Tell the host at once that something arrived broken, so it resends without
            # waiting for its timeout (at most one such NAK per chunk received).
            self._queue_reply(encode_frame(m.ERROR, 0, m.encode_error(0, m.ErrorCode.BAD_FRAME, "bad frame")))
        for frame in frames:
            self._handle(frame)

    def _handle(self, frame: Frame) -> None:
        key = (frame.type, frame.seq, frame.payload)
        if key == self._last_request:
            self._queue_reply(self._last_response)       # a retry: same answer, nothing done twice
            return
        self.requests += 1
        spec = m.BY_CODE.get(frame.type)
        try:
            if spec is None or spec.request is None:
                raise _Refused(m.ErrorCode.UNKNOWN_TYPE, _("unknown request type 0x{type:02x}").format(type=frame.type))
            try:
                # An empty BEGIN_WRITE (a host without a nonce) lets the charger pick the token.
                fields = {"nonce": 0} if frame.type == m.BEGIN_WRITE and not frame.payload else \
                    m.decode_request(frame.type, frame.payload)
            except m.PayloadError as exc:
                raise _Refused(m.ErrorCode.BAD_REQUEST, f"{spec.name}: {exc}") from None
            handler = getattr(self, "_do_" + spec.name.lower(), None)
            if handler is None:         # a board's own requests (the B6's calibration): not this charger's
                raise _Refused(m.ErrorCode.UNKNOWN_TYPE, _("{name}: not a request this charger serves").format(
                    name=spec.name))
            payload = handler(**fields)
            reply = encode_frame(spec.response_code, frame.seq, payload)
        except _Refused as exc:
            reply = encode_frame(m.ERROR, frame.seq, m.encode_error(frame.type, exc.code, exc.message))
        except Exception as exc:     # noqa: BLE001 - a device never dies on a request
            reply = encode_frame(m.ERROR, frame.seq, m.encode_error(frame.type, m.ErrorCode.INTERNAL,
                                                                    f"internal error: {exc}"))
        self._last_request = key
        self._last_response = reply
        self._queue_reply(reply)

    # -- requests -------------------------------------------------------------------------------
    def _do_identify(self) -> bytes:
        lim = self.limits
        return m.encode_response(
            "IDENTIFY", protocol=m.PROTOCOL_VERSION, eeprom_size=len(self.eeprom), max_data=m.MAX_DATA,
            max_charge_ma=round(lim.max_charge_a * 1000), max_charge_dw=round(lim.max_charge_w * 10),
            max_discharge_ma=round(lim.max_discharge_a * 1000), max_discharge_dw=round(lim.max_discharge_w * 10),
            max_mv=round(lim.max_v * 1000), write_us_per_byte=round(self.eeprom_write_s * 1e6),
            model=self.model, firmware=FIRMWARE)

    def _range(self, offset: int, length: int) -> None:
        size = len(self.eeprom)
        if not 1 <= length <= m.MAX_DATA:
            raise _Refused(m.ErrorCode.BAD_RANGE, _("length {length}: 1..{max_data} bytes per request").format(
                    length=length, max_data=m.MAX_DATA))
        if offset + length > size:
            raise _Refused(m.ErrorCode.BAD_RANGE, _("bytes {first}..{last} are outside the {size}-byte EEPROM").format(
                    first=offset, last=offset + length - 1, size=size))

    def _do_read_eeprom(self, offset: int, length: int) -> bytes:
        self._range(offset, length)
        with self._eeprom_lock:
            data = bytes(self.eeprom[offset:offset + length])
        return m.encode_response("READ_EEPROM", offset=offset, data=data)

    def _do_begin_write(self, nonce: int) -> bytes:
        with self._eeprom_lock:
            self._staging = bytearray(self.eeprom)
            token = nonce           # the host's: a COMMIT of it after a reconnect tells this charger from another
            while token in (0, self._token) or (self._committed and token == self._committed[0]):
                token = self.rng.getrandbits(32)
            self._token = token
        return m.encode_response("BEGIN_WRITE", token=token, size=len(self.eeprom))

    def _do_write_stage(self, token: int, offset: int, data: bytes) -> bytes:
        self._range(offset, len(data))
        with self._eeprom_lock:
            if self._staging is None or token != self._token:
                raise _Refused(m.ErrorCode.BAD_TOKEN, _("no write in progress with this token (BEGIN_WRITE first)"))
            self._staging[offset:offset + len(data)] = data
        return m.encode_response("WRITE_STAGE", offset=offset, length=len(data))

    def _do_commit(self, token: int, crc: int) -> bytes:
        with self._eeprom_lock:
            done = self._committed
            if done is not None and token == done[0] and crc == done[1]:
                return m.encode_response("COMMIT", changed=done[2], crc=done[1])   # a repeated COMMIT
            if self._staging is None or token != self._token:
                raise _Refused(m.ErrorCode.BAD_TOKEN, _("no write in progress with this token"))
            staged = bytes(self._staging)
            actual = crc16(staged)
            if actual != crc:
                raise _Refused(m.ErrorCode.CRC_MISMATCH, _("the staged image's CRC is 0x{actual:04x}, the host says "
                                                           "0x{crc:04x}: nothing written").format(
                        actual=actual, crc=crc))
            changed = [i for i in range(len(staged)) if staged[i] != self.eeprom[i]]
            if self.eeprom_path is not None and changed:
                from ..recovery import atomic_write
                try:
                    atomic_write(self.eeprom_path, staged)      # the file first: a failure changes nothing
                except OSError as exc:
                    raise _Refused(m.ErrorCode.INTERNAL, _("the EEPROM file could not be written: {exc}").format(
                            exc=exc)) from None
            for i in changed:
                if self.eeprom_write_s:
                    time.sleep(self.eeprom_write_s)
                self.eeprom[i] = staged[i]
            self._staging = None
            self._token = 0
            self._committed = (token, crc, len(changed))
            self.commits += 1
        return m.encode_response("COMMIT", changed=len(changed), crc=crc)

    def _do_abort(self, token: int) -> bytes:
        with self._eeprom_lock:
            if token == 0 or token == self._token:
                self._staging = None
                self._token = 0
        return b""

    def _do_start(self, slot: int, task: int, repetitions: int, capacity_mah: int, current_ma: int,
                  voltage_mv: int, series: int, sensor: int) -> bytes:
        with self._lock:
            if self._run is not None and not self._run.interpreter.finished:
                # as the firmware: a START during a run would restart its limits' counters
                raise _Refused(m.ErrorCode.BUSY, _("a macro runs: stop it first"))
        if task >= len(m.TASKS):
            raise _Refused(m.ErrorCode.BAD_REQUEST, _("task {task}: 0 charge, 1 discharge, 2 train").format(task=task))
        params = StartParams(m.TASKS[task], max(1, repetitions), float(capacity_mah) if capacity_mah else None,
                             current_ma / 1000.0 if current_ma else None, voltage_mv / 1000.0 if voltage_mv else None,
                             series or None, bool(sensor) and self.sensor)
        record, name = self._slot_record(slot)
        try:
            params = with_template(Program(record), params, self.templates)   # the lockout sees the template's values
        except StartError as exc:
            raise _Refused(m.ErrorCode.START_ERROR, str(exc)) from None
        if self.chip is not None:
            try:
                passport = Passport.from_bytes(self.chip.image)
            except PassportError as exc:
                raise _Refused(m.ErrorCode.PASSPORT_CONFLICT,
                               _("the battery's passport is unreadable ({exc}); not starting").format(
                        exc=exc)) from None
            from ..safety import judge      # the host's check, again: the last line
            found = judge(record, passport, params, templates=self.templates,
                          charger_max_a=self.limits.max_charge_a).errors
            if found:
                raise _Refused(m.ErrorCode.PASSPORT_CONFLICT, "\n".join(found))
        with self._lock:
            try:
                interpreter = self._interpreter(record, params)
            except StartError as exc:
                raise _Refused(m.ErrorCode.START_ERROR, str(exc)) from None
            self._run = _Run(slot, name, interpreter.params, interpreter, time.monotonic())   # after the template
            self._next_telemetry = time.monotonic()
        return m.encode_response("START", slot=slot, name=name)

    def _slot_record(self, slot: int) -> tuple[bytes, str]:
        with self._eeprom_lock:
            image = bytes(self.eeprom)
        try:
            found = slots(image)
        except ImageError as exc:
            raise _Refused(m.ErrorCode.INVALID_RECORD, _("the EEPROM's record list is broken: {exc}").format(
                    exc=exc)) from None
        if slot >= len(found):
            raise _Refused(m.ErrorCode.BAD_SLOT,
                           ngettext("there is no slot {slot}; the EEPROM holds {n_found} macro",
                                    "there is no slot {slot}; the EEPROM holds {n_found} macros", len(found)).format(
                    slot=slot, n_found=len(found)))
        s = found[slot]
        if not s.ok:
            raise _Refused(m.ErrorCode.INVALID_RECORD, _("slot {slot} does not decode: {error}").format(
                    slot=slot, error=s.error))
        return s.record, s.name

    def _interpreter(self, record: bytes, params: StartParams) -> Interpreter:
        """As ``sim.simulate.prepare`` builds a run, but on the device's own battery, power stage and
        start templates."""
        _, params = start_values(record, params, self.templates)
        return Interpreter(record, params, self.pack, self.charger, tick_s=self.tick_s,
                           measurement=self._measurement, limit_s=math.inf, templates=self.templates)

    def _do_stop(self) -> bytes:
        with self._lock:
            run = self._run
            if run is not None and not run.interpreter.finished:
                run.interpreter.stop()
                self._flush_events(run)
                self._next_telemetry = self._idle_wall = time.monotonic()
            return m.encode_response("STOP", state=m.STATES.index(self._state()))

    def _do_status(self) -> bytes:
        with self._lock:
            run = self._run
            state = self._state()
            it = run.interpreter if run else None
            return m.encode_response(
                "STATUS", state=m.STATES.index(state), slot=run.slot if run else m.NO_SLOT,
                task=m.TASKS.index(run.params.task) if run else 0,
                uptime_ms=min(0xFFFFFFFF, round((time.monotonic() - self._t0) * 1000)),
                run_ms=min(0xFFFFFFFF, round(it.time_s * 1000)) if it else 0,
                events=len(run.events) if run else 0, speed=round(self.speed),
                name=run.name if run else "", end_reason=it.end_reason if it and it.finished else "")

    def _do_set_telemetry_rate(self, hz: int) -> bytes:
        if not 1 <= hz <= 50:
            raise _Refused(m.ErrorCode.BAD_RANGE, _("telemetry rate {hz} Hz: 1..50").format(hz=hz))
        with self._lock:
            self.telemetry_hz = hz
            self._next_telemetry = time.monotonic()
        return m.encode_response("SET_TELEMETRY_RATE", hz=hz)

    def _do_get_event(self, number: int) -> bytes:
        with self._lock:
            events = self._run.events if self._run else []
            if number >= len(events):
                raise _Refused(m.ErrorCode.BAD_RANGE, _("there is no event {number}; the run has {n_events}").format(
                        number=number, n_events=len(events)))
            return events[number].encode()

    def _do_list_templates(self) -> bytes:
        with self._lock:
            return m.encode_response("LIST_TEMPLATES", numbers=bytes(sorted(self.templates)))

    def _do_get_template(self, number: int) -> bytes:
        with self._lock:
            template = self.templates.get(number)
        if template is None:
            raise _Refused(m.ErrorCode.NO_TEMPLATE, _("there is no start template {number}; the charger holds "
                                                      "{stored}").format(
                    number=number, stored=', '.join(map(str, sorted(self.templates))) or 'none'))
        return m.encode_response("GET_TEMPLATE", **m.template_fields(number, template))

    def _do_set_template(self, **fields) -> bytes:
        try:
            number, template = m.template_of(fields)
            check_number(number)
        except TemplateError as exc:
            raise _Refused(m.ErrorCode.BAD_RANGE, _("start template {fields}: {exc}").format(
                    fields=fields['number'], exc=exc)) from None
        with self._lock:
            self.templates[number] = template
        return m.encode_response("SET_TEMPLATE", **m.template_fields(number, template))

    def _do_passport(self, request: bytes) -> bytes:
        if self.chip is None:
            raise _Refused(m.ErrorCode.NO_PASSPORT, _("the battery has no passport"))
        with self._lock:
            answer = self.chip.answer(request)      # 32 bytes, an error answer included
        return m.encode_response("PASSPORT", answer=answer)

    # -- the device thread -------------------------------------------------------------------------
    def _loop(self) -> None:
        while not self._stop.is_set():
            started = time.monotonic()
            try:
                self.step(started)
            except Exception:      # noqa: BLE001 - keep the device alive; the run is lost
                with self._lock:
                    if self._run is not None and not self._run.interpreter.finished:
                        self._run.interpreter.stop(EndReason(EndCode.DEVICE_ERROR))
                        self._flush_events(self._run)
            self._stop.wait(max(0.0, STEP_S - (time.monotonic() - started)))

    def step(self, now: float | None = None) -> None:
        """One period of the device: advance the run (or the idle battery), send what is due."""
        now = time.monotonic() if now is None else now
        run = self._run
        if run is not None and not run.interpreter.finished:
            self._advance(run, now)
        else:
            with self._lock:
                self._idle(now)
        with self._lock:
            if now >= self._next_telemetry:
                period = 1.0 / self.telemetry_hz
                self._next_telemetry = max(self._next_telemetry + period, now)
                self._queue_telemetry(self._telemetry())

    def _advance(self, run: _Run, now: float) -> None:
        deadline = time.monotonic() + STEP_S * self.max_busy
        while True:
            with self._lock:
                if self._run is not run or run.interpreter.finished:
                    break
                it = run.interpreter
                due = int(((now - run.wall0) * self.speed - it.time_s) / self.tick_s + 1e-9)
                if due <= 0:
                    break
                it.advance(min(due, MAX_TICKS_PER_STEP))
                self._flush_events(run)
                it.log.keep_last()
                if it.finished:
                    self._idle_wall = now
                    self._next_telemetry = now
            if time.monotonic() > deadline:
                # Cannot keep up with this speed: let the macro clock slip rather than pile up work.
                with self._lock:
                    lag = (now - run.wall0) * self.speed - run.interpreter.time_s
                    if lag > self.speed * 0.5:
                        run.wall0 += lag / self.speed
                break

    def _idle(self, now: float) -> None:
        """No run: the battery and the heat sink relax towards ambient (exact steps up to a minute)."""
        elapsed = (now - self._idle_wall) * self.speed
        self._idle_wall = now
        steps = 0
        while elapsed > 1e-6 and steps < 20:
            dt = min(60.0, elapsed)
            v = self.pack.step(0.0, dt)
            self.charger.step(0.0, v, dt)
            elapsed -= dt
            steps += 1

    def _flush_events(self, run: _Run) -> None:
        it = run.interpreter
        new = it.events[run.taken:]
        run.taken = len(it.events)
        for ev in new:
            dev = m.DeviceEvent(len(run.events), ev.time_s, ev.kind, ev.section, ev.index, ev.repetition,
                                ev.offset, ev.detail)
            if len(run.events) < MAX_EVENTS_KEPT:
                run.events.append(dev)
            self._queue_event(self._device_frame(m.EVENT, dev.encode()))
        if len(it.events) > 1000:     # converted already; the interpreter's own list need not grow
            del it.events[:-1]
            run.taken = len(it.events)

    def _telemetry(self) -> bytes:
        run = self._run
        sensor_t = self.pack.temp_c if self.sensor else None
        if run is None or len(run.interpreter.log) == 0:
            it = run.interpreter if run else None
            t = m.Telemetry(it.time_s if it else 0.0, run.params.task if run else "charge", "", 0, 0, 0, 0,
                            bool(run and not it.finished), False, self.sensor, self.pack.voltage, 0.0, sensor_t,
                            self.charger.heatsink_c, 0.0, 0.0)
        else:
            it = run.interpreter
            last = it.log.last()
            ph = it.phases[-1] if it.phases else None
            if not it.finished:
                t = m.Telemetry(
                    last.time_s, run.params.task, ph.section if ph else "", ph.repetition if ph else 0,
                    ph.cycle_pass if ph else 0, ph.index if ph else 0, ph.run if ph else 0, True, it.paused,
                    self.sensor, last.voltage_v, last.current_a, last.temp_c if self.sensor else None,
                    last.heatsink_c, last.mah_in, last.mah_out)
            else:       # after the end the battery rests: live readings, the run's totals
                t = m.Telemetry(
                    it.time_s, run.params.task, "", ph.repetition if ph else 0, 0, 0, 0, False, False,
                    self.sensor, self.pack.voltage, 0.0, sensor_t, self.charger.heatsink_c,
                    last.mah_in, last.mah_out)
        if self.pack.series > 1:
            t = replace(t, cells_v=self._cells_v(), balance_mask=self._balance_mask())
        return self._device_frame(m.TELEMETRY, t.encode())

    def _cells_v(self) -> tuple[float, ...]:
        pack = self.pack
        return tuple(pack.cell_voltages) if pack.per_cell else (pack.voltage / pack.series,) * pack.series

    def _balance_mask(self) -> int:
        bleed = getattr(self.pack, "bleed_a", ())
        return sum(1 << k for k, amps in enumerate(bleed) if amps)

    def _device_frame(self, type_: int, payload: bytes) -> bytes:
        seq = self._device_seq
        self._device_seq = (seq + 1) & 0xFF
        return encode_frame(type_, seq, payload)

    # -- bytes out --------------------------------------------------------------------------------
    def _queue_reply(self, frame: bytes) -> None:
        with self._out:
            self._replies.append(frame)
            self._out.notify_all()

    def _queue_event(self, frame: bytes) -> None:
        with self._out:
            self._events_out.append(frame)
            while len(self._events_out) > MAX_QUEUED_FRAMES:
                self._events_out.popleft()
                self.dropped_frames += 1
            self._out.notify_all()

    def _queue_telemetry(self, frame: bytes) -> None:
        with self._out:
            self._telemetry_out = frame      # coalesced: only the newest waits
            self._out.notify_all()

    def clear_output(self) -> None:
        with self._out:
            self._replies.clear()
            self._events_out.clear()
            self._telemetry_out = None
            self._partial = b""

    def read_output(self, max_bytes: int, timeout: float | None = None) -> bytes:
        """Up to ``max_bytes`` to send, whole frames in order (responses, events, telemetry);
        waits up to ``timeout`` for something. Never blocks the device itself."""
        with self._out:
            if not (self._partial or self._replies or self._events_out or self._telemetry_out):
                if not timeout:
                    return b""
                self._out.wait(timeout)
            out = bytearray(self._partial)
            self._partial = b""
            while len(out) < max_bytes:
                if self._replies:
                    out += self._replies.popleft()
                elif self._events_out:
                    out += self._events_out.popleft()
                elif self._telemetry_out is not None:
                    out += self._telemetry_out
                    self._telemetry_out = None
                else:
                    break
            if len(out) > max_bytes:
                self._partial = bytes(out[max_bytes:])
                del out[max_bytes:]
            return bytes(out)


class _Refused(ZumlError):
    def __init__(self, code: int, message: str):
        super().__init__(message)
        self.code = code
        self.message = message
