"""The device panel's link to a charger: a QObject that owns the ``ChargerClient`` (and the
built-in virtual charger or the simulated iMAX B6, when that is what the user picked) and one
worker QThread.

Every blocking call (open + IDENTIFY, reads, writes, START, the passport…) runs on the
worker thread, one at a time in the order asked; its result or its error comes back to
the GUI thread as a signal and is handed to the callbacks given with the job. The GUI
thread never waits for the charger, except in ``shutdown``, which closes everything.

Telemetry and events arrive on the client's reader thread: they go straight to the
``on_telemetry``/``on_event`` callables given to the constructor, which must not touch
Qt (the panel's store into numpy buffers and the session CSV). A lost link comes back
as ``disconnected(reason)``.
"""
from __future__ import annotations

import atexit
import itertools
import logging
import threading
import weakref
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

from PySide6.QtCore import QObject, QThread, Signal, Slot

from ...device.zuml.client import ChargerClient, DeviceInfo
from ...device.errors import DeviceError, Disconnected
from ...device.links.ports import SIMULATED_B6
from ...device.install.isp_store import ProgrammerClient, programmer_of
from ...errors import ZumlError
from ...error_words import describe_error
from ...i18n import _

log = logging.getLogger(__name__)

DEFAULT_TELEMETRY_HZ = 10
VIRTUAL_MAX_BUSY = 0.5          # share of the virtual charger's 10 ms periods it may compute (GIL for the GUI)


@dataclass(frozen=True)
class VirtualSpec:
    """The built-in virtual charger to create: battery ``CHEM:MAH:CELLS``, speed, passport."""
    battery: str = "NiMh:2000:4"
    speed: float = 60.0
    passport: str = "match"
    eeprom_path: Path | None = None     # keeps the EEPROM across connections (None: erased each time)
    weak_cell_pct: float = 0.0          # one cell holds this % less capacity (0: none) ...
    weak_cell: int | None = None        # ... this one (1-based; None: the top one)
    cell_spread: tuple[float, float, float] | None = None   # ± % of capacity, resistance, start charge per cell
    seed: int = 1                       # the spread's draw

    def cells(self):
        """The unequal cells to build the battery with (`sim.cell_pack.CellSpec`), None for the
        battery's own; DeviceSetupError says why the cells asked for do not fit the battery."""
        if not self.weak_cell_pct and not self.cell_spread:
            return None
        from ...virtual.virtual_charger import BatterySpec, DeviceSetupError
        from ...sim.interpreter import StartError
        from ...sim.simulate import BatterySetup, pack_cells
        spec = BatterySpec.parse(self.battery)
        try:
            setup = BatterySetup(weak_cell_pct=self.weak_cell_pct, weak_cell=self.weak_cell,
                                 cell_spread=self.cell_spread, seed=self.seed)
            return pack_cells(setup, spec.capacity_mah, spec.cells, 0.0, spec.file_cells())
        except StartError as exc:
            raise DeviceSetupError(str(exc)) from None


@dataclass(frozen=True)
class Opened:
    """What a successful connect hands the GUI."""
    url: str
    info: DeviceInfo
    virtual: VirtualSpec | None
    telemetry_hz: int
    simulated_b6: bool = False          # the window's simulated iMAX B6: its front panel is drawn


class _Worker(QObject):
    """Lives on the worker thread; runs one job at a time."""
    done = Signal(int, object)
    failed = Signal(int, object)
    progress = Signal(int, str, int, int)

    @Slot(int, object)
    def run(self, job_id: int, fn) -> None:
        def progress(stage: str, done: int, total: int) -> None:
            self.progress.emit(job_id, stage, int(done), int(total))
        try:
            result = fn(progress)
        except BaseException as exc:            # every failure goes back to the GUI
            if not isinstance(exc, (ZumlError, ValueError, OSError)):   # a bug, not a failure to word
                log.exception("device job failed")
            self.failed.emit(job_id, exc)
        else:
            self.done.emit(job_id, result)


class DeviceConnection(QObject):
    connected = Signal(object)          # Opened
    connectFailed = Signal(str)         # the message for the user
    disconnected = Signal(str)          # "" when asked for, else why the link went away
    busyChanged = Signal(bool)          # jobs are in flight (or not)
    progress = Signal(str, int, int)    # stage, done, total of the running job
    _submit = Signal(int, object)
    _lost = Signal(object, object)      # client, error (from the reader thread)
    lcdChanged = Signal(str, str)       # the simulated B6's display (from its reader thread)

    def __init__(self, on_telemetry: Callable | None = None, on_event: Callable | None = None,
                 parent: QObject | None = None):
        super().__init__(parent)
        self._on_telemetry = on_telemetry
        self._on_event = on_event
        self.state = "disconnected"     # disconnected | connecting | connected | disconnecting
        self.opened: Opened | None = None
        self._res_lock = threading.RLock()
        self._client: ChargerClient | None = None
        self._device = None             # the built-in VirtualCharger
        self._stop_virtual: Callable[[], None] | None = None
        self._b6 = None                 # the simulated iMAX B6 (virtual.simulated_b6.SimulatedB6)
        self._jobs: dict[int, tuple[Callable | None, Callable | None]] = {}
        self._ids = itertools.count(1)
        self._closing = False
        self.last_error: BaseException | None = None
        self.warned: set[bytes] = set()     # records whose safety warnings the user accepted (asked once)

        self.thread = QThread()
        self.thread.setObjectName("device-worker")
        self._worker = _Worker()
        self._worker.moveToThread(self.thread)
        self._submit.connect(self._worker.run)
        self._worker.done.connect(self._job_done)
        self._worker.failed.connect(self._job_failed)
        self._worker.progress.connect(self._job_progress)
        self._lost.connect(self._link_lost)
        self.thread.start()
        _OPEN.add(self)
        # Collected without shutdown() (a window dropped unclosed): the thread and its worker must
        # outlive the connection until the thread has ended; Qt aborts the process when a running
        # QThread is destroyed. At exit too, whatever is left (weakref.finalize runs then).
        weakref.finalize(self, _end_worker_thread, self.thread, self._worker)

    # -- state --------------------------------------------------------------------------------
    def is_connected(self) -> bool:
        return self.state == "connected"

    @property
    def busy(self) -> bool:
        return bool(self._jobs)

    @property
    def client(self) -> ChargerClient | None:
        return self._client

    @property
    def virtual_device(self):
        """The built-in VirtualCharger while connected to it (tests look inside), else None."""
        return self._device

    # -- jobs ---------------------------------------------------------------------------------
    def submit(self, fn: Callable, on_done: Callable | None = None, on_error: Callable | None = None) -> int:
        """Run ``fn(progress)`` on the worker thread; ``on_done(result)`` or ``on_error(exc)``
        then run on the GUI thread. ``progress(stage, done, total)`` is emitted as ``progress``."""
        if self._closing:
            return 0
        job_id = next(self._ids)
        was_busy = self.busy
        self._jobs[job_id] = (on_done, on_error)
        if not was_busy:
            self.busyChanged.emit(True)
        self._submit.emit(job_id, fn)
        return job_id

    def call(self, fn: Callable, on_done: Callable | None = None, on_error: Callable | None = None) -> int:
        """``submit`` for a job that needs the client: ``fn(client, progress)``."""
        def job(progress):
            client = self._client
            if client is None:
                raise Disconnected(_("not connected to a charger"))
            return fn(client, progress)
        return self.submit(job, on_done, on_error)

    def _finish(self, job_id: int):
        callbacks = self._jobs.pop(job_id, (None, None))
        if not self._jobs:
            self.busyChanged.emit(False)
        return callbacks

    @Slot(int, object)
    def _job_done(self, job_id: int, result) -> None:
        on_done, _on_error = self._finish(job_id)
        if on_done is not None and not self._closing:
            on_done(result)

    @Slot(int, object)
    def _job_failed(self, job_id: int, exc) -> None:
        _on_done, on_error = self._finish(job_id)
        if self._closing:
            return
        if on_error is not None:
            on_error(exc)
        else:
            log.warning("device job failed: %s", exc)

    @Slot(int, str, int, int)
    def _job_progress(self, job_id: int, stage: str, done: int, total: int) -> None:
        if job_id in self._jobs:
            self.progress.emit(stage, done, total)

    # -- connect / disconnect -----------------------------------------------------------------
    def open(self, url: str, baud: int = 115200, virtual: VirtualSpec | None = None,
             telemetry_hz: int = DEFAULT_TELEMETRY_HZ, b6_eeprom: Path | None = None) -> bool:
        """Connect in the background: ``connected(Opened)`` or ``connectFailed(message)``.
        ``virtual``: create the built-in virtual charger first and connect to its port; ``url``
        SIMULATED_B6: start the simulated iMAX B6 on the EEPROM file ``b6_eeprom`` first."""
        if self.state != "disconnected" or self._closing:
            return False
        self.state = "connecting"

        def job(progress):
            return self._open(url, int(baud), virtual, int(telemetry_hz), b6_eeprom)

        self.submit(job, self._opened, self._open_failed)
        return True

    def _open(self, url: str, baud: int, virtual: VirtualSpec | None, hz: int, b6_eeprom: Path | None) -> Opened:
        device = stop = None
        simulated = url == SIMULATED_B6
        if simulated:
            from ...virtual.simulated_b6 import BAUD, SimulatedB6
            if b6_eeprom is None:
                raise ValueError(_("the simulated iMAX B6 needs a file for its EEPROM"))
            b6 = SimulatedB6(b6_eeprom, on_lcd=self.lcdChanged.emit)
            with self._res_lock:
                self._b6 = b6
            url, baud = b6.port, BAUD
        if virtual is not None:
            from ...virtual.transport import serve
            from ...virtual.virtual_charger import VirtualCharger
            from ...virtual.virtual_charger import DeviceSetupError
            cells = virtual.cells()
            try:
                device = VirtualCharger(virtual.battery, speed=virtual.speed, passport=virtual.passport,
                                        eeprom_path=virtual.eeprom_path, cells=cells)
            except DeviceSetupError:
                if virtual.eeprom_path is None:
                    raise
                # an EEPROM file that does not load (wrong size, unreadable): start erased, keep the file
                log.warning("the virtual charger's EEPROM file %s does not load; starting erased",
                            virtual.eeprom_path)
                device = VirtualCharger(virtual.battery, speed=virtual.speed, passport=virtual.passport, cells=cells)
            device.max_busy = VIRTUAL_MAX_BUSY
            url, stop = serve(device)
            with self._res_lock:
                self._device, self._stop_virtual = device, stop
        try:
            client = ProgrammerClient(url) if programmer_of(url) else ChargerClient(url, baud)
        except BaseException:
            self._drop_virtual()
            raise
        with self._res_lock:
            self._client = client
        if self._closing:
            raise Disconnected(_("closing"))
        if self._on_telemetry is not None:
            client.on_telemetry(self._on_telemetry)
        if self._on_event is not None:
            client.on_event(self._on_event)
        client.on_disconnect(lambda exc, c=client: self._lost.emit(c, exc))
        try:
            hz = client.set_telemetry_rate(max(1, min(50, hz)))
        except DeviceError:
            pass            # a charger that keeps its own rate is still a charger
        return Opened(url, client.info, virtual, hz, simulated)

    def _opened(self, opened: Opened) -> None:
        client = self._client
        if client is None or not client.connected:
            self._open_failed(Disconnected(_("{port}: the connection closed right after it opened").format(
                port=opened.url)))
            return
        self.warned.clear()                 # a new connection may be another charger: ask again
        self.state = "connected"
        self.opened = opened
        self.connected.emit(opened)

    def _open_failed(self, exc) -> None:
        self.state = "disconnected"
        self.opened = None
        self.last_error = exc              # the panel's "auto" falls back to monitor-only chargers on NotACharger
        self._release_async()
        self.connectFailed.emit(describe_error(exc, "connect"))

    def close(self) -> None:
        """Disconnect (the user asked): closes the client and any virtual charger off the GUI thread."""
        if self.state in ("disconnected", "disconnecting"):
            return
        self.state = "disconnecting"
        self.submit(lambda progress: self._release(), lambda _result: self._closed(""), lambda exc: self._closed(""))

    def _closed(self, reason: str) -> None:
        was = self.state
        self.state = "disconnected"
        self.opened = None
        if was != "disconnected":
            self.disconnected.emit(reason)

    @Slot(object, object)
    def _link_lost(self, client, exc) -> None:
        if client is not self._client or self._closing:
            return
        if self.state not in ("connected", "connecting"):
            return
        if self.state == "connecting":
            return          # the connect job itself fails (or _opened sees the dead client)
        self._release_async()
        self._closed(describe_error(exc, "link"))

    def _release_async(self) -> None:
        self.submit(lambda progress: self._release())

    def _release(self) -> None:
        """Close the client and the virtual charger (worker thread, or any thread at shutdown)."""
        with self._res_lock:
            client, self._client = self._client, None
        if client is not None:
            try:
                client.close()
            except Exception:
                log.exception("closing the charger client failed")
        self._drop_virtual()

    def _drop_virtual(self) -> None:
        with self._res_lock:
            device, stop, b6 = self._device, self._stop_virtual, self._b6
            self._device = self._stop_virtual = self._b6 = None
        if b6 is not None:
            b6.close()
        if stop is not None:
            try:
                stop()
            except Exception:
                log.exception("stopping the virtual charger's port failed")
        if device is not None:
            device.close()

    # -- the virtual charger ------------------------------------------------------------------
    def set_speed(self, speed: float) -> bool:
        """Change the built-in virtual charger's speed at once (thread-safe on the device)."""
        device = self._device
        if device is None:
            return False
        try:
            device.set_speed(speed)
        except ValueError:
            return False
        return True

    @property
    def simulated_b6(self):
        """The simulated iMAX B6 while connected to it (its buttons, its display), else None."""
        return self._b6

    def hang_up_virtual(self) -> None:
        """Stop the built-in virtual charger's port as if its cable were pulled (tests, demos)."""
        with self._res_lock:
            stop, self._stop_virtual = self._stop_virtual, None
        if stop is not None:
            stop()

    # -- shutdown -------------------------------------------------------------------------------
    def shutdown(self, wait_ms: int = 10_000) -> None:
        """Close the client and the virtual charger and end the worker thread. Blocks (briefly)."""
        if self._closing:
            return
        self._closing = True
        with self._res_lock:
            client = self._client
        if client is not None:
            client.close()          # a job waiting for the charger fails at once
        self.thread.quit()
        if not self.thread.wait(wait_ms):
            log.warning("the device worker thread did not end in %d ms", wait_ms)
        self._release()             # whatever a job created while we waited
        self._jobs.clear()
        was = self.state
        self.state = "disconnected"
        self.opened = None
        if was != "disconnected":
            self.disconnected.emit("")


_OPEN: "weakref.WeakSet[DeviceConnection]" = weakref.WeakSet()
_STRANDED: list = []      # threads that did not end in time: kept, never destroyed while they run


def _end_worker_thread(thread: QThread, worker: QObject) -> None:
    try:
        thread.quit()
        if not thread.wait(3000):
            log.warning("a device worker thread did not end in 3 s; it is left to the process's end")
            _STRANDED.append((thread, worker))
    except RuntimeError:        # its Qt object is gone already (the application was torn down)
        pass


@atexit.register
def _shutdown_all() -> None:
    """A panel the window forgot to shut down: never leave a QThread running at exit."""
    for connection in list(_OPEN):
        try:
            connection.shutdown(wait_ms=3000)
        except RuntimeError:        # its Qt object is gone already
            pass
