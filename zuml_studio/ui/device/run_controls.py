"""The run: which slot, the task and the values entered at start, Start/Stop and the run's
state. It owns the start parameters."""
from __future__ import annotations

from PySide6.QtWidgets import QCheckBox, QComboBox, QGridLayout, QHBoxLayout, QLabel, QPushButton, QVBoxLayout, QWidget

from ...lang.eeprom import Slot
from .device_style import DEFAULT_BATTERY, ElidedLabel, field_double, field_spin, heading

START_TIP = "Check the battery's passport, then start the slot's macro"
TASKS = (("charge", "Charge"), ("discharge", "Discharge"), ("train", "Train"))


class RunControls(QWidget):
    def __init__(self, parent: QWidget | None = None):
        super().__init__(parent)
        self.run_slot = QComboBox()
        self.run_slot.setObjectName("runSlot")
        self.run_slot.setToolTip("The slot to start (default: the macro just flashed)")
        self.task = QComboBox()
        self.task.setObjectName("runTask")
        for key, text in TASKS:
            self.task.addItem(text, key)
        self.task.setToolTip("charge, discharge, or training (discharge + charge, repeated)")
        self.capacity = field_spin(10, 65000, DEFAULT_BATTERY[1], " mAh", "the capacity entered at start")
        self.capacity.setSingleStep(100)
        self.current = field_double(0.0, 50.0, 2.0, " A", 2, 0.1, "the current entered at start "
                                    "(CONSTANT_I=INPUT; limits a CONSTANT_V phase); — none")
        self.current.setSpecialValueText("—")
        self.series_spin = field_spin(0, 255, DEFAULT_BATTERY[2], " cells", "cells in series entered at start; "
                                      "— none")
        self.series_spin.setSpecialValueText("—")
        self.voltage = field_double(0.0, 65.0, 0.0, " V", 2, 0.1, "the voltage entered at start (INPUT); — none")
        self.voltage.setSpecialValueText("—")
        self.repetitions = field_spin(1, 255, 1, "", "training: discharge+charge this many times")
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

        b = QVBoxLayout(self)
        b.setContentsMargins(0, 0, 0, 0)
        b.setSpacing(3)
        b.addWidget(heading("Run"))
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
        self.task.currentIndexChanged.connect(lambda _: self.repetitions.setEnabled(self.task.currentData() == "train"))
        self.repetitions.setEnabled(False)

    def set_slots(self, found: list[Slot], prefer: int | None) -> None:
        """Offer ``found``; select ``prefer`` (the slot just flashed), else keep the choice."""
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
