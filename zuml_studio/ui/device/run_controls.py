"""The run: which slot, the task and the values entered at start, Start/Stop and the run's
state. It owns the start parameters, the macro started last and whether it runs."""
from __future__ import annotations

from PySide6.QtCore import QEventLoop, QTimer, Signal
from PySide6.QtWidgets import QCheckBox, QComboBox, QGridLayout, QHBoxLayout, QLabel, QPushButton, QVBoxLayout, QWidget

from ...device.errors import DeviceError
from ...device.passport import fitness_warnings
from ...i18n import N_, _
from ...lang.eeprom import Slot
from ...safety import judge, named_template
from ...sim.program import TASK_LABELS, TASK_WORDS, Program
from ...sim.reasons import lead_cells_text, shown_reason
from ...sim.start_check import start_warnings
from ..plots.stacked_plot import band_label
from ..base.timefmt import hmmss
from . import unsafe_dialog
from .connection import DeviceConnection, describe_error
from .device_style import DEFAULT_BATTERY, ElidedCombo, ElidedLabel, field_double, field_spin, heading

START_TIP = N_("Check the battery's passport, then start the slot's macro")


class RunControls(QWidget):
    message = Signal(str, str)                  # text, kind
    startFinished = Signal(bool, str)           # START done (or refused: the reasons)
    operationFinished = Signal(str, bool, str)  # "stop", ok, message
    runStarting = Signal()                      # a START goes out: a new run begins
    runUndone = Signal()                        # ... and did not start
    runStarted = Signal(str, int)               # the macro's name, the cells entered (1 if none)
    passportRead = Signal(object)               # the passport START read (None: no chip)
    stopping = Signal()                         # STOP goes out
    changed = Signal()                          # what may be enabled changed

    def __init__(self, connection: DeviceConnection, parent: QWidget | None = None):
        super().__init__(parent)
        self.connection = connection
        self.slots: list[Slot] = []
        self.run_name = ""                      # the macro started last
        self.run_slot_index: int | None = None  # ... and its slot (None: started elsewhere)
        self.run_cells = (0, 0)                 # ... the cells entered and its SERIES (0: not known)
        self.running = False                    # it runs (started here, or the newest frame says so)
        self.charger_max_a: float | None = None
        self.run_slot = ElidedCombo()
        self.run_slot.setObjectName("runSlot")
        self.run_slot.setToolTip(_("The slot to start (default: the macro just flashed)"))
        self.task = QComboBox()
        self.task.setObjectName("runTask")
        for key, text in TASK_LABELS.items():
            self.task.addItem(_(text), key)
        self.task.setToolTip(_("charge, discharge, or training (discharge + charge, repeated)"))
        self.capacity = field_spin(10, 65000, DEFAULT_BATTERY[1], " mAh", _("the capacity entered at start"))
        self.capacity.setSingleStep(100)
        self.current = field_double(0.0, 50.0, 2.0, " A", 2, 0.1, _("the current entered at start "
                                    "(CONSTANT_I=INPUT; limits a CONSTANT_V phase); — none"))
        self.current.setSpecialValueText("—")
        self.series_spin = field_spin(0, 255, DEFAULT_BATTERY[2], _(" cells"), _("cells in series entered at start; "
                                      "— none"))
        self.series_spin.setSpecialValueText("—")
        self.voltage = field_double(0.0, 65.0, 0.0, " V", 2, 0.1, _("the voltage entered at start (INPUT); — none"))
        self.voltage.setSpecialValueText("—")
        self.repetitions = field_spin(1, 255, 1, "", _("training: discharge+charge this many times"))
        self.repetitions.setPrefix("× ")
        self.sensor = QCheckBox(_("T sensor"))
        self.sensor.setObjectName("runSensor")
        self.sensor.setChecked(True)
        self.sensor.setToolTip(_("a battery temperature sensor is connected"))
        self.start_button = QPushButton(_("Start"))
        self.start_button.setObjectName("startButton")
        self.start_button.setToolTip(_(START_TIP))
        self.stop_button = QPushButton(_("Stop"))
        self.stop_button.setObjectName("stopButton")
        self.stop_button.setToolTip(_("Stop the running macro"))
        self.run_label = ElidedLabel("")
        self.run_label.setObjectName("runState")
        # Room for the usual "running · C1 · 0:12:34": a run's state is not cut off at 1366 px.
        self.run_label.setMinimumWidth(self.run_label.fontMetrics().horizontalAdvance(
            _("running") + " · " + _("C{index}").format(index=10) + " · 0:00:00"))     # hmmss: one digit of hours

        b = QVBoxLayout(self)
        b.setContentsMargins(0, 0, 0, 0)
        b.setSpacing(3)
        b.addWidget(heading(_("Run")))
        grid = QGridLayout()
        grid.setHorizontalSpacing(4)
        grid.setVerticalSpacing(3)
        slot_label = QLabel(_("Slot"))
        slot_label.setBuddy(self.run_slot)
        grid.addWidget(slot_label, 0, 0)
        grid.addWidget(self.run_slot, 0, 1, 1, 2)
        grid.addWidget(self.sensor, 0, 3)
        rows = (((_("Task"), self.task), (_("Reps"), self.repetitions)),
                ((_("Capacity"), self.capacity), (_("Current"), self.current)),
                ((_("Cells"), self.series_spin), (_("Voltage"), self.voltage)))
        for r, pair in enumerate(rows, start=1):
            for c, (text, widget) in enumerate(pair):
                label = QLabel(text)
                label.setBuddy(widget)
                label.setToolTip(widget.toolTip())
                grid.addWidget(label, r, 2 * c)
                grid.addWidget(widget, r, 2 * c + 1)
        grid.setColumnStretch(1, 1)
        grid.setColumnStretch(3, 1)
        b.addLayout(grid)
        buttons = QHBoxLayout()
        buttons.setSpacing(4)
        buttons.addWidget(self.start_button)
        buttons.addWidget(self.stop_button)
        buttons.addWidget(self.run_label, 1)
        b.addLayout(buttons)
        self.task.currentIndexChanged.connect(
            lambda _i: self.repetitions.setEnabled(self.task.currentData() == "train"))
        self.repetitions.setEnabled(False)
        self.start_button.clicked.connect(lambda: self.start())
        self.stop_button.clicked.connect(self.stop)

    def set_slots(self, found: list[Slot], prefer: int | None) -> None:
        """Offer ``found``; select ``prefer`` (the slot just flashed), else keep the choice."""
        self.slots = list(found)
        keep = self.run_slot.currentData()
        self.run_slot.clear()
        for s in found:
            self.run_slot.addItem(f"{s.index}: {s.name}", s.index)
        want = prefer if prefer is not None and prefer < len(found) else keep
        k = self.run_slot.findData(want)
        if k >= 0:
            self.run_slot.setCurrentIndex(k)

    def select_slot(self, index: int) -> None:
        k = self.run_slot.findData(index)
        if k >= 0:
            self.run_slot.setCurrentIndex(k)

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

    # -- running ------------------------------------------------------------------------------
    def is_running(self) -> bool:
        """A macro runs on the connected charger (just started here, or as its newest frame says)."""
        return self.running and self.connection.is_connected()

    def set_enabled(self, connected: bool, idle: bool, monitor_reason: str = "") -> None:
        """``monitor_reason``: why a monitor-only charger cannot be started (then all is off)."""
        if monitor_reason:
            for w in (self.start_button, self.stop_button, self.run_slot):
                w.setEnabled(False)
            self.start_button.setToolTip(monitor_reason)
            return
        self.start_button.setEnabled(idle and bool(self.slots) and not self.is_running())
        self.start_button.setToolTip(
            _("{name} is running: Stop it first").format(name=self.run_name or _("A macro"))
            if self.is_running() else _(START_TIP))
        self.stop_button.setEnabled(connected)
        self.run_slot.setEnabled(connected)

    def follow(self, fresh, newest, finishes: list) -> bool:
        """Follow the charger's frames: ``fresh``, the newest frame since the last START or STOP
        (None: none yet), says whether the macro runs; ``newest`` (or None) shows its state;
        ``finishes``, the finish events not seen before with the phase that ended last, are said. True
        if ``running`` changed."""
        changed = fresh is not None and fresh.running != self.running
        if changed:
            self.running = fresh.running
        if newest is not None:
            self._show_state(newest)
        for ev, last in finishes:
            how = shown_reason(ev.detail, *self.run_cells) or _("end")
            if last is not None and last.reason and last.reason != ev.detail:
                # "end of macro" says only that the macro ran out: the last phase's end says which rule ended it
                how = _("{how}; last phase {phase}").format(how=how, phase=band_label(last))
            self.message.emit(_("{name} finished at {time}: {how}.").format(
                name=self.run_name or _("The macro"), time=hmmss(ev.time_s), how=how),
                "warn" if last is not None and last.warns else "ok")
        return changed

    def _show_state(self, tel) -> None:
        if tel.running:
            where = ((_("C{index}") if tel.section == "charge" else _("D{index}")).format(index=tel.phase)
                     if tel.section else "—")
            state = _("paused") if tel.paused else _("running")
            if tel.state:                   # a monitor-only charger's own word for it, as it sends it
                state += f" ({tel.state})"
            self.run_label.set_full_text(f"{state} · {where} · {hmmss(tel.time_s)}")
        else:
            self.run_label.set_full_text(_("{name} ended").format(name=self.run_name) if self.run_name
                                         else _("idle"))

    def start(self, slot: int | None = None) -> None:
        """START the macro in ``slot`` (default: the Slot field, which follows the last flash) with
        the task parameters; the safety check (chemistry limits, the battery's passport, with the
        values of the start template the macro names, read from the charger) runs here first: what
        it refuses does not start, its warnings are asked about once. ``startFinished``."""
        if not self.connection.is_connected():
            self._start_done(False, _("Connect to a charger first."))
            return
        if slot is None:
            slot = self.run_slot.currentData()
        if slot is None or not 0 <= slot < len(self.slots):
            self._start_done(False, _("There is no macro on the charger to start: Compile & Flash one first."))
            return
        if self.is_running():
            self._start_done(False, _("{name} is running: Stop it first, then Start.").format(
                name=self.run_name or _("A macro")))
            return
        params = self.start_params()
        record = self.slots[slot].record
        name = self.slots[slot].name
        charger_max = self.charger_max_a
        warned = record in self.connection.warned

        def job(client, progress):
            from ...lang.record import DecodeError
            from ...sim.interpreter import StartParams
            passport = client.passport_if_any()
            try:
                verdict = judge(record, passport, StartParams(**params),
                                templates=client.templates_named([named_template(record)]), charger_max_a=charger_max)
            except DecodeError:     # a record that does not decode: the charger refuses it
                verdict = None
            if verdict is not None and verdict.errors:
                return ("refused", list(verdict.errors), passport, [])
            if verdict is not None and verdict.warnings and not warned:
                return ("warned", list(verdict.warnings), passport, [])
            started = client.start(slot, params["task"], params["repetitions"], params["capacity_mah"],
                                   params["current_a"], params["voltage_v"], params["series"], params["sensor"])
            # What the charger does not refuse but the user should know: the battery's error count,
            # and values entered at start that the lint could not check (seed 001's -dV rates).
            warnings = (fitness_warnings(passport) if passport is not None else []) + \
                start_warnings(record, StartParams(**params))
            return ("started", started, passport, warnings)

        self.message.emit(_("Starting {name} (slot {slot})…").format(name=name, slot=slot), "info")
        self.runStarting.emit()
        declared = _declared_cells(record)
        self.connection.call(job, lambda r: self._started(r, slot, params, declared),
                             lambda exc: self._start_failed(exc, params["series"] or 0, declared))
        self.changed.emit()

    def _started(self, answer, slot: int, params: dict, declared: int) -> None:
        kind, value, passport, warnings = answer
        self.passportRead.emit(passport)
        name = self.slots[slot].name if slot < len(self.slots) else "?"
        if kind == "refused":
            self.runUndone.emit()
            self._start_done(False, unsafe_dialog.refusal_text(_("Not started: {name}").format(name=name), value))
            return
        if kind == "warned":
            self.runUndone.emit()
            if unsafe_dialog.confirm_warnings(self, _("Start"), value):
                self.connection.warned.add(self.slots[slot].record)
                self.start(slot)
            else:
                self._start_done(False, _("Not started: cancelled at the safety check's warnings."))
            return
        self.run_name = value
        self.run_slot_index = slot
        self.run_cells = (params["series"] or 0, declared)
        self.running = True
        self.runStarted.emit(value, params["series"] or 1)
        task = TASK_WORDS.get(params["task"])
        self._start_done(True, _("Started {name} (slot {slot}): {task}.").format(
            name=value, slot=slot, task=_(task) if task else params["task"])
            + "".join(f"\n⚠ {w}" for w in warnings))

    def _start_failed(self, exc, entered: int = 0, declared: int = 0) -> None:
        self.runUndone.emit()
        if isinstance(exc, DeviceError):    # the charger knows what its port shows; the PC knows what was asked
            exc.lines = [lead_cells_text(line, entered, declared) for line in exc.lines]
        self._start_done(False, describe_error(exc, "start"))

    def _start_done(self, ok: bool, text: str) -> None:
        self.message.emit(text, "ok" if ok else "error")
        self.changed.emit()
        self.startFinished.emit(ok, text)

    def stop(self) -> None:
        if not self.connection.is_connected():
            return

        def done(state):
            self.message.emit(_("Stopped ({state}).").format(state=state), "info")
            self.operationFinished.emit("stop", True, state)

        def failed(exc):
            text = describe_error(exc, "stop")
            self.message.emit(text, "error")
            self.changed.emit()
            self.operationFinished.emit("stop", False, text)

        # STOP goes before anything asked after it: a Start from now on finds the charger stopped
        # (should STOP fail, the next running frame says so again).
        self.running = False
        self.stopping.emit()
        self.changed.emit()
        self.connection.call(lambda client, progress: client.stop(), done, failed)

    def stop_and_wait(self, msecs: int = 5000) -> bool:
        """Send STOP and wait for the answer (closing during a run); True if the charger stopped."""
        if not self.connection.is_connected():
            return False
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


def _declared_cells(record: bytes) -> int:
    """The SERIES the macro on the charger declares (0: none, the cells entered count)."""
    from ...lang import opcodes as ops
    from ...lang.record import DecodeError
    try:
        return Program(record).intro.declarations.get(ops.SERIES.code) or 0
    except DecodeError:
        return 0
