"""The Device panel: a charger (or the built-in virtual one) on a serial line.

It composes its parts, each a widget in its own module with the state it owns: above, the
connection bar (``connection_bar``: port, driver, Connect, Replay, the virtual charger's
battery); left, two narrow columns: what is on the charger (``charger_slots``: its macros,
Compile & Flash, Backup/Restore) and the run (``run_controls``: task parameters, Start/Stop;
``passport_view``: the battery's passport); right, the live view (``live_view``: the readout,
the runs and the plot). Below: the message line and the session CSV (``session_label``). This
module opens and closes the link (a ZUML charger through ``connection``, a monitor-only one
through ``charger_monitor``), routes the parts' signals and says which control is enabled when.

A port's driver is "Auto" by default: a ZUML charger (it answers IDENTIFY), else a monitor-only charger
recognised from what it sends (``streams.drivers``), plotted and logged like ours, Flash and Start off.

Nothing here waits for the charger: requests run on the connection's worker thread and come back as
signals; telemetry goes from the reader thread into the live series and the session CSV without Qt.
"""
from __future__ import annotations

from pathlib import Path
from typing import Callable

from PySide6.QtCore import Qt, QTimer, Signal
from PySide6.QtGui import QKeySequence, QShortcut
from PySide6.QtWidgets import QHBoxLayout, QPushButton, QSplitter, QVBoxLayout, QWidget

from ...streams.drivers import AUTO
from ...device.errors import NotACharger
from ...device.install.isp_store import ProgrammerClient, no_run_text
from ...device.links.ports import SIMULATED_B6, VIRTUAL
from ...i18n import _
from ...user_dirs import data_dir
from .b6_front_panel import B6FrontPanel
from .charger_monitor import ChargerMonitor, recording_cells
from . import confirm_dialogs
from .charger_slots import ChargerSlots
from .connection import DeviceConnection, Opened
from .connection_bar import ConnectionBar
from .device_style import ControlsScroll, MessageLine
from .live_view import LiveView
from .passport_view import PassportView
from .run_controls import RunControls
from .session_label import SessionLabel

READINGS_MS = 250
VIRTUAL_EEPROM = "virtual-charger-eeprom.bin"
SIMULATED_B6_EEPROM = "simulated-imaxb6-eeprom.bin"     # its macros, templates and calibration
# The parts' controls, under the names the panel's callers and tests know.
ALIASES = {"bar": ("ports", "driver_combo", "connect_button", "replay_button", "v_chem", "v_mah", "v_cells",
                   "v_passport", "v_speed", "rate", "virtual_box", "info_label", "add_named_batteries"),
           "charger": ("table", "free_label", "flash_slot", "flash_button", "progress", "result_label",
                       "backup_button", "restore_button", "reload_button", "flash", "backup", "restore", "slot_names",
                       "refresh_slots"),
           "run": ("run_slot", "task", "capacity", "current", "series_spin", "voltage", "repetitions", "sensor",
                   "start_button", "stop_button", "run_label", "start", "stop", "start_params", "set_start_params",
                   "is_running", "stop_and_wait"),
           "passport": ("pp_refresh", "pp_labels", "refresh_passport"),
           "monitor": ("is_monitoring",),
           "live": ("plot", "readings", "follow", "follow_minutes", "all_button", "clear_button")}


class DevicePanel(QWidget):
    connectedChanged = Signal(bool)
    flashFinished = Signal(bool, str)
    telemetryReceived = Signal(int)         # points plotted so far; at most at the redraw rate
    statusMessage = Signal(str)
    startFinished = Signal(bool, str)       # START done (or refused: the reasons)
    operationFinished = Signal(str, bool, str)   # "backup" | "restore" | "stop" | "passport" | "slots", ok, message
    phaseActivated = Signal(int)            # FAZE byte offset of a double-clicked band (the editor may show it)
    runEnded = Signal()                     # the run started here (or seen running) stopped
    runSeen = Signal()                      # a run the window did not start runs (a B6's own START button)

    def __init__(self, get_record: Callable[[], tuple[bytes, str] | None], session_dir: Path,
                 parent: QWidget | None = None, *, port_lister: Callable | None = None):
        super().__init__(parent)
        self.setObjectName("devicePanel")
        self._get_record = get_record
        self.session_dir = Path(session_dir)
        self._shut = False
        self._before_replay: tuple[str, str] | None = None     # (the replay's pty, the target chosen before)
        self.telemetry_taps: list[Callable] = []   # called with every frame, on the reader thread
        self._auto_fallback: tuple[str, int] | None = None   # (port, baud) to watch if no ZUML charger answers
        self.monitor = ChargerMonitor(self._telemetry_rt, self, self._event_rt)
        self.connection = DeviceConnection(self._telemetry_rt, self._event_rt, self)
        self.bar = ConnectionBar(port_lister)
        self.charger = ChargerSlots(self.connection, get_record)
        self.run = RunControls(self.connection)
        self.passport = PassportView(self.connection)
        self.live = LiveView()
        self.session = SessionLabel(self.session_dir)
        self.front_panel = B6FrontPanel()
        for part, names in ALIASES.items():
            for name in names:
                setattr(self, name, getattr(getattr(self, part), name))
        self.session_label = self.session
        self._layout()
        self._wire()
        self._set_state_disconnected()
        self.show_message(_("Pick a port (the built-in virtual charger needs no hardware) and Connect."), "info")

    def _layout(self) -> None:
        self.controls_scroll = ControlsScroll(self.charger, self.run, self.passport)
        self.splitter = QSplitter(Qt.Orientation.Horizontal)
        self.splitter.setObjectName("deviceSplitter")
        self.splitter.setChildrenCollapsible(False)
        # Standing in one column (the window's height is the panel's), the controls take the run's
        # phases under them and the plot keeps the whole height; else the phases stand under the plot.
        self.controls_scroll.stackedChanged.connect(self._place_phases)
        self.splitter.addWidget(self.controls_scroll)
        self.splitter.addWidget(self.live)
        self.splitter.setStretchFactor(0, 0)
        self.splitter.setStretchFactor(1, 1)

        self.message = MessageLine()
        bottom = QHBoxLayout()
        bottom.setContentsMargins(0, 0, 0, 0)
        bottom.setSpacing(12)
        bottom.addWidget(self.message, 3)
        bottom.addWidget(self.session, 2)
        self.calibrate_button = QPushButton(_("Calibrate…"))       # an iMAX B6 with the ZUML firmware
        self.calibrate_button.setObjectName("calibrateButton")
        self.calibrate_button.clicked.connect(self.calibrate)
        bottom.addWidget(self.calibrate_button)

        layout = QVBoxLayout(self)
        layout.setContentsMargins(6, 4, 6, 3)
        layout.setSpacing(3)
        layout.addWidget(self.bar)
        layout.addWidget(self.front_panel)
        layout.addWidget(self.splitter, 1)
        layout.addLayout(bottom)

    def _wire(self) -> None:
        self._readings_timer = QTimer(self, interval=READINGS_MS)
        self._readings_timer.timeout.connect(self._update_readings)
        self.flash_shortcut = QShortcut(QKeySequence("Ctrl+Shift+F"), self)
        self.flash_shortcut.setContext(Qt.ShortcutContext.WidgetWithChildrenShortcut)
        self.flash_shortcut.activated.connect(lambda: self.flash())
        self.monitor.status.connect(self._monitor_status)
        self.monitor.placeholder.connect(self.plot.set_placeholder)
        self.monitor.ended.connect(self._closed)
        self.monitor.lcdChanged.connect(self.front_panel.show_lcd)
        self.connection.lcdChanged.connect(self.front_panel.show_lcd)
        self.connection.connected.connect(self._on_connected)
        self.connection.connectFailed.connect(self._on_connect_failed)
        self.connection.disconnected.connect(self._closed)
        self.connection.busyChanged.connect(lambda _busy: self._update_enabled())
        self.connect_button.clicked.connect(self._connect_clicked)
        self.replay_button.clicked.connect(self._replay_clicked)
        self.ports.changed.connect(self._update_enabled)
        self.v_speed.valueChanged.connect(lambda value: self.connection.set_speed(float(value)))
        self.rate.valueChanged.connect(self._rate_changed)
        self.v_mah.valueChanged.connect(self.capacity.setValue)
        self.v_cells.valueChanged.connect(self.series_spin.setValue)
        self.v_chem.currentIndexChanged.connect(lambda _i: self._battery_choice_changed())
        for part in (self.charger, self.run, self.monitor):
            part.message.connect(self.show_message)
        for part in (self.charger, self.run):
            part.changed.connect(self._update_enabled)
        for part in (self.charger, self.run, self.passport):
            part.operationFinished.connect(self.operationFinished)
        self.charger.flashFinished.connect(self.flashFinished)
        self.charger.imageShown.connect(self._image_shown)
        self.charger.slotChosen.connect(self.run.select_slot)
        self.charger.running_macro = lambda: ((self.run.run_slot_index, self.run.run_name) if self.run.is_running()
                                              else None)
        self.run.startFinished.connect(self.startFinished)
        self.run.stopping.connect(self.runEnded)    # a STOP ends the run as its end does
        self.run.runStarting.connect(lambda: self.live.new_run(self.run.run_name))
        self.run.runUndone.connect(self._undo_new_run)
        self.run.runStarted.connect(self.live.run_started)
        self.run.passportRead.connect(lambda p: self.passport.show_passport(p, "", self.is_connected()))
        self.run.stopping.connect(self.live.mark_start)
        self.clear_button.clicked.connect(self.clear_plot)
        self.plot.pointsAdded.connect(self.telemetryReceived)
        self.plot.phaseActivated.connect(self.phaseActivated)

    # ================================================================ public API
    @property
    def series(self):
        """The current run's telemetry (``live_plot.LiveSeries``)."""
        return self.live.series

    @property
    def session_file(self) -> Path | None:
        return self.session.path

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
            self.show_message(_("Already connected (or connecting): Disconnect first."), "warn")
            return False
        if self.ports.is_programmer() and not confirm_dialogs.confirm_programmer(self):
            self.show_message(_("Not connected: disconnect the battery first, then connect through the programmer."),
                              "warn")
            return False
        watch_with = self.bar.monitor_driver(target)
        if watch_with is not None:
            return self._watch(target, watch_with)
        auto = target not in (VIRTUAL, SIMULATED_B6) and (self.driver_combo.currentData() or AUTO) == AUTO
        self._auto_fallback = (target, self.ports.baudrate()) if auto else None
        try:
            virtual = (self.bar.virtual_spec(self.virtual_battery(), self.virtual_eeprom_path())
                       if target == VIRTUAL else None)
        except ValueError as exc:           # the virtual battery's cells, typed wrong
            self.show_message(str(exc), "error")
            return False
        self.session.open()
        ok = self.connection.open(target, self.ports.baudrate(), virtual, self.rate.value(),
                                  self.simulated_b6_eeprom_path())
        if not ok:
            self.session.close(discard_empty=True)
        else:
            what = (_("the built-in virtual charger ({battery}, ×{speed:g})").format(battery=virtual.battery,
                                                                                     speed=virtual.speed)
                    if virtual else _("the simulated iMAX B6") if target == SIMULATED_B6 else target)
            self.show_message(_("Connecting to {what}…").format(what=what), "info")
            self._update_enabled()
        return ok

    def disconnect(self, *args, **kw):  # noqa: A003 - the panel's verb
        """Close the link (and the built-in virtual charger). The plot and the session CSV stay.
        (With arguments it is QObject.disconnect, for signal connections.)"""
        if args or kw:
            return super().disconnect(*args, **kw)
        if self.is_monitoring():
            self.monitor.close()
        elif self.connection.state in ("connected", "connecting"):
            self.connection.close()
            self.show_message(_("Disconnecting…"), "info")
            self._update_enabled()

    def clear_plot(self) -> None:
        self.plot.clear_session()
        self.live.update_phases()
        self.telemetryReceived.emit(0)

    def calibrate(self) -> None:
        from .calibration_dialog import CalibrationDialog
        CalibrationDialog(self.connection, self).open()

    def shutdown(self) -> None:
        """Stop every thread, close the client and the built-in virtual charger, close the CSV.
        The main window calls this when it closes; idempotent."""
        if self._shut:
            return
        self._shut = True
        self.plot.stop()
        self._readings_timer.stop()
        self.passport.poll_timer.stop()
        self.ports.shutdown()
        self.connection.shutdown()
        self.monitor.shutdown()
        self.session.close()

    def message_text(self) -> str:
        return self.message.full_text

    def virtual_eeprom_path(self) -> Path:
        """Where the built-in virtual charger keeps its EEPROM: like a real charger, it still
        holds its macros after a disconnect (and the next time ZUML Studio starts)."""
        return self.session_dir / VIRTUAL_EEPROM

    def simulated_b6_eeprom_path(self) -> Path:
        """The simulated iMAX B6's EEPROM (macros, templates, calibration), kept in the user's data
        folder: the next session finds the charger as this one left it."""
        return data_dir() / SIMULATED_B6_EEPROM

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

    def run_name(self) -> str:
        """The macro started last ("" before the first start)."""
        return self.run.run_name

    def replay(self, path: str | Path, speed: float | None = None) -> bool:
        """Play a recording onto a pty (in this process) and watch it: ``speed`` × its pace (None:
        the speed box's value)."""
        if self.connection.state != "disconnected" or self.is_monitoring():
            self.show_message(_("Disconnect first, then replay."), "warn")
            return False
        served = self.monitor.serve_replay(Path(path), float(speed or self.v_speed.value()))
        if served is None:
            return False
        self._fresh_run(Path(path).name, served[1])
        # The replay's pty goes into the URL field for the connection; it is the replay's, not the
        # user's choice: when the replay ends the field gets back what the user had chosen.
        self._before_replay = (served[0], self.ports.target())
        if not self.connect_to(served[0], served[1].driver):
            self.monitor.stop_replay()
            self._forget_replay_port()
            return False
        self.monitor.say_replaying(Path(path), *served)
        return True

    def _fresh_run(self, name: str, recording) -> None:
        """A recording is another device: its run starts anew (the one before is kept in the run
        list, not appended to), per cell by its own cells, and the last charger's macros and
        passport go from the panel."""
        self.live.new_run(self.run.run_name)
        self.run.run_name = name
        self.live.run_started(name, recording_cells(recording))
        self.charger.forget()
        self.run.set_slots([], None)
        self.passport.show_passport(None)

    def show_message(self, text: str, kind: str = "info") -> None:
        self.message.say(text, kind)
        self.statusMessage.emit(text)

    # ================================================================ routing
    def _image_shown(self) -> None:
        self.run.set_slots(self.charger.slots, self.charger.flashed_slot)
        self._update_enabled()

    def _undo_new_run(self) -> None:
        name = self.live.undo_new_run()
        if name is not None:
            self.run.run_name = name

    def _place_phases(self, in_column: bool) -> None:
        if in_column:
            self.live.phases_in_column()
            self.controls_scroll.hold(self.live.phase_box)
        else:
            self.live.keep_phases()

    def _update_readings(self) -> None:
        if self.run.follow(self.live.fresh_telemetry(), self.series.last_telemetry, self.live.new_finishes()):
            self._update_enabled()
            if not self.run.running:
                self.runEnded.emit()
            else:                           # a START here sets running itself: this one began on the charger
                self.runSeen.emit()
        if self.series.last_telemetry is not None:
            self.live.show_readings(self.series.last_telemetry)
        self.live.update_phases()
        self.bar.show_monitor(self.monitor.link)
        error = self.session.update_text()
        if error:
            self.show_message(error, "warn")

    def _battery_choice_changed(self) -> None:
        if self.connection.state == "disconnected":
            self.virtual_battery()
        self._update_enabled()

    def _rate_changed(self, value: int) -> None:
        if self.is_connected():
            self.connection.call(lambda client, progress: client.set_telemetry_rate(value), None, lambda exc: None)

    # ================================================================ reader thread (no Qt)
    def _telemetry_rt(self, tel) -> None:
        self.live.series.add_telemetry(tel)
        self.session.add_telemetry(tel)
        for tap in self.telemetry_taps:
            tap(tel)

    def _event_rt(self, ev) -> None:
        self.live.series.add_event(ev)
        self.session.add_event(ev)

    # ================================================================ the link
    def _connect_clicked(self) -> None:
        if self.connection.state in ("connected", "connecting") or self.is_monitoring():
            self.disconnect()
        else:
            self.connect_to(None)

    def _replay_clicked(self) -> None:
        path = self.bar.ask_recording()
        if path:
            self.replay(path)

    def _on_connected(self, opened: Opened) -> None:
        self.run.charger_max_a = opened.info.max_charge_a
        self.charger.charger_info = opened.info
        self.bar.show_charger(opened)
        self._set_state_connected()
        self.plot.set_placeholder(_("connected: Start a macro to plot its run"))
        where = (_("built-in virtual charger") if opened.virtual else
                 _("the simulated iMAX B6") if opened.simulated_b6 else opened.url)
        self.front_panel.show_device(self.connection.simulated_b6)
        self.show_message(_("Connected to {where}: {model}, firmware {firmware}.").format(
            where=where, model=opened.info.model, firmware=opened.info.firmware), "ok")
        self.refresh_slots()
        self.refresh_passport()
        self.connectedChanged.emit(True)

    def _on_connect_failed(self, message: str) -> None:
        fallback, self._auto_fallback = self._auto_fallback, None
        self.session.close(discard_empty=True)
        self._set_state_disconnected()
        if fallback is not None and isinstance(self.connection.last_error, NotACharger):
            self._watch(fallback[0], AUTO, fallback[1])
            return
        self.show_message(message, "error")
        self.connectedChanged.emit(False)

    def _forget_replay_port(self) -> None:
        pty, chosen = self._before_replay or ("", "")
        self._before_replay = None
        if pty and self.ports.url.text().strip() == pty:
            self.ports.set_target(chosen)

    def _closed(self, error: str, counts: str = "") -> None:
        self._forget_replay_port()
        self.session.close()
        self._set_state_disconnected()
        kept = " " + _("The plot and the session CSV are kept.") if self.plot.points or error else ""
        self.show_message((error or _("Disconnected.")) + counts + kept, "error" if error else "info")
        self.plot.refresh()
        self.connectedChanged.emit(False)

    def _set_state_connected(self, monitor: bool = False) -> None:
        self.ports.auto_refresh = False
        self.plot.start()
        self._readings_timer.start()
        if not monitor:
            self.passport.poll_timer.start()
        self._update_enabled()

    def _set_state_disconnected(self) -> None:
        self.front_panel.show_device(None)
        if self.run.running:                # the link went mid-run: what came of the run is still its record
            self.run.running = False
            self.runEnded.emit()
        self.ports.auto_refresh = True
        self._readings_timer.stop()
        self.passport.poll_timer.stop()
        self.plot.stop()
        self.charger.progress_done()
        self.run.charger_max_a = None
        if not self.plot.points:
            self.plot.set_placeholder(_("not connected: pick a port and Connect"))
        self.bar.show_disconnected()
        self._update_enabled()

    def _update_enabled(self) -> None:
        monitoring = self.is_monitoring()
        self.bar.set_link_state(self.connection.state, monitoring, self._shut)
        reason = self.monitor.reason()
        connected = self.connection.state == "connected"
        idle = connected and not self.connection.busy
        self.charger.set_enabled(idle, reason)
        # Through the programmer the processor is held in reset: macros only, runs start on the front panel
        programmer = connected and isinstance(self.connection.client, ProgrammerClient)
        self.run.set_enabled(connected, idle, reason or (no_run_text() if programmer else ""))
        self.pp_refresh.setEnabled(idle and not monitoring)

    # ================================================================ monitor-only chargers
    def _watch(self, port: str, driver: str, baud: int | None = None) -> bool:
        # A monitor-only charger's frames are its recording (some never say "running"): all kept.
        self.session.open(cells=None, idle_s=0.0)
        if not self.monitor.watch(port, driver, self.ports.baudrate(), baud, fallback=baud is not None):
            self.session.close(discard_empty=True)
            self._set_state_disconnected()
            self.connectedChanged.emit(False)
            return False
        self._set_state_connected(monitor=True)
        self.front_panel.listen()            # a B6 heard on its TX: its display, when its stream carries it
        self._monitor_status()
        self.connectedChanged.emit(True)
        return True

    def _monitor_status(self) -> None:
        self.bar.show_monitor(self.monitor.link)
        self._update_enabled()
