"""The Device panel: a charger (or the built-in virtual one) on a serial line.

Left, two narrow columns: what is on the charger (device info, its macros, Compile & Flash,
Backup/Restore) and the run (task parameters, Start/Stop, the battery's passport); right,
the live plot. Above: the port, the baud rate, the driver, Connect, Replay; for the built-in
virtual charger its battery, passport and speed. Below: the message line and the session CSV.

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
from PySide6.QtWidgets import (QAbstractItemView, QCheckBox, QComboBox, QDoubleSpinBox, QFileDialog,
                               QFrame, QGridLayout, QHBoxLayout, QHeaderView, QLabel, QProgressBar, QPushButton,
                               QScrollArea, QSizePolicy, QSpinBox, QSplitter, QTableWidget, QTableWidgetItem,
                               QToolButton, QVBoxLayout, QWidget)

from ...device import messages as msg
from ...device.drivers import AUTO, DRIVERS, MONITOR_ONLY_REASON, ZUML
from ...device.errors import CommitUncertain, CommitUnverified, DeviceError, ImageTooLarge, NotACharger
from ...device.flashing import merge_record
from ...device.passport import akk_name, fitness_warnings, printable
from ...sim.start_check import start_warnings
from ...device.ports import VIRTUAL
from ...lang.eeprom import Slot, slots, used_bytes
from ...safety import image_problems, record_problems
from ..number_boxes import double_spin_box, form_field, spin_box
from ..timefmt import hmmss
from .charger_monitor import ChargerMonitor
from .connection import DeviceConnection, Opened, VirtualSpec, describe_error
from .live_plot import DEFAULT_FOLLOW_MIN, LivePlot, LiveSeries
from .port_chooser import PortChooser
from ...device.session_log import SessionLog, display_path, session_path
from .unsafe_dialog import confirm_unsafe

log = logging.getLogger(__name__)

FLASH_TIP = "Write the editor's macro to the charger, verify it (Ctrl+Shift+F)"
START_TIP = "Check the battery's passport, then start the slot's macro"
COLORS = {"info": "#505050", "ok": "#1d6b2c", "error": "#b00020", "warn": "#a04000"}
TASKS = (("charge", "Charge"), ("discharge", "Discharge"), ("train", "Train"))
FIELD_WIDTH = 92
READINGS_MS = 250
PASSPORT_POLL_MS = 5000
DEFAULT_BATTERY = ("NiMh", 2000, 4)
NAMED_BATTERY = "battery:"      # virtual chemistry box data of a saved fitted battery
MATCH = "match"
VIRTUAL_EEPROM = "virtual-charger-eeprom.bin"


class _Unsafe:
    """What a job hands back instead of writing: the safety check's problems, for the dialog."""

    def __init__(self, problems: list[str]):
        self.problems = problems

    def summary(self) -> str:
        return "the safety check refused it:\n" + "\n".join(f"• {line}" for line in self.problems)


def _chemistry_names() -> list[str]:
    from ...sim.chemistry import chemistry_names
    return chemistry_names()


def record_chemistry(record: bytes) -> str:
    """The AKK_TYPE a record declares ("NiMh"), "Undef" without one, "?" if it does not decode."""
    try:
        from ...lang.opcodes import AKK_TYPE
        from ...sim.program import Program
        return akk_name(Program(record).intro.declarations.get(AKK_TYPE.code, 0))
    except Exception:   # noqa: BLE001 - a record that does not decode
        return "?"


class ElidedLabel(QLabel):
    """A one-line label that elides its (plain) text to its width; the whole text is the tooltip."""

    def __init__(self, text: str = "", parent: QWidget | None = None,
                 mode: Qt.TextElideMode = Qt.TextElideMode.ElideRight):
        super().__init__(parent)
        self._full = ""
        self._mode = mode
        self.setSizePolicy(QSizePolicy.Policy.Ignored, QSizePolicy.Policy.Preferred)
        self.setMinimumWidth(40)
        self.set_full_text(text)

    def set_full_text(self, text: str) -> None:
        self._full = text
        self.setToolTip(text)
        self._elide()

    def full_text(self) -> str:
        return self._full

    def resizeEvent(self, event) -> None:  # noqa: N802
        super().resizeEvent(event)
        self._elide()

    def _elide(self) -> None:
        width = max(10, self.width() - 2)
        super().setText(self.fontMetrics().elidedText(self._full, self._mode, width))


class SlotTable(QTableWidget):
    """The slot list. Its preferred height is small (a header and three rows): the column's
    layout gives it whatever room is left, and a preferred height of its own would make the
    controls scroll in a 380 px dock."""

    def sizeHint(self):  # noqa: N802
        hint = super().sizeHint()
        rows = self.verticalHeader().defaultSectionSize()
        hint.setHeight(self.horizontalHeader().sizeHint().height() + 3 * rows + 2 * self.frameWidth())
        return hint


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
        # -- the port row --------------------------------------------------------------------
        self.ports = PortChooser(port_lister)
        self.connect_button = QPushButton("Connect")
        self.connect_button.setObjectName("connectButton")
        self.connect_button.setToolTip("Connect to the charger on the chosen port (or Disconnect)")
        self.connect_button.setMinimumWidth(96)
        port_label = QLabel("Port")
        port_label.setBuddy(self.ports.combo)
        top = QHBoxLayout()
        top.setContentsMargins(0, 0, 0, 0)
        top.setSpacing(6)
        self.driver_combo = QComboBox()
        self.driver_combo.setObjectName("driverCombo")
        self.driver_combo.addItem("Auto", AUTO)
        self.driver_combo.addItem("ZUML charger", ZUML)
        for d in DRIVERS.values():
            self.driver_combo.addItem(d.title, d.name)
        self.driver_combo.setSizeAdjustPolicy(QComboBox.SizeAdjustPolicy.AdjustToMinimumContentsLengthWithIcon)
        self.driver_combo.setMinimumContentsLength(10)
        self.driver_combo.setToolTip("The charger's protocol. Auto: a ZUML charger if one answers, else a "
                                     "monitor-only charger (cheali, iCharger, iMAX B6, Ultramat, SkyRC, ISDT) "
                                     "recognised from what it sends")
        self.replay_button = QPushButton("Replay a recording…")
        self.replay_button.setObjectName("replayButton")
        self.replay_button.setToolTip("Play a charger recording ($ lines, {…} frames, Ultramat frames, a HID "
                                      "report dump, an iCharger DUO/X log) onto a port and watch it here, at the "
                                      "virtual charger's speed ×")
        top.addWidget(port_label)
        top.addWidget(self.ports, 1)
        top.addWidget(self.driver_combo)
        top.addWidget(self.connect_button)
        top.addWidget(self.replay_button)

        # -- the virtual charger row ---------------------------------------------------------
        self.v_chem = QComboBox()
        self.v_chem.setObjectName("virtualChemistry")
        self.v_chem.addItem("from the macro", None)
        for name in _chemistry_names():
            self.v_chem.addItem(name, name)
        self.add_named_batteries()
        self.v_chem.setToolTip("The virtual battery's chemistry; 'from the macro' uses the editor macro's "
                               "AKK_TYPE (NiMh if it has none); a saved fitted battery brings its own "
                               "capacity and cells")
        self.v_mah = self._spin_box(100, 65000, DEFAULT_BATTERY[1], " mAh", "the virtual battery's capacity")
        self.v_mah.setSingleStep(100)
        self.v_cells = self._spin_box(1, 24, DEFAULT_BATTERY[2], " cells", "cells in series in the virtual battery")
        self.v_passport = QComboBox()
        self.v_passport.setObjectName("virtualPassport")
        self.v_passport.addItem("as battery", MATCH)
        for name in _chemistry_names():
            self.v_passport.addItem(name, name)
        self.v_passport.addItem("none", "none")
        self.v_passport.setToolTip("The battery passport chip (spec §4): its chemistry as the battery's, "
                                   "another one (to see the lockout), or no chip")
        self.v_speed = self._spin_box(1, 100000, 60, "×", "the virtual charger runs the macro this many times "
                                  "faster than real time (changes at once)")
        self.v_speed.setObjectName("virtualSpeed")
        self.v_speed.setMaximumWidth(FIELD_WIDTH)
        self.rate = self._spin_box(1, 50, 10, " Hz", "telemetry frames per second the charger sends")
        self.rate.setObjectName("telemetryRate")
        self.virtual_box = QWidget()
        vrow = QHBoxLayout(self.virtual_box)
        vrow.setContentsMargins(0, 0, 0, 0)
        vrow.setSpacing(4)
        for w in (QLabel("Battery"), self.v_chem, self.v_mah, self.v_cells, QLabel("Passport"), self.v_passport,
                  QLabel("Speed"), self.v_speed):
            vrow.addWidget(w)
        second = QHBoxLayout()
        second.setContentsMargins(0, 0, 0, 0)
        second.setSpacing(6)
        self.info_label = ElidedLabel("")
        self.info_label.setObjectName("deviceInfo")
        self.info_label.setStyleSheet(f"color:{COLORS['info']};")
        second.addWidget(self.virtual_box)
        second.addWidget(self.info_label, 1)
        second.addWidget(QLabel("Telemetry"))
        second.addWidget(self.rate)

        # -- column A: the charger's EEPROM --------------------------------------------------
        self.table = SlotTable(0, 5)
        self.table.setObjectName("slotTable")
        self.table.setHorizontalHeaderLabels(["#", "Macro", "Bytes", "Type", "Check"])
        self.table.verticalHeader().setVisible(False)
        self.table.verticalHeader().setDefaultSectionSize(self.fontMetrics().height() + 6)
        self.table.setEditTriggers(QAbstractItemView.EditTrigger.NoEditTriggers)
        self.table.setSelectionBehavior(QAbstractItemView.SelectionBehavior.SelectRows)
        self.table.setSelectionMode(QAbstractItemView.SelectionMode.SingleSelection)
        self.table.setAlternatingRowColors(True)
        self.table.setShowGrid(False)
        header = self.table.horizontalHeader()
        header.setSectionResizeMode(QHeaderView.ResizeMode.ResizeToContents)
        header.setSectionResizeMode(1, QHeaderView.ResizeMode.Stretch)
        header.setHighlightSections(False)
        self.table.setMinimumHeight(2 * self.table.verticalHeader().defaultSectionSize() + 26)
        self.table.setToolTip("The macros in the charger's EEPROM, in slot order; select one to run it")
        self.free_label = QLabel("")
        self.free_label.setObjectName("freeLabel")
        self.flash_slot = QComboBox()
        self.flash_slot.setObjectName("flashSlot")
        self.flash_slot.addItem("By name", None)
        self.flash_slot.setSizeAdjustPolicy(QComboBox.SizeAdjustPolicy.AdjustToMinimumContentsLengthWithIcon)
        self.flash_slot.setMinimumContentsLength(12)
        self.flash_slot.setToolTip("Where Compile & Flash puts the macro: over the one of the same name "
                                   "(else appended), or into a slot you pick")
        self.flash_button = QPushButton("Compile && Flash")
        self.flash_button.setObjectName("flashButton")
        self.flash_button.setToolTip(FLASH_TIP)
        self.progress = QProgressBar()
        self.progress.setObjectName("flashProgress")
        self.progress.setTextVisible(False)
        self.progress.setFixedHeight(6)
        self.progress.setRange(0, 1)
        self.progress.setValue(0)
        self.result_label = QLabel("")
        self.result_label.setObjectName("flashResult")
        self.result_label.setWordWrap(True)
        self.result_label.setTextInteractionFlags(Qt.TextInteractionFlag.TextSelectableByMouse)
        self.backup_button = QPushButton("Backup…")
        self.backup_button.setToolTip("Save the charger's whole EEPROM to a file")
        self.restore_button = QPushButton("Restore…")
        self.restore_button.setToolTip("Write a saved EEPROM image back (every record is checked first)")
        self.reload_button = QToolButton()
        self.reload_button.setText("⟳")
        self.reload_button.setToolTip("Read the macros on the charger again")

        col_a = QWidget()
        col_a.setObjectName("deviceColumn")
        a = QVBoxLayout(col_a)
        a.setContentsMargins(0, 0, 0, 0)
        a.setSpacing(3)
        head = QHBoxLayout()
        head.setSpacing(4)
        head.addWidget(self._heading("Macros on the charger"), 1)
        head.addWidget(self.reload_button)
        a.addLayout(head)
        a.addWidget(self.table, 1)
        a.addWidget(self.free_label)
        flash_row = QHBoxLayout()
        flash_row.setSpacing(4)
        flash_row.addWidget(self.flash_slot, 1)
        flash_row.addWidget(self.flash_button)
        a.addLayout(flash_row)
        a.addWidget(self.progress)
        a.addWidget(self.result_label)
        file_row = QHBoxLayout()
        file_row.setSpacing(4)
        file_row.addWidget(self.backup_button)
        file_row.addWidget(self.restore_button)
        file_row.addStretch(1)
        a.addLayout(file_row)

        # -- column B: the run ---------------------------------------------------------------
        self.run_slot = QComboBox()
        self.run_slot.setObjectName("runSlot")
        self.run_slot.setToolTip("The slot to start (default: the macro just flashed)")
        self.task = QComboBox()
        self.task.setObjectName("runTask")
        for key, text in TASKS:
            self.task.addItem(text, key)
        self.task.setToolTip("charge, discharge, or training (discharge + charge, repeated)")
        self.capacity = self._spin_box(10, 65000, DEFAULT_BATTERY[1], " mAh", "the capacity entered at start")
        self.capacity.setSingleStep(100)
        self.current = self._double_box(0.0, 50.0, 2.0, " A", 2, 0.1, "the current entered at start "
                                   "(CONSTANT_I=INPUT; limits a CONSTANT_V phase); — none")
        self.current.setSpecialValueText("—")
        self.series_spin = self._spin_box(0, 255, DEFAULT_BATTERY[2], " cells", "cells in series entered at start; "
                                      "— none")
        self.series_spin.setSpecialValueText("—")
        self.voltage = self._double_box(0.0, 65.0, 0.0, " V", 2, 0.1, "the voltage entered at start (INPUT); — none")
        self.voltage.setSpecialValueText("—")
        self.repetitions = self._spin_box(1, 255, 1, "", "training: discharge+charge this many times")
        self.repetitions.setPrefix("× ")
        self.sensor = QCheckBox("T sensor")
        self.sensor.setObjectName("runSensor")
        self.sensor.setChecked(True)
        self.sensor.setToolTip("a battery temperature sensor is connected")
        self.start_button = QPushButton("Start")
        self.start_button.setObjectName("startButton")
        self.start_button.setToolTip(START_TIP)
        self.stop_button = QPushButton("Stop")
        self.stop_button.setObjectName("stopButton")
        self.stop_button.setToolTip("Stop the running macro")
        self.run_label = ElidedLabel("")
        self.run_label.setObjectName("runState")

        self.pp_refresh = QToolButton()
        self.pp_refresh.setText("⟳")
        self.pp_refresh.setToolTip("Read the battery's passport again")
        self.pp_labels = {k: QLabel("—") for k in ("serial", "type", "limits")}
        for k, lab in self.pp_labels.items():
            lab.setObjectName(f"passport_{k}")
            lab.setTextInteractionFlags(Qt.TextInteractionFlag.TextSelectableByMouse)
            lab.setTextFormat(Qt.TextFormat.PlainText)      # a battery's bytes are never markup

        col_b = QWidget()
        col_b.setObjectName("runColumn")
        b = QVBoxLayout(col_b)
        b.setContentsMargins(0, 0, 0, 0)
        b.setSpacing(3)
        b.addWidget(self._heading("Run"))
        grid = QGridLayout()
        grid.setHorizontalSpacing(4)
        grid.setVerticalSpacing(3)
        slot_label = QLabel("Slot")
        slot_label.setBuddy(self.run_slot)
        grid.addWidget(slot_label, 0, 0)
        grid.addWidget(self.run_slot, 0, 1, 1, 2)
        grid.addWidget(self.sensor, 0, 3)
        rows = ((("Task", self.task), ("Reps", self.repetitions)),
                (("Capacity", self.capacity), ("Current", self.current)),
                (("Cells", self.series_spin), ("Voltage", self.voltage)))
        for r, pair in enumerate(rows, start=1):
            for c, (text, widget) in enumerate(pair):
                if text:
                    label = QLabel(text)
                    label.setBuddy(widget)
                    label.setToolTip(widget.toolTip())
                    grid.addWidget(label, r, 2 * c)
                    grid.addWidget(widget, r, 2 * c + 1)
                else:
                    grid.addWidget(widget, r, 2 * c, 1, 2)
        grid.setColumnStretch(1, 1)
        grid.setColumnStretch(3, 1)
        b.addLayout(grid)
        buttons = QHBoxLayout()
        buttons.setSpacing(4)
        buttons.addWidget(self.start_button)
        buttons.addWidget(self.stop_button)
        buttons.addWidget(self.run_label, 1)
        b.addLayout(buttons)
        pp_head = QHBoxLayout()
        pp_head.setSpacing(4)
        pp_head.addWidget(self._heading("Battery passport"), 1)
        pp_head.addWidget(self.pp_refresh)
        b.addLayout(pp_head)
        pp = QGridLayout()
        pp.setHorizontalSpacing(6)
        pp.setVerticalSpacing(1)
        for r, (key, text) in enumerate((("serial", "Serial"), ("type", "Type"), ("limits", "Limits"))):
            name = QLabel(text)
            name.setStyleSheet("color:#6a6a6a;")
            pp.addWidget(name, r, 0)
            pp.addWidget(self.pp_labels[key], r, 1)
        pp.setColumnStretch(1, 1)
        b.addLayout(pp)
        b.addStretch(1)

        columns = QWidget()
        cols = QHBoxLayout(columns)
        cols.setContentsMargins(0, 0, 4, 0)
        cols.setSpacing(10)
        cols.addWidget(col_a, 10)
        cols.addWidget(self._vline())
        cols.addWidget(col_b, 11)
        self.controls_scroll = ControlsScroll()
        self.controls_scroll.setObjectName("deviceControls")
        self.controls_scroll.setWidget(columns)
        self.controls_scroll.setWidgetResizable(True)
        self.controls_scroll.setFrameShape(QFrame.Shape.NoFrame)
        self.controls_scroll.setHorizontalScrollBarPolicy(Qt.ScrollBarPolicy.ScrollBarAlwaysOff)
        col_a.setMinimumWidth(215)
        col_b.setMinimumWidth(265)
        self.controls_scroll.setMinimumWidth(columns.minimumSizeHint().width() + 14)

        # -- the plot ------------------------------------------------------------------------
        self.plot = LivePlot(self.series)
        self.plot.setMinimumWidth(280)
        self.readings = QLabel("")
        self.readings.setObjectName("readings")
        self.readings.setTextInteractionFlags(Qt.TextInteractionFlag.TextSelectableByMouse)
        self.readings.setSizePolicy(QSizePolicy.Policy.Ignored, QSizePolicy.Policy.Preferred)
        self.follow = QCheckBox("Follow last")
        self.follow.setObjectName("followCheck")
        self.follow.setChecked(True)
        self.follow.setToolTip("Keep the newest minutes in view; zooming or panning the plot turns this off")
        self.follow_minutes = self._spin_box(1, 24 * 60, DEFAULT_FOLLOW_MIN, " min", "how much of the run to keep in view")
        self.follow_minutes.setMaximumWidth(80)
        self.all_button = QToolButton()
        self.all_button.setText("All")
        self.all_button.setToolTip("Show the whole session (stops following)")
        self.clear_button = QToolButton()
        self.clear_button.setText("Clear")
        self.clear_button.setToolTip("Forget the plotted session (the session CSV keeps everything)")
        plot_bar = QHBoxLayout()
        plot_bar.setContentsMargins(4, 0, 0, 0)
        plot_bar.setSpacing(4)
        plot_bar.addWidget(self.readings, 1)
        plot_bar.addWidget(self.follow)
        plot_bar.addWidget(self.follow_minutes)
        plot_bar.addWidget(self.all_button)
        plot_bar.addWidget(self.clear_button)
        plot_box = QWidget()
        pv = QVBoxLayout(plot_box)
        pv.setContentsMargins(0, 0, 0, 0)
        pv.setSpacing(0)
        pv.addLayout(plot_bar)
        pv.addWidget(self.plot, 1)

        self.splitter = QSplitter(Qt.Orientation.Horizontal)
        self.splitter.setObjectName("deviceSplitter")
        self.splitter.setChildrenCollapsible(False)
        self.splitter.addWidget(self.controls_scroll)
        self.splitter.addWidget(plot_box)
        self.splitter.setStretchFactor(0, 0)
        self.splitter.setStretchFactor(1, 1)

        # -- the bottom line -----------------------------------------------------------------
        self.message = QLabel("")
        self.message.setObjectName("deviceMessage")
        self.message.setWordWrap(True)
        self.message.setTextInteractionFlags(Qt.TextInteractionFlag.TextSelectableByMouse)
        self.message.setSizePolicy(QSizePolicy.Policy.Expanding, QSizePolicy.Policy.Preferred)
        self.session_label = ElidedLabel("", mode=Qt.TextElideMode.ElideMiddle)
        self.session_label.setObjectName("sessionLabel")
        self.session_label.setStyleSheet(f"color:{COLORS['info']};")
        self.session_label.setAlignment(Qt.AlignmentFlag.AlignRight | Qt.AlignmentFlag.AlignVCenter)
        bottom = QHBoxLayout()
        bottom.setContentsMargins(0, 0, 0, 0)
        bottom.setSpacing(12)
        bottom.addWidget(self.message, 3)
        bottom.addWidget(self.session_label, 2)

        layout = QVBoxLayout(self)
        layout.setContentsMargins(6, 4, 6, 3)
        layout.setSpacing(3)
        layout.addLayout(top)
        layout.addLayout(second)
        layout.addWidget(self.splitter, 1)
        layout.addLayout(bottom)

        self._readings_timer = QTimer(self, interval=READINGS_MS)
        self._readings_timer.timeout.connect(self._update_readings)
        self._passport_timer = QTimer(self, interval=PASSPORT_POLL_MS)
        self._passport_timer.timeout.connect(self._poll_passport)
        self.flash_shortcut = QShortcut(QKeySequence("Ctrl+Shift+F"), self)
        self.flash_shortcut.setContext(Qt.ShortcutContext.WidgetWithChildrenShortcut)

    def _heading(self, text: str) -> QLabel:
        label = QLabel(text)
        font = label.font()
        font.setBold(True)
        label.setFont(font)
        return label

    @staticmethod
    def _vline() -> QFrame:
        line = QFrame()
        line.setFrameShape(QFrame.Shape.VLine)
        line.setFrameShadow(QFrame.Shadow.Plain)
        line.setStyleSheet("color:#d8d8d8;")
        return line


    @staticmethod
    def _spin_box(*args) -> QSpinBox:
        return form_field(spin_box(*args), min_width=60)

    @staticmethod
    def _double_box(*args) -> QDoubleSpinBox:
        return form_field(double_spin_box(*args), min_width=60)

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
        self.task.currentIndexChanged.connect(lambda _: self.repetitions.setEnabled(self.task.currentData() == "train"))
        self.repetitions.setEnabled(False)
        self.follow.toggled.connect(self._follow_toggled)
        self.follow_minutes.valueChanged.connect(lambda v: self.plot.set_follow(self.plot.follow, v))
        self.plot.followChanged.connect(self._plot_follow_changed)
        self.all_button.clicked.connect(self._show_all)
        self.clear_button.clicked.connect(self.clear_plot)
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
        self.progress.setRange(0, 0)

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
        self.connection.call(job, lambda r: self._started(r, slot, params), self._start_failed)
        self._update_enabled()

    def stop(self) -> None:
        if not self.is_connected():
            return

        def done(state):
            self.show_message(f"Stopped ({state}).", "info")
            self.operationFinished.emit("stop", True, state)

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

        self.progress.setRange(0, 0)
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

        self.progress.setRange(0, 0)
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
    def start_params(self) -> dict:
        voltage = self.voltage.value()
        current = self.current.value()
        series = self.series_spin.value()
        return {"task": self.task.currentData(), "repetitions": self.repetitions.value(),
                "capacity_mah": float(self.capacity.value()), "current_a": current if current > 0 else None,
                "voltage_v": voltage if voltage > 0 else None, "series": series if series > 0 else None,
                "sensor": self.sensor.isChecked()}

    def set_start_params(self, task: str | None = None, repetitions: int | None = None,
                         capacity_mah: float | None = None, current_a: float | None = None,
                         voltage_v: float | None = None, series: int | None = None,
                         sensor: bool | None = None) -> None:
        if task is not None:
            self.task.setCurrentIndex(self.task.findData(task))
        if repetitions is not None:
            self.repetitions.setValue(int(repetitions))
        if capacity_mah is not None:
            self.capacity.setValue(int(capacity_mah))
        if current_a is not None:
            self.current.setValue(float(current_a))
        if voltage_v is not None:
            self.voltage.setValue(float(voltage_v))
        if series is not None:
            self.series_spin.setValue(int(series))
        if sensor is not None:
            self.sensor.setChecked(bool(sensor))

    def slot_names(self) -> list[str]:
        return [s.name for s in self._slots]

    def message_text(self) -> str:
        return self.message.text()

    def virtual_eeprom_path(self) -> Path:
        """Where the built-in virtual charger keeps its EEPROM: like a real charger, it still
        holds its macros after a disconnect (and the next time ZUML Studio starts)."""
        return self.session_dir / VIRTUAL_EEPROM

    def add_named_batteries(self) -> None:
        """Offer the saved fitted batteries (docs/fit.md) after the chemistries."""
        from ...sim.batteries import battery_names
        for name in battery_names():
            if self.v_chem.findData(NAMED_BATTERY + name) < 0:
                self.v_chem.addItem(f"{name} (fitted)", NAMED_BATTERY + name)

    def virtual_battery(self) -> str:
        """``CHEM:MAH:CELLS`` for the built-in virtual charger: the chemistry field, or the editor
        macro's AKK_TYPE, or NiMh; ``battery:NAME`` for a saved fitted battery."""
        chem = self.v_chem.currentData()
        if isinstance(chem, str) and chem.startswith(NAMED_BATTERY):
            return chem
        if chem is None:
            chem = DEFAULT_BATTERY[0]
            got = self._get_record()
            if got is not None:
                declared = record_chemistry(got[0])
                if declared in _chemistry_names():
                    chem = declared
        return f"{chem}:{self.v_mah.value()}:{self.v_cells.value()}"

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
        self.progress.setRange(0, max(1, total))
        self.progress.setValue(min(done, total))
        verbs = {"read": "reading", "write": "writing", "verify": "verifying"}
        self.progress.setToolTip(f"{verbs.get(stage, stage)} {done} of {total} bytes")

    def _progress_done(self) -> None:
        self.progress.setRange(0, 1)
        self.progress.setValue(0)

    # -- flash --------------------------------------------------------------------------------
    def _flashed(self, answer) -> None:
        if isinstance(answer, _Unsafe):
            self._progress_done()
            if confirm_unsafe(self, "Flash", answer.problems):
                self.flash(force=True)
            else:
                self._flash_done(False, "Not flashed: " + answer.summary())
            return
        merged, result = answer
        self._progress_done()
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
        self.result_label.setText(text)
        self.result_label.setStyleSheet(f"color:{COLORS['ok' if ok else 'error']};")
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
            if not unfit and confirm_unsafe(self, "Start", value):
                self.start(slot, force=True)
                return
            text = (f"Not started: the safety check forbids {name}:\n"
                    + "\n".join(f"• {line}" for line in value))
            self._start_done(False, text)
            return
        self._run_name = value
        self.plot.set_series_count(params["series"] or 1)
        if not self.plot.follow:
            self.follow.setChecked(True)
        self._start_done(True, f"Started {value} (slot {slot}): {params['task']}."
                         + "".join(f"\n⚠ {w}" for w in warnings))

    def _start_failed(self, exc) -> None:
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
            self.show_message(f"Read back after the lost link: the charger holds neither the new image nor the "
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
        self.message.setStyleSheet(f"color:{COLORS.get(kind, COLORS['info'])};")
        self.message.setToolTip(text if len(text) > 80 else "")
        self.statusMessage.emit(text)

    def _show_image(self, image: bytes) -> None:
        self._image = bytes(image)
        try:
            found = slots(self._image)
            used = used_bytes(self._image)
            broken = ""
        except Exception as exc:   # noqa: BLE001 - a broken record list
            found, used, broken = [], 0, str(exc)
        self._slots = found
        self.table.setRowCount(len(found))
        for row, s in enumerate(found):
            check = "ok" if s.ok else "BAD"
            values = (str(s.index), s.name, str(len(s.record)), record_chemistry(s.record) if s.ok else "?", check)
            for col, value in enumerate(values):
                item = QTableWidgetItem(value)
                if col in (0, 2):
                    item.setTextAlignment(Qt.AlignmentFlag.AlignRight | Qt.AlignmentFlag.AlignVCenter)
                if col == 4 and not s.ok:
                    item.setForeground(Qt.GlobalColor.red)
                    item.setToolTip(str(s.error.message if s.error else ""))
                self.table.setItem(row, col, item)
        size = len(self._image)
        if broken:
            self.free_label.setText(f"<span style='color:{COLORS['error']};'>broken record list: {broken}</span>")
        else:
            self.free_label.setText(f"{size - used} of {size} bytes free · {len(found)} macro(s)")
        keep_flash = self.flash_slot.currentData()
        keep_run = self.run_slot.currentData()
        self.flash_slot.clear()
        self.flash_slot.addItem("By name", None)
        for s in found:
            self.flash_slot.addItem(f"Replace slot {s.index} ({s.name})", s.index)
        self.flash_slot.addItem(f"Append as slot {len(found)}", len(found))
        k = self.flash_slot.findData(keep_flash)
        self.flash_slot.setCurrentIndex(k if k >= 0 and keep_flash is not None and keep_flash < len(found) else 0)
        self.run_slot.clear()
        for s in found:
            self.run_slot.addItem(f"{s.index}: {s.name}", s.index)
        want = self._flashed_slot if self._flashed_slot is not None and self._flashed_slot < len(found) else keep_run
        k = self.run_slot.findData(want)
        if k >= 0:
            self.run_slot.setCurrentIndex(k)
        self._update_enabled()

    def _table_selected(self) -> None:
        rows = self.table.selectionModel().selectedRows()
        if rows:
            k = self.run_slot.findData(rows[0].row())
            if k >= 0:
                self.run_slot.setCurrentIndex(k)

    def _show_passport(self, passport, error: str = "") -> None:
        if passport is None:
            text = error or ("no passport chip" if self.is_connected() else "—")
            self.pp_labels["serial"].setText(text)
            self.pp_labels["serial"].setToolTip(error)
            for key in ("type", "limits"):
                self.pp_labels[key].setText("—")
            return
        vendor = f" · {printable(passport.vendor)}" if passport.vendor else ""
        odd = passport.unprintable_fields
        self.pp_labels["serial"].setText(f"{printable(passport.serial) or '—'}{vendor}" + (" ⚠" if odd else ""))
        self.pp_labels["serial"].setToolTip(
            f"serial · vendor. ⚠ The {' and '.join(odd)} hold non-printable bytes (shown as \\xNN): "
            "a damaged or forged passport" if odd else "serial · vendor")
        self.pp_labels["serial"].setStyleSheet(f"color:{COLORS['warn']};" if odd else "")
        self.pp_labels["type"].setText(f"{passport.type_name} · TEMP {passport.temp} °C")
        v = f"{passport.v_limit} V" if passport.v_limit else "V not set"
        a = f"{passport.a_limit} A" if passport.a_limit else "A not set"
        err = (f" · ERR {passport.err}" if passport.err else "") + \
            (f" · CRIT {passport.crit}: not fit for use" if passport.crit else "")
        self.pp_labels["limits"].setText(f"{v} · {a}{err}")

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
        if tel is not None:
            t = "—" if tel.temp_c is None else f"{tel.temp_c:.1f} °C"
            tc = "—" if tel.heatsink_c is None else f"{tel.heatsink_c:.1f} °C"
            self.readings.setText(
                f"<span style='color:#1f4e9c;'><b>{tel.voltage_v:.3f} V</b></span>&nbsp;&nbsp;"
                f"<span style='color:#23803a;'><b>{tel.current_a:+.3f} A</b></span>&nbsp;&nbsp;"
                f"<span style='color:#d0481c;'>T {t}</span>&nbsp;&nbsp;"
                f"<span style='color:#7b5ea7;'>Tc {tc}</span>&nbsp;&nbsp;"
                f"in {tel.mah_in:.0f} mAh · out {tel.mah_out:.0f} mAh")
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
            self.result_label.setText(f"<span style='color:{COLORS['warn']};'>{reason}.</span>")
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
        self.start_button.setEnabled(idle and bool(self._slots))
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
        self._open_session_log(cells=None)
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
        self.info_label.setStyleSheet(f"color:{COLORS['warn' if bad else 'info']};")

    def _on_monitor_closed(self, error: str) -> None:
        link, self.monitor.link = self.monitor.link, None
        self._stop_replay_link()
        self._close_session_log()
        self._set_state_disconnected()
        self.info_label.setStyleSheet(f"color:{COLORS['info']};")
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

    def _follow_toggled(self, on: bool) -> None:
        self.plot.set_follow(on, self.follow_minutes.value())

    def _plot_follow_changed(self, on: bool) -> None:
        if self.follow.isChecked() != on:
            self.follow.blockSignals(True)
            self.follow.setChecked(on)
            self.follow.blockSignals(False)

    def _show_all(self) -> None:
        self.follow.setChecked(False)
        self.plot.show_all()

    # ================================================================ session CSV
    def _open_session_log(self, cells: int | None = 0) -> None:
        self._close_session_log()
        try:
            self._log = SessionLog(session_path(self.session_dir), cells=cells)
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
        path, _ = QFileDialog.getSaveFileName(self, "Back up the charger's EEPROM", "eeprom-backup.bin",
                                              "EEPROM images (*.bin);;All files (*)")
        if path:
            self.backup(path)

    def _restore_clicked(self) -> None:
        path, _ = QFileDialog.getOpenFileName(self, "Restore an EEPROM image", "",
                                              "EEPROM images (*.bin);;All files (*)")
        if path:
            self.restore(path)

    def closeEvent(self, event) -> None:  # noqa: N802
        self.shutdown()
        super().closeEvent(event)
