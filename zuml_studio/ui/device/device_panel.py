"""The Device panel: a charger (or the built-in virtual one) on a serial line.

It composes its parts, each a widget in its own module with the state it owns: above, the
connection bar (``connection_bar``: port, driver, Connect, Replay, the virtual charger's
battery); left, two narrow columns: what is on the charger (``charger_slots``: its macros,
Compile & Flash, Backup/Restore) and the run (``run_controls``: task parameters, Start/Stop;
``passport_view``: the battery's passport); right, the live view (``live_view``). Below: the
message line and the session CSV. This module does what crosses the parts: talking to the
charger, and which control is enabled when.

A port's driver is "Auto" by default: a ZUML charger (it answers IDENTIFY), else a
monitor-only charger recognised from what it sends (``device.drivers``). Monitor-only
chargers plot and log like ours; Flash and Start are disabled with the reason.

Nothing here waits for the charger: every request runs on the connection's worker thread
(``connection.py``) and comes back as a signal; telemetry goes from the reader thread into
numpy buffers and the session CSV without Qt (``live_plot.LiveSeries``, ``session_log``)
and is drawn by a ~30 Hz timer.
"""
from __future__ import annotations

import logging
from pathlib import Path
from typing import Callable

from PySide6.QtCore import Qt, QTimer, Signal
from PySide6.QtGui import QKeySequence, QShortcut
from PySide6.QtWidgets import (QFileDialog, QFrame, QHBoxLayout, QLabel, QScrollArea, QSizePolicy, QSplitter,
                               QVBoxLayout, QWidget)

from ...device import messages as msg
from ...device.drivers import AUTO, DRIVERS, MONITOR_ONLY_REASON
from ...device.errors import CommitUncertain, CommitUnverified, DeviceError, ImageTooLarge, NotACharger
from ...device.flashing import merge_record
from ...device.passport import fitness_warnings
from ...sim.start_check import start_warnings
from ...device.ports import VIRTUAL
from ...lang.eeprom import Slot, slots
from ...safety import image_problems, record_problems
from ..timefmt import hmmss
from .charger_monitor import ChargerMonitor
from .charger_slots import FLASH_TIP, ChargerSlots
from .confirm_dialogs import confirm_restore, documents_folder, restore_text
from .connection import DeviceConnection, Opened, VirtualSpec, describe_error
from .connection_bar import MATCH, ConnectionBar
from .device_style import colour, ElidedLabel, vline
from .live_plot import LiveSeries
from .live_view import LiveView
from .passport_view import PassportView
from .run_controls import START_TIP, RunControls
from ...device.session_log import IDLE_LOG_S, SessionLog, display_path, session_path
from .unsafe_dialog import confirm_unsafe

log = logging.getLogger(__name__)

READINGS_MS = 250
PASSPORT_POLL_MS = 5000
VIRTUAL_EEPROM = "virtual-charger-eeprom.bin"
KEEP_RUNS = 10          # earlier runs kept for the run chooser (the session CSV keeps them all)


class _Unsafe:
    """What a job hands back instead of writing: the safety check's problems, for the dialog."""

    def __init__(self, problems: list[str]):
        self.problems = problems

    def summary(self) -> str:
        return "the safety check refused it:\n" + "\n".join(f"• {line}" for line in self.problems)




class ControlsScroll(QScrollArea):
    """The controls' scroll area, preferring the width its columns want (QScrollArea caps its
    size hint at 36 lines of text, which would squeeze the fields), and scrolling vertically
    only when the dock is too low."""

    def sizeHint(self):  # noqa: N802
        hint = super().sizeHint()
        widget = self.widget()
        if widget is not None:
            hint.setWidth(widget.sizeHint().width() + self.verticalScrollBar().sizeHint().width()
                          + 2 * self.frameWidth())
        return hint


class DevicePanel(QWidget):
    connectedChanged = Signal(bool)
    flashFinished = Signal(bool, str)
    telemetryReceived = Signal(int)         # points plotted so far; at most at the redraw rate
    statusMessage = Signal(str)
    startFinished = Signal(bool, str)       # START done (or refused: the reasons)
    operationFinished = Signal(str, bool, str)   # "backup" | "restore" | "stop" | "passport" | "slots", ok, message
    phaseActivated = Signal(int)            # FAZE byte offset of a double-clicked band (the editor may show it)

    def __init__(self, get_record: Callable[[], tuple[bytes, str] | None], session_dir: Path,
                 parent: QWidget | None = None, *, port_lister: Callable | None = None):
        super().__init__(parent)
        self.setObjectName("devicePanel")
        self._get_record = get_record
        self.session_dir = Path(session_dir)
        self.series = LiveSeries()
        self._log: SessionLog | None = None
        self._log_error_said = False
        self._unsettled: tuple[str, CommitUncertain | CommitUnverified] | None = None   # (what, error)
        self.session_file: Path | None = None
        self._image: bytes | None = None
        self._slots: list[Slot] = []
        self._info = None
        self._flashed_slot: int | None = None
        self._run_name = ""
        self._running = False              # a macro runs (started here, or the newest frame says so)
        self._start_frames = 0
        self.runs: list[tuple[str, LiveSeries]] = []   # earlier runs, oldest first
        self._before_run: tuple[str, LiveSeries] | None = None   # the run a pending START replaced
        self._shut = False
        self._finished_seen = 0
        self._auto_fallback: tuple[str, int] | None = None   # (port, baud) to watch if no ZUML charger answers
        self._stop_replay = None                             # stops the in-process replay behind the port

        self.monitor = ChargerMonitor(self._telemetry_rt, self)
        self.monitor.status.connect(self._on_monitor_status)
        self.monitor.closed.connect(self._on_monitor_closed)

        self._build(port_lister)
        self.connection = DeviceConnection(self._telemetry_rt, self._event_rt, self)
        self.connection.connected.connect(self._on_connected)
        self.connection.connectFailed.connect(self._on_connect_failed)
        self.connection.disconnected.connect(self._on_disconnected)
        self.connection.progress.connect(self._on_progress)
        self.connection.busyChanged.connect(lambda _: self._update_enabled())
        self._wire()
        self._set_state_disconnected()
        self.show_message("Pick a port (the built-in virtual charger needs no hardware) and Connect.", "info")

    # ================================================================ building
    def _build(self, port_lister) -> None:
        self.bar = ConnectionBar(port_lister)
        self.charger = ChargerSlots()
        self.run = RunControls()
        self.passport = PassportView()
        self.live = LiveView(self.series)
        # The parts' controls, under the names the panel's callers and tests know.
        for part, names in ((self.bar, ("ports", "driver_combo", "connect_button", "replay_button", "v_chem",
                                        "v_mah", "v_cells", "v_passport", "v_speed", "rate", "virtual_box",
                                        "info_label")),
                            (self.charger, ("table", "free_label", "flash_slot", "flash_button", "progress",
                                            "result_label", "backup_button", "restore_button", "reload_button")),
                            (self.run, ("run_slot", "task", "capacity", "current", "series_spin", "voltage",
                                        "repetitions", "sensor", "start_button", "stop_button", "run_label")),
                            (self.passport, ("pp_refresh", "pp_labels")),
                            (self.live, ("plot", "readings", "follow", "follow_minutes", "all_button",
                                         "clear_button"))):
            for name in names:
                setattr(self, name, getattr(part, name))

        col_b = QWidget()
        col_b.setObjectName("runColumn")
        b = QVBoxLayout(col_b)
        b.setContentsMargins(0, 0, 0, 0)
        b.setSpacing(3)
        b.addWidget(self.run)
        b.addWidget(self.passport)
        b.addStretch(1)
        columns = QWidget()
        cols = QHBoxLayout(columns)
        cols.setContentsMargins(0, 0, 4, 0)
        cols.setSpacing(10)
        cols.addWidget(self.charger, 10)
        cols.addWidget(vline())
        cols.addWidget(col_b, 11)
        self.controls_scroll = ControlsScroll()
        self.controls_scroll.setObjectName("deviceControls")
        self.controls_scroll.setWidget(columns)
        self.controls_scroll.setWidgetResizable(True)
        self.controls_scroll.setFrameShape(QFrame.Shape.NoFrame)
        self.controls_scroll.setHorizontalScrollBarPolicy(Qt.ScrollBarPolicy.ScrollBarAlwaysOff)
        self.charger.setMinimumWidth(215)
        col_b.setMinimumWidth(265)
        self.controls_scroll.setMinimumWidth(columns.minimumSizeHint().width() + 14)

        self.splitter = QSplitter(Qt.Orientation.Horizontal)
        self.splitter.setObjectName("deviceSplitter")
        self.splitter.setChildrenCollapsible(False)
        self.splitter.addWidget(self.controls_scroll)
        self.splitter.addWidget(self.live)
        self.splitter.setStretchFactor(0, 0)
        self.splitter.setStretchFactor(1, 1)

        self.message = QLabel("")
        self.message.setObjectName("deviceMessage")
        self.message.setWordWrap(True)
        self.message.setTextInteractionFlags(Qt.TextInteractionFlag.TextSelectableByMouse)
        self.message.setSizePolicy(QSizePolicy.Policy.Expanding, QSizePolicy.Policy.Preferred)
        self.session_label = ElidedLabel("", mode=Qt.TextElideMode.ElideMiddle)
        self.session_label.setObjectName("sessionLabel")
        self.session_label.setStyleSheet(f"color:{colour(self, 'info')};")
        self.session_label.setAlignment(Qt.AlignmentFlag.AlignRight | Qt.AlignmentFlag.AlignVCenter)
        bottom = QHBoxLayout()
        bottom.setContentsMargins(0, 0, 0, 0)
        bottom.setSpacing(12)
        bottom.addWidget(self.message, 3)
        bottom.addWidget(self.session_label, 2)

        layout = QVBoxLayout(self)
        layout.setContentsMargins(6, 4, 6, 3)
        layout.setSpacing(3)
        layout.addWidget(self.bar)
        layout.addWidget(self.splitter, 1)
        layout.addLayout(bottom)

        self._readings_timer = QTimer(self, interval=READINGS_MS)
        self._readings_timer.timeout.connect(self._update_readings)
        self._passport_timer = QTimer(self, interval=PASSPORT_POLL_MS)
        self._passport_timer.timeout.connect(self._poll_passport)
        self.flash_shortcut = QShortcut(QKeySequence("Ctrl+Shift+F"), self)
        self.flash_shortcut.setContext(Qt.ShortcutContext.WidgetWithChildrenShortcut)

    def _wire(self) -> None:
        self.connect_button.clicked.connect(self._connect_clicked)
        self.replay_button.clicked.connect(self._replay_clicked)
        self.ports.changed.connect(self._port_changed)
        self.flash_button.clicked.connect(self.flash)
        self.flash_shortcut.activated.connect(self.flash)
        self.backup_button.clicked.connect(self._backup_clicked)
        self.restore_button.clicked.connect(self._restore_clicked)
        self.reload_button.clicked.connect(self.refresh_slots)
        self.start_button.clicked.connect(lambda: self.start())
        self.stop_button.clicked.connect(self.stop)
        self.pp_refresh.clicked.connect(self.refresh_passport)
        self.v_speed.valueChanged.connect(self._speed_changed)
        self.rate.valueChanged.connect(self._rate_changed)
        self.v_mah.valueChanged.connect(self.capacity.setValue)
        self.v_cells.valueChanged.connect(self.series_spin.setValue)
        self.table.itemSelectionChanged.connect(self._table_selected)
        self.clear_button.clicked.connect(self.clear_plot)
        self.live.runChosen.connect(self._run_chosen)
        self.v_chem.currentIndexChanged.connect(lambda _: self._battery_choice_changed())
        self.plot.pointsAdded.connect(self.telemetryReceived)
        self.plot.phaseActivated.connect(self.phaseActivated)


    # ================================================================ public API
    def is_connected(self) -> bool:
        return self.connection.is_connected()

    def connect_to(self, url_or_virtual: str | None = None, driver: str | None = None) -> bool:
        """Connect to ``"virtual"`` (the built-in virtual charger), a port path or a URL; None: what
        the chooser shows. ``driver``: "auto", "zuml" or a monitor-only driver's name (None: the
        driver chooser's). Returns at once; ``connectedChanged(True)`` or a message follows."""
        if self._shut:
            return False
        if url_or_virtual is not None:
            self.ports.set_target(url_or_virtual)
        if driver is not None:
            self.driver_combo.setCurrentIndex(max(0, self.driver_combo.findData(driver)))
        target = self.ports.target()
        if self.connection.state != "disconnected" or self.is_monitoring():
            self.show_message("Already connected (or connecting): Disconnect first.", "warn")
            return False
        driver = self.driver_combo.currentData() or AUTO
        self._auto_fallback = None
        if target.startswith("hid:"):
            # ZUML chargers are serial: a HID charger is watched with its chosen driver, or by its USB ids
            return self._watch(target, driver if driver in DRIVERS else AUTO)
        if target != VIRTUAL and driver in DRIVERS:
            return self._watch(target, driver)
        if target != VIRTUAL and driver == AUTO:
            self._auto_fallback = (target, self.ports.baudrate())
        virtual = None
        if target == VIRTUAL:
            virtual = VirtualSpec(self.virtual_battery(), float(self.v_speed.value()),
                                  self.v_passport.currentData() or MATCH, self.virtual_eeprom_path())
        self._open_session_log()
        ok = self.connection.open(target, self.ports.baudrate(), virtual, self.rate.value())
        if not ok:
            self._close_session_log(discard_empty=True)
        else:
            what = f"the built-in virtual charger ({virtual.battery}, ×{virtual.speed:g})" if virtual else target
            self.show_message(f"Connecting to {what}…", "info")
            self._update_enabled()
        return ok

    def disconnect(self, *args, **kw):  # noqa: A003 - the panel's verb
        """Close the link (and the built-in virtual charger). The plot and the session CSV stay.
        (With arguments it is QObject.disconnect, for signal connections.)"""
        if args or kw:
            return super().disconnect(*args, **kw)
        if self.is_monitoring():
            self.monitor.close()
            return
        if self.connection.state in ("connected", "connecting"):
            self.connection.close()
            self.show_message("Disconnecting…", "info")
            self._update_enabled()

    def flash(self, force: bool = False) -> None:
        """Compile & Flash: the editor's record into the charger (same name replaced, else appended,
        or the slot chosen), written, verified; ``flashFinished(ok, message)``. The safety check
        runs first; what it refuses is written only after the user confirms (or with ``force``)."""
        if not self.is_connected():
            self._flash_done(False, "Connect to a charger first, then Compile & Flash.")
            return
        got = self._get_record()
        if got is None:
            self._flash_done(False, "The macro has errors: fix them (see Problems), then Compile & Flash.")
            return
        record, name = bytes(got[0]), got[1]
        slot = self.flash_slot.currentData()
        self.result_label.setText("")
        self.show_message(f"Flashing {name}…", "info")
        self.charger.progress_busy()

        def job(client, progress):
            if not force:
                problems = record_problems(record, client.passport_if_any(), charger_max_a=client.info.max_charge_a)
                if problems:
                    return _Unsafe(problems)
            current = client.read_image(progress)
            merged = merge_record(current, record, slot)
            result = client.write_image(merged.image, progress, current=current)
            return merged, result

        self.connection.call(job, self._flashed, self._flash_failed)
        self._update_enabled()

    def start(self, slot: int | None = None, force: bool = False) -> None:
        """START the macro in ``slot`` (default: the Slot field, which follows the last flash) with
        the task parameters; the safety check (chemistry limits, the battery's passport) runs here
        first, and what it refuses starts only after the user confirms (or with ``force``; the
        charger still has its own check). ``startFinished``."""
        if not self.is_connected():
            self._start_done(False, "Connect to a charger first.")
            return
        if slot is None:
            slot = self.run_slot.currentData()
        if slot is None or not 0 <= slot < len(self._slots):
            self._start_done(False, "There is no macro on the charger to start: Compile & Flash one first.")
            return
        if self.is_running():
            self._start_done(False, f"{self._run_name or 'A macro'} is running: Stop it first, then Start.")
            return
        params = self.start_params()
        record = self._slots[slot].record
        name = self._slots[slot].name
        charger_max = self._info.max_charge_a if self._info else None

        def job(client, progress):
            from ...lang.record import DecodeError
            from ...sim.interpreter import StartParams
            passport = client.passport_if_any()
            if not force:
                try:
                    found = record_problems(record, passport, StartParams(**params), charger_max_a=charger_max)
                except DecodeError:     # a record that does not decode: the charger refuses it
                    found = []
                if found:
                    return ("refused", found, passport, [])
            started = client.start(slot, params["task"], params["repetitions"], params["capacity_mah"],
                                   params["current_a"], params["voltage_v"], params["series"], params["sensor"])
            # What the charger does not refuse but the user should know: the battery's error count,
            # and values entered at start that the lint could not check (seed 001's -dV rates).
            warnings = (fitness_warnings(passport) if passport is not None else []) + \
                start_warnings(record, StartParams(**params))
            return ("started", started, passport, warnings)

        self.show_message(f"Starting {name} (slot {slot})…", "info")
        self._new_run()
        self.connection.call(job, lambda r: self._started(r, slot, params), self._start_failed)
        self._update_enabled()

    def stop(self) -> None:
        if not self.is_connected():
            return

        def done(state):
            self.show_message(f"Stopped ({state}).", "info")
            self.operationFinished.emit("stop", True, state)

        # STOP goes before anything asked after it: a Start from now on finds the charger stopped
        # (should STOP fail, the next running frame says so again).
        self._running = False
        self._start_frames = self.series.frames
        self._update_enabled()
        self.connection.call(lambda client, progress: client.stop(), done,
                             lambda exc: self._op_failed("stop", exc))

    def backup(self, path: str | Path) -> None:
        """Save the charger's whole EEPROM to ``path``; ``operationFinished("backup", ok, message)``."""
        if not self.is_connected():
            self._op_failed("backup", "Connect to a charger first.")
            return
        path = Path(path)

        def job(client, progress):
            image = client.read_image(progress)
            path.write_bytes(image)
            return image

        def done(image):
            self._show_image(image)
            try:
                count = f"{len(slots(image))} macro(s)"
            except Exception:   # noqa: BLE001
                count = "a broken record list"
            text = f"Saved the charger's EEPROM ({len(image)} bytes, {count}) to {path}."
            self._progress_done()
            self.show_message(text, "ok")
            self.operationFinished.emit("backup", True, text)

        self.charger.progress_busy()
        self.connection.call(job, done, lambda exc: self._op_failed("backup", exc))

    def restore(self, path: str | Path, force: bool = False) -> None:
        """Write a saved image back (checked first, then written and verified); records the safety
        check refuses are written only after the user confirms (or with ``force``)."""
        if not self.is_connected():
            self._op_failed("restore", "Connect to a charger first.")
            return
        path = Path(path)

        def job(client, progress):
            from ...device.client import check_image
            image = path.read_bytes()
            check_image(image)
            if len(image) > client.info.eeprom_size:
                raise ImageTooLarge(len(image), client.info.eeprom_size)
            if not force:
                problems = image_problems(image, client.passport_if_any(), charger_max_a=client.info.max_charge_a)
                if problems:
                    return _Unsafe(problems)
            result = client.write_image(image, progress, validate=False)
            return image + b"\xff" * (client.info.eeprom_size - len(image)), result

        def done(answer):
            if isinstance(answer, _Unsafe):
                self._progress_done()
                if confirm_unsafe(self, "Restore", answer.problems):
                    self.restore(path, force=True)
                else:
                    self._op_failed("restore", "Not restored: " + answer.summary())
                return
            image, result = answer
            self._show_image(image)
            text = f"Restored {path.name}: {result.changed} bytes changed, verified."
            self._progress_done()
            self.show_message(text, "ok")
            self.operationFinished.emit("restore", True, text)

        self.charger.progress_busy()
        self.connection.call(job, done, lambda exc: self._op_failed("restore", exc))

    def refresh_slots(self) -> None:
        if not self.is_connected():
            return

        def done(image):
            self._show_image(image)
            self._settle(image)
            self.operationFinished.emit("slots", True, "")

        self.connection.call(lambda client, progress: client.read_image(), done,
                             lambda exc: self._op_failed("slots", exc))

    def refresh_passport(self) -> None:
        if not self.is_connected():
            return

        def job(client, progress):
            try:
                return client.passport_read()
            except DeviceError as exc:
                if exc.code == msg.ErrorCode.NO_PASSPORT:
                    return None
                raise

        def done(passport):
            self._show_passport(passport)
            self.operationFinished.emit("passport", True, "")

        def failed(exc):
            self._show_passport(None, describe_error(exc))
            self.operationFinished.emit("passport", False, describe_error(exc))

        self.connection.call(job, done, failed)

    def clear_plot(self) -> None:
        self.plot.clear()
        self.telemetryReceived.emit(0)

    def shutdown(self) -> None:
        """Stop every thread, close the client and the built-in virtual charger, close the CSV.
        The main window calls this when it closes; idempotent."""
        if self._shut:
            return
        self._shut = True
        self.plot.stop()
        self._readings_timer.stop()
        self._passport_timer.stop()
        self.ports.shutdown()
        self.connection.shutdown()
        self.monitor.closed.disconnect(self._on_monitor_closed)
        self.monitor.close()
        self.monitor.link = None
        self._stop_replay_link()
        self._close_session_log()

    # -- what tests and the main window may read --------------------------------------------------

    # -- what tests and the main window may read --------------------------------------------------
    def start_params(self) -> dict:
        return self.run.start_params()

    def set_start_params(self, **values) -> None:
        """Set the values entered at start (``RunControls.set_start_params``'s names)."""
        self.run.set_start_params(**values)


    def slot_names(self) -> list[str]:
        return [s.name for s in self._slots]

    def message_text(self) -> str:
        return self.message.text()

    def virtual_eeprom_path(self) -> Path:
        """Where the built-in virtual charger keeps its EEPROM: like a real charger, it still
        holds its macros after a disconnect (and the next time ZUML Studio starts)."""
        return self.session_dir / VIRTUAL_EEPROM

    def add_named_batteries(self) -> None:
        """Offer the saved fitted batteries (docs/fit.md) in the virtual battery box."""
        self.bar.add_named_batteries()

    def virtual_battery(self) -> str:
        """``CHEM:MAH:CELLS`` for the built-in virtual charger (``ConnectionBar.virtual_battery``)."""
        got = self._get_record()
        return self.bar.virtual_battery(got[0] if got is not None else None, self.capacity.value(),
                                        self.series_spin.value())

    def macro_changed(self, record: bytes | None) -> None:
        """The editor's macro compiled to ``record``: show what a virtual battery "from the
        macro" would be (the main window calls this; it must not ask for the record again)."""
        if self.connection.state == "disconnected":
            self.bar.virtual_battery(record, self.capacity.value(), self.series_spin.value())

    def _battery_choice_changed(self) -> None:
        if self.connection.state == "disconnected":
            self.virtual_battery()
        self._update_enabled()

    def run_name(self) -> str:
        """The macro started last ("" before the first start)."""
        return self._run_name

    def is_running(self) -> bool:
        """A macro runs on the connected charger (just started here, or as its newest frame says)."""
        return self._running and self.is_connected()

    def stop_and_wait(self, msecs: int = 5000) -> bool:
        """Send STOP and wait for the answer (closing during a run); True if the charger stopped."""
        if not self.is_connected():
            return False
        from PySide6.QtCore import QEventLoop
        loop = QEventLoop()
        answer = []

        def finished(op, ok, _text):
            if op == "stop":
                answer.append(ok)
                loop.quit()
        self.operationFinished.connect(finished)
        QTimer.singleShot(msecs, loop.quit)
        self.stop()
        if not answer:
            loop.exec()
        self.operationFinished.disconnect(finished)
        return bool(answer and answer[0])

    # ================================================================ runs
    def _new_run(self) -> None:
        """A START makes a new session of the plot (its axis from 0); the run before it is kept."""
        if len(self.series) == 0 and not self.series.events:
            return
        self._before_run = (self._run_name, self.series)
        self.runs = (self.runs + [self._before_run])[-KEEP_RUNS:]
        self.series = LiveSeries()
        self._finished_seen = 0
        self._start_frames = 0
        self.plot.set_series(self.series)
        self._show_runs()

    def _undo_new_run(self) -> None:
        """START did not start: show the run before it again, as the current one."""
        before, self._before_run = self._before_run, None
        if before is None or len(self.series):
            return
        self.runs = [r for r in self.runs if r is not before]
        self._run_name, self.series = before
        self._finished_seen = len(self.series.events)
        self._start_frames = self.series.frames
        self.plot.set_series(self.series)
        self._show_runs()

    def _show_runs(self) -> None:
        labels = [f"Run {i + 1}: {name or '?'}" for i, (name, _) in enumerate(self.runs)]
        labels.append(f"Run {len(self.runs) + 1}: {self._run_name or '?'} (now)")
        self.live.set_runs(labels)

    def _run_chosen(self, index: int) -> None:
        series = self.runs[index][1] if index < len(self.runs) else self.series
        if series is not self.plot.series:
            self.plot.set_series(series)
            if series is not self.series:
                self.follow.setChecked(False)
                self.plot.show_all()


    # ================================================================ reader thread (no Qt)
    def _telemetry_rt(self, tel) -> None:
        self.series.add_telemetry(tel)
        logger = self._log
        if logger is not None:
            logger.add_telemetry(tel)

    def _event_rt(self, ev) -> None:
        self.series.add_event(ev)
        logger = self._log
        if logger is not None:
            logger.add_event(ev)

    # ================================================================ connection results
    def _connect_clicked(self) -> None:
        if self.connection.state in ("connected", "connecting") or self.is_monitoring():
            self.disconnect()
        else:
            self.connect_to(None)

    def _on_connected(self, opened: Opened) -> None:
        self._info = info = opened.info
        where = "built-in virtual charger" if opened.virtual else opened.url
        limits = (f"charge {info.max_charge_a:g} A/{info.max_charge_w:g} W, discharge "
                  f"{info.max_discharge_a:g} A/{info.max_discharge_w:g} W, {info.max_v:g} V max")
        self.info_label.set_full_text(f"{info.model} · {info.firmware} · EEPROM {info.eeprom_size} bytes · {limits}")
        self.info_label.setToolTip(f"{where}: {info.model}, firmware {info.firmware}, protocol {info.protocol}\n"
                                   f"EEPROM {info.eeprom_size} bytes; {limits}\n"
                                   f"{opened.telemetry_hz} telemetry frames/s")
        self._set_state_connected()
        self.plot.set_placeholder("connected: Start a macro to plot its run")
        self.show_message(f"Connected to {where}: {info.model}, firmware {info.firmware}.", "ok")
        self.refresh_slots()
        self.refresh_passport()
        self.connectedChanged.emit(True)

    def _on_connect_failed(self, message: str) -> None:
        fallback, self._auto_fallback = self._auto_fallback, None
        if fallback is not None and isinstance(self.connection.last_error, NotACharger):
            self._close_session_log(discard_empty=True)
            self._set_state_disconnected()
            if self._watch(fallback[0], AUTO, fallback[1]):
                self.show_message(f"No ZUML charger answered on {fallback[0]}: listening for a monitor-only "
                                  f"charger ({', '.join(DRIVERS)}) instead…", "info")
            return
        self._close_session_log(discard_empty=True)
        self._set_state_disconnected()
        self.show_message(message, "error")
        self.connectedChanged.emit(False)

    def _on_disconnected(self, reason: str) -> None:
        self._close_session_log()
        self._set_state_disconnected()
        kept = " The plot and the session CSV are kept."
        if reason:
            self.show_message(reason + kept, "error")
        else:
            self.show_message("Disconnected." + kept if self.plot.points else "Disconnected.", "info")
        self.plot.refresh()
        self.connectedChanged.emit(False)

    def _on_progress(self, stage: str, done: int, total: int) -> None:
        self.charger.on_progress(stage, done, total)

    def _progress_done(self) -> None:
        self.charger.progress_done()


    def _flashed(self, answer) -> None:
        if isinstance(answer, _Unsafe):
            self._progress_done()
            if confirm_unsafe(self, "Flash", answer.problems):
                self.flash(force=True)
            else:
                self._flash_done(False, "Not flashed: " + answer.summary())
            return
        merged, result = answer
        self.charger.progress_complete(f"flashed {merged.name}: {merged.size} bytes, verified")
        self._show_image(merged.image)
        self._flashed_slot = merged.index
        index = self.run_slot.findData(merged.index)
        if index >= 0:
            self.run_slot.setCurrentIndex(index)
        if result.changed:
            text = (f"Flashed {merged.name} into slot {merged.index}: {merged.size} bytes, "
                    f"{result.changed} bytes changed, verified")
        else:
            text = f"{merged.name} is already in slot {merged.index} ({merged.size} bytes): nothing to write"
        if merged.replaced is not None and merged.replaced != merged.name:
            text += f" (it replaced {merged.replaced})"
        self._flash_done(True, text + ".")

    def _flash_failed(self, exc) -> None:
        self._progress_done()
        self._note_unsettled("flash", exc)
        self._flash_done(False, describe_error(exc, "flash"))
        if self.is_connected():
            self.refresh_slots()

    def _flash_done(self, ok: bool, text: str) -> None:
        self.charger.set_result(ok, text)
        self.show_message(text, "ok" if ok else "error")
        self._update_enabled()
        self.flashFinished.emit(ok, text)

    # -- start --------------------------------------------------------------------------------
    def _started(self, answer, slot: int, params: dict) -> None:
        kind, value, passport, warnings = answer
        self._show_passport(passport)
        name = self._slots[slot].name if slot < len(self._slots) else "?"
        if kind == "refused":
            # A battery unfit for use (CRIT) is refused by the charger whatever the user says: no override.
            unfit = passport is not None and passport.crit
            self._undo_new_run()
            if not unfit and confirm_unsafe(self, "Start", value):
                self.start(slot, force=True)
                return
            text = (f"Not started: the safety check forbids {name}:\n"
                    + "\n".join(f"• {line}" for line in value))
            self._start_done(False, text)
            return
        self._before_run = None
        self._run_name = value
        self._running = True
        self._start_frames = self.series.frames
        self._show_runs()
        self.plot.set_series_count(params["series"] or 1)
        self.live.follow_again()
        self._start_done(True, f"Started {value} (slot {slot}): {params['task']}."
                         + "".join(f"\n⚠ {w}" for w in warnings))

    def _start_failed(self, exc) -> None:
        self._undo_new_run()
        self._start_done(False, describe_error(exc, "start"))

    def _start_done(self, ok: bool, text: str) -> None:
        self.show_message(text, "ok" if ok else "error")
        self._update_enabled()
        self.startFinished.emit(ok, text)

    def _note_unsettled(self, what: str, exc) -> None:
        if isinstance(exc, (CommitUncertain, CommitUnverified)):
            self._unsettled = (what, exc)

    def _settle(self, image: bytes) -> None:
        """The first image read after a write whose end was lost tells what the charger holds."""
        if self._unsettled is None:
            return
        (what, exc), self._unsettled = self._unsettled, None
        verdict = exc.settle(image)
        if verdict == "new":
            self.show_message(f"Read back after the lost link: the {what} is on the charger, verified.", "ok")
        elif verdict == "previous":
            self.show_message(f"Read back after the lost link: the charger kept its previous image; the {what} "
                              "was not written. Do it again.", "warn")
        else:
            self.show_message("Read back after the lost link: the charger holds neither the new image nor the "
                              "previous one (changed since by another program?). Check its macros.", "warn")

    def _op_failed(self, op: str, exc) -> None:
        self._progress_done()
        self._note_unsettled(op, exc)
        text = exc if isinstance(exc, str) else describe_error(exc, op)
        self.show_message(text, "error")
        self._update_enabled()
        self.operationFinished.emit(op, False, text)

    # ================================================================ showing things
    def show_message(self, text: str, kind: str = "info") -> None:
        self.message.setText(text)
        self.message.setStyleSheet(f"color:{colour(self, kind)};")
        self.message.setToolTip(text if len(text) > 80 else "")
        self.statusMessage.emit(text)

    def _show_image(self, image: bytes) -> None:
        found = self.charger.show_image(image)
        self._image, self._slots = self.charger.image, found
        self.run.set_slots(found, self._flashed_slot)
        self._update_enabled()

    def _table_selected(self) -> None:
        row = self.charger.selected_row()
        if row is not None:
            self.run.select_slot(row)

    def _show_passport(self, passport, error: str = "") -> None:
        self.passport.show_passport(passport, error, self.is_connected())


    def _poll_passport(self) -> None:
        if self.is_connected() and not self.connection.busy and self.isVisible():
            def job(client, progress):
                try:
                    return client.passport_read()
                except DeviceError:
                    return None
            self.connection.call(job, self._show_passport, lambda exc: None)

    def _update_readings(self) -> None:
        tel = self.series.last_telemetry
        if tel is not None and self.series.frames > self._start_frames and tel.running != self._running:
            self._running = tel.running
            self._update_enabled()
        if tel is not None:
            self.live.show_readings(tel)
            if tel.running:
                where = f"{'C' if tel.section == 'charge' else 'D'}{tel.phase}" if tel.section else "—"
                state = tel.state or ("paused" if tel.paused else "running")
                self.run_label.set_full_text(f"{state} · {where} · {hmmss(tel.time_s)}")
            else:
                self.run_label.set_full_text("idle" if not self._run_name else f"{self._run_name} ended")
        self._note_finish()
        self._update_monitor_label()
        logger = self._log
        if logger is not None:
            if logger.error and not self._log_error_said:
                self._log_error_said = True
                self.show_message(f"Session CSV: {logger.error}. The plot goes on; the CSV ends here.", "warn")
            self.session_label.set_full_text(self._session_text(logger))


    def _note_finish(self) -> None:
        """Say so when a run finishes (the finish event)."""
        with self.series.lock:
            events = self.series.events[self._finished_seen:]
            self._finished_seen = len(self.series.events)
        for _, ev in events:
            if ev.kind == "finish":
                self.show_message(f"{self._run_name or 'The macro'} finished at {hmmss(ev.time_s)}: "
                                  f"{ev.detail or 'end'}.", "ok")

    # ================================================================ state
    def _set_state_connected(self, monitor: bool = False) -> None:
        self.connect_button.setText("Disconnect")
        self.ports.auto_refresh = False
        self.plot.start()
        self._readings_timer.start()
        if not monitor:
            self._passport_timer.start()
        self._update_enabled()

    def _set_state_disconnected(self) -> None:
        self._running = False
        self.connect_button.setText("Connect")
        self.ports.auto_refresh = True
        self._readings_timer.stop()
        self._passport_timer.stop()
        self.plot.stop()
        self._progress_done()
        self._info = None
        if not self.plot.points:
            self.plot.set_placeholder("not connected: pick a port and Connect")
        self.info_label.set_full_text("not connected")
        self._update_enabled()
        self._port_changed()

    def _update_enabled(self) -> None:
        monitoring = self.is_monitoring()
        self.replay_button.setEnabled(not self._shut and not monitoring and self.connection.state == "disconnected")
        self.driver_combo.setEnabled(not monitoring and self.connection.state == "disconnected"
                                     and not self.ports.is_virtual())
        if monitoring:
            link = self.monitor.link
            title = link.driver.title if link.driver else "this charger"
            reason = MONITOR_ONLY_REASON.format(title=title) + ": Flash and Start are off"
            self.connect_button.setEnabled(not self._shut)
            for w in (self.ports, self.v_chem, self.v_mah, self.v_cells, self.v_passport, self.flash_button,
                      self.backup_button, self.restore_button, self.reload_button, self.flash_slot,
                      self.start_button, self.stop_button, self.pp_refresh, self.run_slot, self.rate):
                w.setEnabled(False)
            self.flash_button.setToolTip(reason)
            self.start_button.setToolTip(reason)
            self.result_label.setText(f"<span style='color:{colour(self, 'warn')};'>{reason}.</span>")
            return
        if self.result_label.text().endswith("Flash and Start are off.</span>"):
            self.result_label.setText("")
        self.rate.setEnabled(True)
        self.flash_button.setToolTip(FLASH_TIP)
        self.start_button.setToolTip(START_TIP)
        state = self.connection.state
        connected = state == "connected"
        idle = connected and not self.connection.busy
        self.connect_button.setEnabled(state in ("disconnected", "connected", "connecting") and not self._shut)
        for w in (self.ports, self.v_chem, self.v_mah, self.v_cells, self.v_passport):
            w.setEnabled(state == "disconnected")
        for w in (self.flash_button, self.backup_button, self.restore_button, self.reload_button, self.flash_slot):
            w.setEnabled(idle)
        self.start_button.setEnabled(idle and bool(self._slots) and not self.is_running())
        self.start_button.setToolTip(f"{self._run_name or 'A macro'} is running: Stop it first"
                                     if self.is_running() else START_TIP)
        self.stop_button.setEnabled(connected)
        self.pp_refresh.setEnabled(idle)
        self.run_slot.setEnabled(connected)

    def _port_changed(self) -> None:
        virtual = self.ports.is_virtual()
        self.virtual_box.setVisible(virtual)
        self.driver_combo.setEnabled(not virtual and self.connection.state == "disconnected"
                                     and not self.is_monitoring())

    # ================================================================ monitor-only chargers
    def is_monitoring(self) -> bool:
        """A monitor-only charger's link is open (or still being recognised)."""
        return self.monitor.link is not None

    def _watch(self, port: str, driver: str, baud: int | None = None) -> bool:
        """Read a monitor-only charger on ``port`` (``driver`` "auto": recognise it)."""
        if baud is None:
            chosen = self.ports.baudrate()
            bauds = (DRIVERS[driver].baud,) + DRIVERS[driver].bauds if driver in DRIVERS else ()
            baud = chosen if driver == AUTO or chosen in bauds else None
        # A monitor-only charger's frames are its recording (some never say "running"): all kept.
        self._open_session_log(cells=None, idle_s=0.0)
        error = self.monitor.open(port, driver, baud)
        if error:
            self.monitor.link = None
            self._close_session_log(discard_empty=True)
            self._set_state_disconnected()
            self.show_message(f"Cannot watch {port}: {error}", "error")
            self.connectedChanged.emit(False)
            return False
        self._set_state_connected(monitor=True)
        link = self.monitor.link
        if link.driver is not None:
            self._on_monitor_status(f"monitoring {link.driver.title}")
        else:
            self.info_label.set_full_text(f"{port}: listening for a charger…")
            self.show_message(f"Listening on {port} for a monitor-only charger "
                              f"({', '.join(DRIVERS)})…", "info")
            self.plot.set_placeholder("listening: a charger sends while a program runs")
        self.connectedChanged.emit(True)
        return True

    def _on_monitor_status(self, text: str) -> None:
        link = self.monitor.link
        if link is None:
            return
        if link.driver is not None:
            self.plot.set_placeholder("monitoring: waiting for the charger's first record")
            self.show_message(f"{text[0].upper()}{text[1:]} on {link.port}. "
                              + MONITOR_ONLY_REASON.format(title=link.driver.title) + ".", "ok")
        else:
            self.show_message(text, "warn" if "nothing recognisable" in text else "info")
        self._update_monitor_label()
        self._update_enabled()

    def _update_monitor_label(self) -> None:
        link = self.monitor.link
        if link is None:
            return
        name = link.driver.title if link.driver else "recognising…"
        bad = link.bad
        self.info_label.set_full_text(f"{name} · monitor-only · {link.good} records · {bad} bad")
        self.info_label.setToolTip(f"{link.port}: {name}\n{link.good} records decoded; {bad} bad (checksum, torn "
                                   "line or garbage: counted, never plotted)")
        self.info_label.setStyleSheet(f"color:{colour(self, 'warn' if bad else 'info')};")

    def _on_monitor_closed(self, error: str) -> None:
        link, self.monitor.link = self.monitor.link, None
        self._stop_replay_link()
        self._close_session_log()
        self._set_state_disconnected()
        self.info_label.setStyleSheet(f"color:{colour(self, 'info')};")
        kept = " The plot and the session CSV are kept."
        counts = f" {link.good} records, {link.bad} bad." if link is not None else ""
        if error:
            self.show_message(error + counts + kept, "error")
        else:
            self.show_message("Disconnected." + counts + (kept if self.plot.points else ""), "info")
        self.plot.refresh()
        self.connectedChanged.emit(False)

    def replay(self, path: str | Path, speed: float | None = None) -> bool:
        """Play a recording onto a pty (in this process) and watch it: ``speed`` × its pace (None:
        the speed box's value)."""
        from ...device.drivers import CaptureError
        from ...device.replay import load_recording, serve_replay
        if self.connection.state != "disconnected" or self.is_monitoring():
            self.show_message("Disconnect first, then replay.", "warn")
            return False
        try:
            recording = load_recording(Path(path).read_bytes())
            port, stop, _device = serve_replay(recording, float(speed or self.v_speed.value()))
        except CaptureError as exc:
            self.show_message(f"{Path(path).name}: {exc}", "error")
            return False
        except OSError as exc:
            self.show_message(f"Cannot replay {Path(path).name}: {exc.strerror or exc}", "error")
            return False
        self._stop_replay = stop
        if not self.connect_to(port, recording.driver):
            self._stop_replay_link()
            return False
        self.show_message(f"Replaying {Path(path).name} ({DRIVERS[recording.driver].title}, "
                          f"{len(recording.records)} records) on {port}.", "ok")
        return True

    def _stop_replay_link(self) -> None:
        stop, self._stop_replay = self._stop_replay, None
        if stop is not None:
            stop()

    def _replay_clicked(self) -> None:
        path, _ = QFileDialog.getOpenFileName(self, "Replay a charger recording", "",
                                              "Recordings (*.txt *.log *.bin *.hex *.csv);;All files (*)")
        if path:
            self.replay(path)

    def _speed_changed(self, value: int) -> None:
        self.connection.set_speed(float(value))

    def _rate_changed(self, value: int) -> None:
        if self.is_connected():
            self.connection.call(lambda client, progress: client.set_telemetry_rate(value), None, lambda exc: None)

    # ================================================================ session CSV
    def _open_session_log(self, cells: int | None = 0, idle_s: float = IDLE_LOG_S) -> None:
        self._close_session_log()
        try:
            self._log = SessionLog(session_path(self.session_dir), cells=cells, idle_s=idle_s)
        except OSError as exc:
            self._log = None
            self.session_label.set_full_text(f"no session CSV: cannot write in {self.session_dir}: {exc.strerror or exc}")
            return
        self.session_file = self._log.path
        self._log_error_said = False
        self.session_label.set_full_text(f"Session: {display_path(self._log.path)}")

    def _close_session_log(self, discard_empty: bool = False) -> None:
        logger, self._log = self._log, None
        if logger is None:
            return
        logger.close()
        if discard_empty and logger.rows == 0:
            try:
                logger.path.unlink()
            except OSError:
                pass
            self.session_label.set_full_text("")
            self.session_file = None
        else:
            self.session_label.set_full_text(self._session_text(logger))

    @staticmethod
    def _session_text(logger: SessionLog) -> str:
        rows = f" · {logger.rows} rows" if logger.rows else ""
        err = f" · ⚠ {logger.error}" if logger.error else ""
        return f"Session: {display_path(logger.path)}{rows}{err}"

    # ================================================================ dialogs
    def _backup_clicked(self) -> None:
        path, _ = QFileDialog.getSaveFileName(self, "Back up the charger's EEPROM",
                                              str(Path(documents_folder()) / "eeprom-backup.bin"),
                                              "EEPROM images (*.bin);;All files (*)")
        if path:
            self.backup(path)

    def _restore_clicked(self) -> None:
        path, _ = QFileDialog.getOpenFileName(self, "Restore an EEPROM image", documents_folder(),
                                              "EEPROM images (*.bin);;All files (*)")
        if not path:
            return
        try:
            in_image = [s.name for s in slots(Path(path).read_bytes())]
        except Exception:   # noqa: BLE001 - unreadable or broken: restore() says precisely why
            in_image = None
        if confirm_restore(self, restore_text(Path(path).name, self.slot_names(), in_image)):
            self.restore(path)
        else:
            self.show_message(f"Not restored: {Path(path).name} was not written.", "info")

    def closeEvent(self, event) -> None:  # noqa: N802
        self.shutdown()
        super().closeEvent(event)
