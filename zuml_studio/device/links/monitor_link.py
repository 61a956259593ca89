"""Reading a monitor-only charger: a thread that takes bytes from a serial port (or reports
from a USB-HID device), runs them through the driver's decoder (detecting the driver first
for ``auto``) and hands samples over. No Qt: ``zuml monitor`` and the device panel share it.

Callbacks run on the reader thread: ``on_sample(Telemetry)``, ``on_status(text)`` (the
charger was recognised, the baud changed, …), ``on_extra(kind, item)`` for what a charger says
besides samples (the ZUML firmware's events and display lines: ``StreamDecoder.take_extras``) and
``on_closed(error_text | None)`` once at the end. ``good``/``bad`` count the decoder's records; ``driver`` is the driver in use
(None while detecting).
"""
from __future__ import annotations

import threading
import time
from typing import Callable

from ...streams.autodetect import BaudSweep, Detector
from ...streams.drivers import AUTO, DRIVERS, Driver
from ..errors import DeviceLinkError, why_lost
from ...protocol.messages import Telemetry
from ...i18n import _

READ_S = 0.05


class MonitorLink:
    def __init__(self, port: str, driver: str = AUTO, baud: int | None = None, *,
                 on_sample: Callable[[Telemetry], None] | None = None,
                 on_status: Callable[[str], None] | None = None,
                 on_closed: Callable[[str | None], None] | None = None,
                 on_extra: Callable[[str, object], None] | None = None,
                 give_up: bool = True):
        from .hid_link import PREFIX
        self.port = port
        self.hid = port.startswith(PREFIX)
        if driver != AUTO and driver not in DRIVERS:
            raise DeviceLinkError(_("unknown driver {driver!r}; drivers: auto, {drivers}").format(
                    driver=driver, drivers=', '.join(DRIVERS)))
        self.requested = driver
        self.baud = baud
        self.give_up = give_up              # auto: stop with a message after a sweep with no charger
        self._on_sample = on_sample or (lambda t: None)
        self._on_status = on_status or (lambda s: None)
        self._on_closed = on_closed or (lambda e: None)
        self._on_extra = on_extra or (lambda kind, item: None)
        self.driver: Driver | None = None if driver == AUTO else DRIVERS[driver]
        self._decoder = self.driver.decoder() if self.driver else None
        self._detector: Detector | None = None
        self.samples = 0
        self.error: str | None = None
        self._stop = threading.Event()
        self._dev = self._open()
        self._thread = threading.Thread(target=self._run, name=f"monitor {port}", daemon=True)

    @property
    def good(self) -> int:
        dec = self._decoder
        return dec.good if dec else 0

    @property
    def received(self) -> int:
        """Bytes read while recognising the charger (0 once a driver was given or found on HID)."""
        return self._detector.received if self._detector else 0

    @property
    def bad(self) -> int:
        dec = self._decoder
        if dec is not None:
            return dec.bad
        det = self._detector
        return min((d.bad for d in det.decoders.values()), default=0) if det else 0

    def _open(self):
        if self.hid:
            from .hid_link import HidPort, driver_for
            dev = HidPort(self.port)
            if self.driver is None:
                self.driver = driver_for(dev.vid, dev.pid)
                if self.driver is None:
                    dev.close()
                    raise DeviceLinkError(_("{port}: no driver for USB id {vid:04x}:{pid:04x}").format(
                            port=self.port, vid=dev.vid, pid=dev.pid))
                self._decoder = self.driver.decoder()
            elif self.driver.transport != "hid":
                dev.close()
                raise DeviceLinkError(_("{port}: {name} is a serial charger, not USB HID").format(
                        port=self.port, name=self.driver.name))
            return dev
        # A HID driver on a serial port reads a replayed report dump (``zuml replay``): the reports
        # come as a byte stream and nothing is polled.
        from .serial_port import open_serial
        if self.driver is None:
            self._detector = Detector()
            self._sweep = BaudSweep(first=self.baud)
            baud = self._sweep.baud
        else:
            baud = self.baud or self.driver.baud or 115200
        self.current_baud = baud
        dev = open_serial(self.port, baud)
        dev.timeout = READ_S
        return dev

    def start(self) -> "MonitorLink":
        self._thread.start()
        if self.driver is not None:
            self._on_status(f"monitoring {self.driver.title}")
        return self

    def close(self, wait_s: float = 5.0) -> None:
        self._stop.set()
        if self._thread.is_alive() and self._thread is not threading.current_thread():
            self._thread.join(wait_s)

    def _run(self) -> None:
        error = None
        try:
            if self.hid:
                self._run_hid()
            else:
                self._run_serial()
        except DeviceLinkError as exc:
            error = str(exc)
        except Exception as exc:    # noqa: BLE001 - a lost port ends the link with a message, never a crash
            error = f"{self.port}: {exc}"
        finally:
            try:
                self._dev.close()
            except Exception:       # noqa: BLE001 - closing: whatever a dying port raises, it is closed
                pass
        self.error = error
        self._on_closed(error)

    def _emit(self, samples: list[Telemetry]) -> None:
        for s in samples:
            self.samples += 1
            self._on_sample(s)
        for kind, item in self._decoder.take_extras():
            self._on_extra(kind, item)

    def _run_serial(self) -> None:
        dev = self._dev
        while not self._stop.is_set():
            try:
                data = dev.read(max(1, dev.in_waiting))
            except Exception as exc:    # noqa: BLE001 - pyserial raises several types for a lost port
                raise DeviceLinkError(_("{url}: the connection was lost ({why_lost})").format(   # the ZUML link's words
                        url=self.port, why_lost=why_lost(exc))) from None
            if self._decoder is not None:
                if data:
                    self._emit(self._decoder.feed(data))
                continue
            det = self._detector
            samples = det.feed(data) if data else []
            if det.winner is not None:
                self.driver = DRIVERS[det.winner]
                self._decoder = det.decoders[det.winner]
                self._on_status(_("recognised {title} at {baud} baud").format(title=self.driver.title,
                                                                              baud=self.current_baud))
                self._emit(samples)
                continue
            if self._sweep.advance(time.monotonic(), data):
                self.current_baud = self._sweep.baud
                dev.baudrate = self.current_baud
                det.new_baud()
                self._on_status(_("listening at {baud} baud").format(baud=self.current_baud))
            elif self._sweep.done:
                message = self._sweep.message(self.port, det)
                if self.give_up:
                    raise DeviceLinkError(message)
                self._on_status(message)
                self._sweep = BaudSweep(self._sweep.bauds)
                dev.baudrate = self.current_baud = self._sweep.baud
                det.new_baud()

    def _run_hid(self) -> None:
        import importlib
        mod = importlib.import_module(f"{Driver.__module__.rpartition('.')[0]}.{self.driver.module}")   # streams/
        poll = getattr(mod, "POLL", None)
        if poll is None and hasattr(mod, "poll_request"):
            poll = mod.poll_request(0)
        period = getattr(mod, "POLL_S", 1.0)
        next_poll = 0.0
        while not self._stop.is_set():
            now = time.monotonic()
            if poll is not None and now >= next_poll:
                self._dev.write(poll)
                next_poll = now + period
            data = self._dev.read(0.1)
            if data:
                self._emit(self._decoder.feed(data.ljust(64, b"\x00")))

