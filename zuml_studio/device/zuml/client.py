"""``ChargerClient``: the host side of the device protocol, for the CLI and the GUI.

One reader thread reads the port, parses frames, completes the pending request and calls
the telemetry/event callbacks. Requests are one at a time (a lock), each with its own SEQ,
a timeout derived from the baud rate and the frame sizes, and up to 3 retries with the same
SEQ (every request is idempotent: the device answers a repeated one without doing it twice).
When the device NAKs a broken frame, or garbage arrives where the answer should be, the
request is sent again at once instead of after its timeout.

Thread safety: any thread may call the methods (one request runs at a time); callbacks
run on the reader thread and must return quickly (a GUI emits a signal there).
"""
from __future__ import annotations

import logging
import queue
import random
import secrets
import threading
import time
from dataclasses import dataclass
from typing import Callable

from ...lang.eeprom import ImageError, Slot, slots
from ...protocol import messages as m
from ...protocol import passport as pp
from ...protocol.crc import crc16
from ..errors import (CommitUncertain, CommitUnverified, DeviceError, DeviceLinkError, DeviceTimeout, Disconnected, ImageTooLarge,
                     InvalidImage, NoisyLine, NotACharger, VerifyFailed, why_lost)
from ...protocol.frames import MAX_FRAME, OVERHEAD, FrameParser, encode_frame
from ..links.serial_port import open_serial
from ...i18n import _, ngettext

log = logging.getLogger(__name__)

DEFAULT_BAUD = 115200
RETRIES = 3
MIN_CHUNK = 16
PIECE_FAILURES = 8            # requests of one piece that may fail in a row (each already retried)
BACKOFF_S = 0.02              # first wait after a failed piece; doubles, at most BACKOFF_MAX_S
BACKOFF_MAX_S = 0.5
TIMEOUT_MARGIN_S = 0.1        # device processing and OS latency on top of the wire time, at least
# The link's own delay, measured: each answer's time beyond its wire time (first tries only, as an
# answer to a resent request may be the first one's) updates a smoothed delay and its variation, and a
# try waits for the delay plus four variations (RFC 6298's estimator), so a slow link (a simulated
# charger on a loaded machine, a Bluetooth bridge) gets the time it takes. A try that timed out waits
# twice as long the next time, up to TIMEOUT_MAX_S.
TIMEOUT_MAX_S = 5.0


@dataclass(frozen=True)
class DeviceInfo:
    protocol: int
    model: str
    firmware: str
    eeprom_size: int
    max_data: int
    max_charge_a: float
    max_charge_w: float
    max_discharge_a: float
    max_discharge_w: float
    max_v: float
    write_s_per_byte: float


@dataclass(frozen=True)
class Status:
    state: str                # idle | running | paused | finished
    slot: int | None
    task: str
    name: str                 # the running (or last) macro's name
    uptime_s: float           # since the device started
    run_s: float              # the macro's clock
    events: int               # events of this run so far (numbers 0..events-1)
    speed: float              # real time × speed (1 on a real charger)
    end_reason: str


@dataclass(frozen=True)
class WriteResult:
    size: int                 # EEPROM size
    changed: int              # bytes that differed
    sent: int                 # data bytes sent in WRITE_STAGE frames
    chunks: int
    seconds: float


class _Pending:
    __slots__ = ("code", "seq", "done", "payload", "error", "suspect", "nak")

    def __init__(self, code: int, seq: int):
        self.code = code
        self.seq = seq
        self.done = False
        self.payload = b""
        self.error: tuple[int, int, str] | None = None
        self.suspect = 0.0      # when garbage or a NAK arrived while waiting (0: none)
        self.nak = False        # the device said a frame reached it broken: resend at once


class ChargerClient:
    """A connection to one charger. Opening it identifies the device (``info``).

    ``timeout``: seconds per attempt; None derives it from the baud rate and frame sizes.
    Raises PortNotFound, PermissionDenied, PortBusy, NotACharger or NoisyLine."""

    def __init__(self, url: str, baudrate: int = DEFAULT_BAUD, timeout: float | None = None, *,
                 retries: int = RETRIES, exclusive: bool = True):
        self.url = url
        self.baudrate = int(baudrate)
        self.timeout = timeout
        self.retries = retries
        self._byte_s = 10.0 / self.baudrate
        self._delay_s: float | None = None        # the link's smoothed delay beyond the wire time
        self._delay_var_s = 0.0
        self._serial = open_serial(url, self.baudrate, exclusive)
        try:
            self._serial.reset_input_buffer()      # stale frames a previous session left in the port
        except Exception:   # noqa: BLE001 - not every URL handler has it
            pass
        self._parser = FrameParser(m.DEVICE_TYPES)
        self._req_lock = threading.RLock()
        self._cv = threading.Condition()
        self._pending: _Pending | None = None
        self._seq = random.randrange(256)
        self._closing = False
        self._disconnected: DeviceLinkError | None = None
        self._heard = False                       # any byte came from the device
        self._telemetry_cbs: list[Callable[[m.Telemetry], None]] = []
        self._event_cbs: list[Callable[[m.DeviceEvent], None]] = []
        self._disconnect_cbs: list[Callable[[DeviceLinkError], None]] = []
        self._queues: list[queue.Queue] = []
        self.last_telemetry: m.Telemetry | None = None
        self._next_event: int | None = None
        self.missed_events: list[int] = []      # event numbers seen missing (get_event fetches them)
        self.stats = {"requests": 0, "retries": 0, "early_resends": 0, "timeouts": 0, "stale": 0,
                      "naks": 0, "telemetry": 0, "events": 0}
        self._chunk = m.MAX_DATA
        self._good_streak = 0
        self.info: DeviceInfo | None = None
        self._reader = threading.Thread(target=self._read_loop, name=f"charger-reader {url}", daemon=True)
        self._reader.start()
        try:
            self.info = self.identify()
        except DeviceTimeout:
            self.close()
            if self._parser.damaged >= _NOISY_FRAMES:
                raise NoisyLine(noisy_line(url, self._parser.damaged)) from None
            raise NotACharger(_("{url}: no ZUML charger answered (wrong port or baud rate? tried {baudrate} "
                                  "baud)").format(
                    url=url, baudrate=self.baudrate)) from None
        except DeviceError as exc:
            self.close()
            raise NotACharger(_("{url}: the device refused IDENTIFY ({exc}); not a ZUML charger?").format(
                    url=url, exc=exc)) from None
        except Disconnected:
            self.close()
            # Only a TCP charger that already serves another program closes a new connection at once.
            maybe = _(" (or it serves another program already)") if url.lower().startswith("socket://") \
                and not self._heard else ""
            raise Disconnected(_("{url}: the connection closed before the charger answered: it stopped or went "
                                 "away{maybe}").format(url=url, maybe=maybe)) from None
        except BaseException:
            self.close()
            raise
        if self.info.protocol != m.PROTOCOL_VERSION:
            version = self.info.protocol
            self.close()
            raise NotACharger(_("{url}: the charger speaks protocol {version}; this ZUML Studio speaks "
                                "{protocol_version}").format(
                    url=url, version=version, protocol_version=m.PROTOCOL_VERSION))
        self._chunk = max(MIN_CHUNK, min(self.info.max_data, m.MAX_DATA))

    # -- lifecycle -----------------------------------------------------------------------------
    def close(self) -> None:
        """Idempotent. Callbacks are not called after close returns."""
        self._closing = True
        try:
            self._serial.cancel_read()
        except Exception:   # noqa: BLE001 - closing: whatever a dying port raises, it is being closed
            pass
        if self._reader.is_alive() and self._reader is not threading.current_thread():
            self._reader.join(timeout=2)
        try:
            self._serial.close()
        except Exception:   # noqa: BLE001 - closing: whatever a dying port raises, it is closed
            pass
        with self._cv:
            if self._disconnected is None:
                self._disconnected = Disconnected(_("{url}: closed").format(url=self.url))
            self._cv.notify_all()

    def __enter__(self) -> "ChargerClient":
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    @property
    def connected(self) -> bool:
        return self._disconnected is None

    # -- callbacks -------------------------------------------------------------------------------
    def on_telemetry(self, callback: Callable[[m.Telemetry], None]) -> None:
        self._telemetry_cbs.append(callback)

    def on_event(self, callback: Callable[[m.DeviceEvent], None]) -> None:
        self._event_cbs.append(callback)

    def on_disconnect(self, callback: Callable[[DeviceLinkError], None]) -> None:
        self._disconnect_cbs.append(callback)

    def subscribe(self, maxsize: int = 10000) -> queue.Queue:
        """A queue of ("telemetry", Telemetry), ("event", DeviceEvent) and ("disconnected", error).
        When it is full the oldest item goes (a consumer that stalls loses old samples, not the link)."""
        q: queue.Queue = queue.Queue(maxsize)
        self._queues.append(q)
        return q

    def unsubscribe(self, q: queue.Queue) -> None:
        if q in self._queues:
            self._queues.remove(q)

    # -- the reader thread --------------------------------------------------------------------------
    def _read_loop(self) -> None:
        ser = self._serial
        parser = self._parser
        while not self._closing:
            try:
                data = ser.read(ser.in_waiting or 1)
            except Exception as exc:   # noqa: BLE001 - SerialException, OSError, a closed port
                if not self._closing:
                    self._lost(Disconnected(_("{url}: the connection was lost ({why_lost})").format(
                            url=self.url, why_lost=why_lost(exc))))
                return
            if not data:
                if parser.pending:           # the line went quiet inside a frame: its LEN was garbage
                    frames = parser.flush_stale()
                    self._suspect()
                    for frame in frames:
                        self._dispatch_safely(frame)
                continue
            self._heard = True
            garbage = parser.bad_frames + parser.skipped
            frames = parser.feed(data)
            if parser.bad_frames + parser.skipped != garbage:
                self._suspect()
            for frame in frames:
                self._dispatch_safely(frame)

    def _dispatch_safely(self, frame) -> None:
        try:
            self._dispatch(frame)
        except Exception:   # a callback's bug never kills the link
            log.exception("charger client: handling a frame failed")

    def _suspect(self) -> None:
        with self._cv:
            if self._pending is not None and not self._pending.done:
                self._pending.suspect = time.monotonic()
                self._cv.notify_all()

    def _lost(self, exc: DeviceLinkError) -> None:
        with self._cv:
            if self._disconnected is None:
                self._disconnected = exc
            self._cv.notify_all()
        for cb in list(self._disconnect_cbs):
            try:
                cb(exc)
            except Exception:
                log.exception("charger client: disconnect callback failed")
        self._publish(("disconnected", exc))

    def _publish(self, item) -> None:
        for q in list(self._queues):
            while True:
                try:
                    q.put_nowait(item)
                    break
                except queue.Full:
                    try:
                        q.get_nowait()
                    except queue.Empty:
                        pass

    def _dispatch(self, frame) -> None:
        t = frame.type
        if t == m.TELEMETRY:
            try:
                tel = m.Telemetry.decode(frame.payload)
            except m.PayloadError:
                return
            self.last_telemetry = tel
            self.stats["telemetry"] += 1
            for cb in list(self._telemetry_cbs):
                cb(tel)
            self._publish(("telemetry", tel))
        elif t == m.EVENT:
            try:
                ev = m.DeviceEvent.decode(frame.payload)
            except m.PayloadError:
                return
            self.stats["events"] += 1
            expected = self._next_event
            if expected is not None and ev.number > expected and ev.number - expected < 10000:
                self.missed_events.extend(range(expected, ev.number))
            if ev.number == 0 or expected is None or ev.number >= expected:
                self._next_event = ev.number + 1
            for cb in list(self._event_cbs):
                cb(ev)
            self._publish(("event", ev))
        elif t == m.ERROR:
            try:
                req, code, text = m.decode_error(frame.payload)
            except m.PayloadError:
                return
            with self._cv:
                p = self._pending
                if req == 0 and code == m.ErrorCode.BAD_FRAME:
                    self.stats["naks"] += 1
                    if p is not None and not p.done:
                        p.suspect = time.monotonic()
                        p.nak = True
                        self._cv.notify_all()
                elif p is not None and not p.done and frame.seq == p.seq and req == p.code:
                    p.error = (req, code, text)
                    p.done = True
                    self._cv.notify_all()
                else:
                    self.stats["stale"] += 1
        elif t & m.RESPONSE_FLAG:
            with self._cv:
                p = self._pending
                if p is not None and not p.done and frame.seq == p.seq and (t & 0x7F) == p.code:
                    p.payload = frame.payload
                    p.done = True
                    self._cv.notify_all()
                else:
                    self.stats["stale"] += 1

    # -- requests -------------------------------------------------------------------------------------
    def _wire_s(self, request_len: int, response_len: int) -> float:
        return (request_len + OVERHEAD + response_len + OVERHEAD) * self._byte_s

    def _attempt_timeout(self, request_len: int, response_len: int) -> float:
        if self.timeout is not None:
            return self.timeout
        margin = TIMEOUT_MARGIN_S
        if self._delay_s is not None:
            margin = max(margin, self._delay_s + 4 * self._delay_var_s)
        return min(TIMEOUT_MAX_S, self._wire_s(request_len, response_len) * 1.5 + margin)

    def _measured(self, delay_s: float) -> None:
        """One first try's answer came ``delay_s`` after its wire time: update the link's delay."""
        delay_s = max(0.0, delay_s)
        if self._delay_s is None:
            self._delay_s, self._delay_var_s = delay_s, delay_s / 2
        else:
            self._delay_var_s = 0.75 * self._delay_var_s + 0.25 * abs(self._delay_s - delay_s)
            self._delay_s = 0.875 * self._delay_s + 0.125 * delay_s

    def request(self, name: str, payload: bytes = b"", *, response_len: int = MAX_FRAME,
                extra_s: float = 0.0) -> bytes:
        """Send a request by message name, return the response payload.

        Raises DeviceError (the device refused), DeviceTimeout, Disconnected."""
        code = m.BY_NAME[name].code
        if threading.current_thread() is self._reader:
            raise RuntimeError(_("a request from a telemetry/event callback would wait for its own reader "
                                 "thread; hand the work to another thread"))
        with self._req_lock:
            if self._disconnected is not None:
                raise self._disconnected
            self._seq = (self._seq + 1) & 0xFF
            seq = self._seq
            frame = encode_frame(code, seq, payload)
            per_try = self._attempt_timeout(len(payload), response_len) + extra_s
            first_try = per_try
            # After garbage where the answer should be, wait a little for the rest of it, then resend.
            grace = min(per_try, 0.002 + 0.25 * (response_len + OVERHEAD) * self._byte_s)
            pending = _Pending(code, seq)
            with self._cv:
                self._pending = pending
            self.stats["requests"] += 1
            timeouts = 0
            resends = 0
            # Tries double (per_try, 2x, 4x, ...): the whole request may take their sum.
            deadline_total = time.monotonic() + per_try * ((2 ** (self.retries + 1) - 1) if self.timeout is None
                                                           else self.retries + 1)
            try:
                while True:
                    self._write(frame)
                    sent_at = time.monotonic()
                    with self._cv:
                        pending.suspect = 0.0
                        pending.nak = False
                        while True:
                            if pending.done or self._disconnected is not None:
                                break
                            now = time.monotonic()
                            if now - sent_at >= per_try:
                                break
                            wait_more = 0.0005 if pending.nak else grace
                            if pending.suspect and now - pending.suspect >= wait_more:
                                break
                            wait = per_try - (now - sent_at)
                            if pending.suspect:
                                wait = min(wait, wait_more - (now - pending.suspect))
                            self._cv.wait(max(0.0005, wait))
                        if pending.done:
                            if timeouts + resends == 0 and self.timeout is None:
                                self._measured(time.monotonic() - sent_at - extra_s
                                               - self._wire_s(len(payload), len(pending.payload or b"")))
                            break
                        if self._disconnected is not None:
                            raise self._disconnected
                        early = bool(pending.suspect) and time.monotonic() - sent_at < per_try
                    if early and resends < 8 and time.monotonic() < deadline_total:
                        resends += 1
                        self.stats["early_resends"] += 1
                        continue
                    timeouts += 1
                    self.stats["timeouts"] += 1
                    if timeouts > self.retries or time.monotonic() >= deadline_total + per_try:
                        raise DeviceTimeout(_("{url}: no answer to {name} after {timeouts} tries ({first:.2f} s "
                                              "to {per_try:.2f} s each)").format(
                                url=self.url, name=name, timeouts=timeouts, first=first_try, per_try=per_try))
                    self.stats["retries"] += 1
                    if self.timeout is None:
                        per_try = min(per_try * 2, max(TIMEOUT_MAX_S, first_try))
            finally:
                with self._cv:
                    self._pending = None
            self._note_quality(timeouts + resends == 0)
            if pending.error is not None:
                req, err, text = pending.error
                raise DeviceError(err, text, req)
            return pending.payload

    def _write(self, frame: bytes) -> None:
        try:
            self._serial.write(frame)
        except Exception as exc:   # noqa: BLE001 - pyserial on a port gone under it: SerialException, OSError, TypeError
            import serial
            if isinstance(exc, serial.SerialTimeoutException):
                raise DeviceTimeout(_("{url}: the port does not take data (flow control?)").format(
                        url=self.url)) from None
            err = Disconnected(_("{url}: the connection was lost ({exc})").format(url=self.url, exc=exc))
            self._lost(err)
            raise err from None

    def _note_quality(self, clean: bool) -> None:
        """Adaptive chunk size: halve on a noisy request, grow back after a clean streak."""
        top = self.info.max_data if self.info else m.MAX_DATA
        if clean:
            self._good_streak += 1
            if self._good_streak >= 8 and self._chunk < top:
                self._chunk = min(top, self._chunk * 2)
                self._good_streak = 0
        else:
            self._good_streak = 0
            self._chunk = max(MIN_CHUNK, self._chunk // 2)

    def _call(self, name: str, response_len: int = MAX_FRAME, extra_s: float = 0.0, **fields) -> dict:
        payload = m.encode_request(name, **fields)
        answer = self.request(name, payload, response_len=response_len, extra_s=extra_s)
        try:
            return m.decode_response(m.BY_NAME[name].code, answer)
        except m.PayloadError as exc:
            raise DeviceError(m.ErrorCode.BAD_REQUEST, _("the charger's answer to {name} does not fit: {exc}").format(
                    name=name, exc=exc)) from None

    # -- the API -------------------------------------------------------------------------------------
    def identify(self) -> DeviceInfo:
        v = self._call("IDENTIFY", response_len=80)
        return DeviceInfo(v["protocol"], v["model"], v["firmware"], v["eeprom_size"], v["max_data"],
                          v["max_charge_ma"] / 1000.0, v["max_charge_dw"] / 10.0, v["max_discharge_ma"] / 1000.0,
                          v["max_discharge_dw"] / 10.0, v["max_mv"] / 1000.0, v["write_us_per_byte"] / 1e6)

    def read_eeprom(self, offset: int, length: int) -> bytes:
        v = self._call("READ_EEPROM", response_len=length + 2, offset=offset, length=length)
        if v["offset"] != offset or len(v["data"]) != length:
            raise DeviceError(m.ErrorCode.BAD_REQUEST,
                              _("asked for {length} bytes at {offset}, got {n_v} at {v}").format(
                    length=length, offset=offset, n_v=len(v['data']), v=v['offset']))
        return v["data"]

    def read_image(self, progress: Callable[[str, int, int], None] | None = None, *, stage: str = "read") -> bytes:
        size = self.info.eeprom_size
        out = bytearray()
        while len(out) < size:
            at = len(out)
            out += self._in_pieces(min(self._chunk, size - at), lambda n: self.read_eeprom(at, n))
            if progress:
                progress(stage, len(out), size)
        return bytes(out)

    def _in_pieces(self, n: int, do: Callable[[int], object]):
        """``do(n)``; when its request fails every retry (a noisy line, a long frame that rarely gets
        through whole), again with half the piece after a growing pause, down to MIN_CHUNK bytes;
        DeviceTimeout after PIECE_FAILURES failures in a row. ``do`` must do the first n bytes."""
        failures = 0
        while True:
            try:
                return do(n)
            except DeviceTimeout:
                failures += 1
                if failures >= PIECE_FAILURES:
                    raise
                n = max(min(MIN_CHUNK, n), n // 2)
                self._chunk = min(self._chunk, max(MIN_CHUNK, n))
                self._good_streak = 0
                _pause(min(BACKOFF_MAX_S, BACKOFF_S * 2 ** (failures - 1)))

    def slots(self) -> list[Slot]:
        """The macros in the device's EEPROM (``lang.eeprom.slots``; ImageError for a broken list)."""
        return slots(self.read_image())

    def write_image(self, image: bytes, progress: Callable[[str, int, int], None] | None = None, *,
                    validate: bool = True, current: bytes | None = None) -> WriteResult:
        """Make the device's EEPROM equal ``image`` (padded with 0xFF to the EEPROM size).

        Reads the present image (unless ``current``, what the caller last read, is given; a stale
        one costs a refused COMMIT and a fresh read), stages only the bytes that
        differ, commits with the CRC of the whole image, reads back and compares. Any failure
        raises and leaves the device's previous image as it was (the write is staged until
        COMMIT). ``progress(stage, done, total)`` with stage "read", "write", "verify"."""
        started = time.monotonic()
        size = self.info.eeprom_size
        if len(image) > size:
            raise ImageTooLarge(len(image), size)
        image = bytes(image) + b"\xff" * (size - len(image))
        if validate:
            check_image(image)
        if current is not None and len(current) == size and current != image:
            try:
                return self._write_image(image, current, progress, started)
            except DeviceError as exc:
                if exc.code != m.ErrorCode.CRC_MISMATCH:
                    raise
                # The image the caller knew is stale (the EEPROM changed since): read it and try again.
        return self._write_image(image, self.read_image(progress), progress, started)

    def _write_image(self, image: bytes, current: bytes, progress, started: float) -> WriteResult:
        size = len(image)
        runs = _changed_runs(current, image)
        changed = sum(a != b for a, b in zip(current, image))
        if not changed:
            return WriteResult(size, 0, 0, 0, time.monotonic() - started)
        nonce = secrets.randbits(32) or 1
        token = self._call("BEGIN_WRITE", response_len=6, nonce=nonce)["token"]
        proof = {"token": token, "nonce_taken": token == nonce}
        sent = chunks = 0
        commit_sent = confirmed = False
        try:
            total = sum(len(d) for __, d in runs)
            for offset, data in runs:
                at = 0
                while at < len(data):
                    start = offset + at
                    rest = data[at:]

                    def stage(n: int) -> int:
                        piece = rest[:n]
                        v = self._call("WRITE_STAGE", response_len=3, token=token, offset=start, data=piece)
                        if v["offset"] != start or v["length"] != len(piece):
                            raise DeviceError(m.ErrorCode.BAD_REQUEST, _("the charger staged other bytes than sent"))
                        return len(piece)
                    done = self._in_pieces(min(self._chunk, len(rest)), stage)
                    at += done
                    sent += done
                    chunks += 1
                    if progress:
                        progress("write", sent, total)
            write_s = changed * self.info.write_s_per_byte * 1.5
            commit_sent = True
            self._call("COMMIT", response_len=4, extra_s=write_s, token=token, crc=crc16(image))
            confirmed = True
        except DeviceTimeout:
            if not commit_sent:
                self._abort(token)
                raise
            # Every answer to COMMIT was lost, perhaps not the COMMIT itself: the read-back tells.
        except Disconnected as exc:
            if commit_sent:
                raise self._uncertain(exc, image, current, proof) from None
            raise
        except BaseException:
            self._abort(token)
            raise
        try:
            back = self.read_image(progress, stage="verify")
        except DeviceLinkError as exc:
            if confirmed:
                raise CommitUnverified(ngettext("{url}: the charger confirmed the new image ({changed} byte changed), "
                                                "then the link failed while reading it back ({error}): reconnect to "
                                                "verify it",
                                                "{url}: the charger confirmed the new image ({changed} bytes changed), "
                                                "then the link failed while reading it back ({error}): reconnect to "
                                                "verify it", changed).format(url=self.url, changed=changed, error=exc),
                                       image, current, **proof) from None
            raise self._uncertain(exc, image, current, proof) from None
        if back != image:
            if not confirmed and back == current:
                raise DeviceTimeout(_("{url}: the charger did not take COMMIT; it keeps its previous image").format(
                        url=self.url))
            at = next(i for i in range(size) if back[i] != image[i])
            raise VerifyFailed(_("verify failed: byte {at} reads 0x{back:02x}, wrote 0x{image:02x}").format(
                    at=at, back=back[at], image=image[at]))
        return WriteResult(size, changed, sent, chunks, time.monotonic() - started)

    def _abort(self, token: int) -> None:
        """Drop a staged write (best effort: the device drops it anyway on the next BEGIN_WRITE)."""
        if self._disconnected is None:
            try:
                self._call("ABORT", response_len=0, token=token)
            except DeviceLinkError:
                pass

    def _uncertain(self, exc: DeviceLinkError, image: bytes, current: bytes, proof: dict) -> CommitUncertain:
        return CommitUncertain(_("{url}: the link failed right after COMMIT ({error}); the charger holds "
                                 "either the new image or its previous one, never a mix: reconnect to tell "
                                 "which").format(url=self.url, error=exc), image, current, **proof)

    def committed(self, lost: CommitUncertain | CommitUnverified) -> bool | None:
        """After a reconnect: is this the charger that committed ``lost``'s write? COMMIT of its token
        again is answered only by the unit that committed it (a repeated COMMIT), never by another of
        its model, which knows no such token. ABORT first drops the write if it is still staged here,
        so that asking never commits it late. None: it cannot be told (the charger did not take the
        host's nonce as the token, or it restarted and forgot it: then False too)."""
        if not lost.nonce_taken:
            return None
        self._abort(lost.token)
        try:
            answer = self._call("COMMIT", response_len=4, token=lost.token, crc=crc16(lost.image))
        except DeviceError as exc:
            if exc.code in (m.ErrorCode.BAD_TOKEN, m.ErrorCode.CRC_MISMATCH):
                return False
            raise
        return answer["crc"] == crc16(lost.image)

    def start(self, slot: int, task: str = "charge", repetitions: int = 1, capacity_mah: float | None = None,
              current_a: float | None = None, voltage_v: float | None = None, series: int | None = None,
              sensor: bool = True) -> str:
        """Start the macro in ``slot``; returns its name. DeviceError lists a refusal's reasons
        (``.lines``: one passport conflict per line)."""
        if task not in m.TASKS:
            raise ValueError(_("task must be one of {tasks}").format(tasks=', '.join(m.TASKS)))
        v = self._call("START", response_len=40, slot=slot, task=m.TASKS.index(task),
                       repetitions=max(1, min(255, int(repetitions))),
                       capacity_mah=_u16(capacity_mah, 1), current_ma=_u16(current_a, 1000),
                       voltage_mv=_u16(voltage_v, 1000), series=min(255, int(series or 0)), sensor=int(bool(sensor)))
        self._next_event = None
        self.missed_events.clear()
        return v["name"]

    def stop(self) -> str:
        """Stop the running macro (nothing happens if none runs); returns the state after."""
        return m.STATES[min(self._call("STOP", response_len=1)["state"], len(m.STATES) - 1)]

    def status(self) -> Status:
        v = self._call("STATUS", response_len=120)
        return Status(m.STATES[min(v["state"], 3)], None if v["slot"] == m.NO_SLOT else v["slot"],
                      m.TASKS[min(v["task"], 2)], v["name"], v["uptime_ms"] / 1000.0, v["run_ms"] / 1000.0,
                      v["events"], float(v["speed"]), v["end_reason"])

    def set_telemetry_rate(self, hz: int) -> int:
        return self._call("SET_TELEMETRY_RATE", response_len=1, hz=int(hz))["hz"]

    def get_event(self, number: int) -> m.DeviceEvent:
        """An event of the current run again (to fill a gap in ``missed_events``)."""
        answer = self.request("GET_EVENT", m.encode_request("GET_EVENT", number=number), response_len=220)
        ev = m.DeviceEvent.decode(answer)
        if number in self.missed_events:
            self.missed_events.remove(number)
        return ev

    def list_templates(self) -> list[int]:
        """The numbers of the start templates the charger holds."""
        return list(self._call("LIST_TEMPLATES", response_len=32)["numbers"])

    def get_template(self, number: int):
        """Start template ``number`` as a ``domain.start_templates.StartTemplate``; DeviceError NO_TEMPLATE."""
        return _template(self._call("GET_TEMPLATE", response_len=12, number=number))

    def templates_named(self, numbers) -> dict:
        """The charger's start templates with these numbers (None among them ignored), for the
        safety check: a number the charger does not hold is left out (a start then is refused)."""
        table = {}
        for number in sorted({n for n in numbers if n is not None}):
            try:
                table[number] = self.get_template(number)
            except DeviceError as exc:
                if exc.code not in (m.ErrorCode.NO_TEMPLATE, m.ErrorCode.UNKNOWN_TYPE):
                    raise
        return table

    def set_template(self, number: int, template):
        """Store a ``StartTemplate`` as template ``number``; returns what the charger stored."""
        return _template(self._call("SET_TEMPLATE", response_len=12, **m.template_fields(number, template)))

    def passport_raw(self, request: bytes) -> bytes:
        """Pass an 8-byte passport request to the battery; its 32-byte answer."""
        answer = self._call("PASSPORT", response_len=pp.SIZE, request=bytes(request))["answer"]
        if len(answer) != pp.SIZE:
            raise DeviceError(m.ErrorCode.PASSPORT_ERROR, _("the passport answer has {n_answer} bytes, not 32").format(
                    n_answer=len(answer)))
        return answer

    def _passport_answer(self, request: bytes) -> bytes:
        """The answer to a request; DeviceError when the battery answers with an error."""
        answer = self.passport_raw(request)
        refused = pp.answer_error(answer)
        if refused is not None:
            raise DeviceError(m.ErrorCode.PASSPORT_ERROR, _("the battery refused: {refused}").format(refused=refused))
        return answer

    def passport_read(self) -> pp.Passport:
        answer = self._passport_answer(pp.read_all_request())
        try:
            return pp.Passport.from_bytes(answer)
        except pp.PassportError as exc:
            raise DeviceError(m.ErrorCode.PASSPORT_ERROR, _("the battery's passport is unreadable: {exc}").format(
                    exc=exc)) from None

    def passport_if_any(self) -> pp.Passport | None:
        """The passport, or None when the battery has no chip or an unreadable one (the charger's
        own check at START then decides)."""
        try:
            return self.passport_read()
        except DeviceError as exc:
            if exc.code in (m.ErrorCode.NO_PASSPORT, m.ErrorCode.PASSPORT_ERROR):
                return None
            raise

    def passport_write(self, field: str, value) -> pp.Passport:
        """Set one field (a production battery takes err and crit only; a factory one also serial,
        vendor, type and v_limit); writes only the pages that change, then reads the passport back.
        PassportError for a bad field or value, DeviceError when the battery refuses the write."""
        old = self._passport_answer(pp.read_all_request())
        try:
            current = pp.Passport.from_bytes(old)
        except pp.PassportError as exc:
            raise DeviceError(m.ErrorCode.PASSPORT_ERROR, _("the battery's passport is unreadable: {exc}").format(
                    exc=exc)) from None
        wanted = current.with_field(field, value)
        for req in pp.page_writes(old, wanted.to_bytes()):
            self._passport_answer(req)
        now = self.passport_read()
        key = field.strip().lower()
        if getattr(now, key) != getattr(wanted, key):
            raise VerifyFailed(_("the passport's {key} reads {read!r} after writing {written!r}").format(
                    key=key, read=getattr(now, key), written=getattr(wanted, key)))
        return now


def check_image(image: bytes) -> None:
    """Refuse an image whose record list is broken or holds a record that does not decode."""
    try:
        found = slots(image)
    except ImageError as exc:
        raise InvalidImage(_("the image's record list is broken: {exc}").format(exc=exc)) from None
    bad = [s for s in found if not s.ok]
    if bad:
        s = bad[0]
        raise InvalidImage(_("slot {index} at offset {offset} does not decode: {error}").format(
                index=s.index, offset=s.offset, error=s.error))


# Damaged answers (whole frames that fail only their CRC) that make a silent IDENTIFY a noisy line.
_NOISY_FRAMES = 2


def noisy_line(url: str, damaged: int) -> str:
    """What a link says when the charger answers but no answer arrives whole."""
    return ngettext("{url}: the charger answers, but {n} answer arrived damaged (a bad CRC) and none whole: the "
                    "line is noisy (a long or poor cable, a loose connector, a bad USB adapter); try another cable "
                    "or port",
                    "{url}: the charger answers, but {n} answers arrived damaged (a bad CRC) and none whole: the "
                    "line is noisy (a long or poor cable, a loose connector, a bad USB adapter); try another cable "
                    "or port", damaged).format(url=url, n=damaged)


def _pause(seconds: float) -> None:
    time.sleep(seconds)


def _changed_runs(old: bytes, new: bytes, gap: int = OVERHEAD + 6) -> list[tuple[int, bytes]]:
    """Runs of differing bytes; runs closer than ``gap`` merge (a new frame costs more than a few bytes)."""
    runs: list[list[int]] = []
    for i in range(len(new)):
        if old[i] != new[i]:
            if runs and i - runs[-1][1] <= gap:
                runs[-1][1] = i + 1
            else:
                runs.append([i, i + 1])
    return [(a, bytes(new[a:b])) for a, b in runs]


def _template(fields: dict):
    from ...domain.start_templates import TemplateError
    try:
        return m.template_of(fields)[1]
    except TemplateError as exc:
        raise DeviceError(m.ErrorCode.BAD_REQUEST, _("the charger's start template does not fit: {exc}").format(
                exc=exc)) from None


def _u16(value: float | None, scale: float) -> int:
    if value is None or value <= 0:
        return 0
    raw = round(value * scale)
    if raw > 0xFFFF:
        raise ValueError(_("{value} does not fit the start request (at most {value2:g})").format(
                value=value, value2=0xFFFF / scale))
    return max(1, raw)
