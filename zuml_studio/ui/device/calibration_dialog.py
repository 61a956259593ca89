"""The device panel's Calibrate…: the procedure of docs/firmware.md (*Calibration*) for an iMAX B6 running
the ZUML firmware, driven by device/zuml/calibration.py on the panel's connection. The voltages are entered
first; each current is asked while the charger holds it (the worker waits for the user's reading)."""
from __future__ import annotations

import threading

from PySide6.QtCore import Signal
from PySide6.QtWidgets import (QDialog, QDialogButtonBox, QDoubleSpinBox, QFormLayout, QHBoxLayout, QLabel,
                               QLineEdit, QPlainTextEdit, QPushButton, QVBoxLayout, QWidget)

from ...device.zuml.calibration import CHARGE, INPUTS, CalibrationError, Calibrator, parse_cells
from ...i18n import _

MAX_MA = 5000.0

def procedure() -> str:
    return "<ol>" + "".join(f"<li>{step}</li>" for step in (
        _("Connect a Li pack (2 to 6 cells) to the output and its balance lead to the balance port; power the "
          "charger; stop any macro."),
        _("Measure the pack at the output, the supply and each cell with your multimeter and enter them below "
          "(supply 0 or no cells: those inputs are kept)."),
        _("Put an ammeter in series with the pack. The charger then charges at about 100 and 1000 mA and "
          "discharges at about 50 and 300 mA: at each, enter what the ammeter reads (within a minute: the "
          "charger switches the current off after 60 s)."),
    )) + "</ol>"


class _GuiMeter:
    """The user's readings: the voltages from the form, the currents asked on the GUI thread while the
    worker waits."""

    def __init__(self, dialog: CalibrationDialog, pack_mv: float, supply_mv: float | None,
                 cells_mv: list[float] | None):
        self.dialog = dialog
        self._pack, self._supply, self._cells = pack_mv, supply_mv, cells_mv
        self._answered = threading.Event()
        self._answer: float | None = None

    def pack_mv(self) -> float:
        return self._pack

    def supply_mv(self) -> float | None:
        return self._supply

    def cells_mv(self) -> list[float] | None:
        return self._cells

    def current_ma(self, mode: int, asked_ma: int) -> float:
        self._answered.clear()
        what = _("charging") if mode == CHARGE else _("discharging")
        self.dialog.askCurrent.emit(_("The charger is {what} at about {ma} mA: what does the ammeter read?").format(
            what=what, ma=asked_ma))
        self._answered.wait()
        if self._answer is None:
            raise CalibrationError(_("cancelled: nothing was written"))
        return self._answer

    def answer(self, value: float | None) -> None:
        self._answer = value
        self._answered.set()


class CalibrationDialog(QDialog):
    askCurrent = Signal(str)        # from the worker: show the question, wait for the reading
    said = Signal(str)

    def __init__(self, connection, parent: QWidget | None = None):
        super().__init__(parent)
        self.setObjectName("calibrationDialog")
        self.setWindowTitle(_("Calibrate the Charger"))
        self.connection = connection
        self.meter: _GuiMeter | None = None
        self.job = 0
        layout = QVBoxLayout(self)
        self.status = QLabel()          # "connect first" until there is a charger to calibrate
        self.status.setObjectName("calibrationStatus")
        self.status.setWordWrap(True)
        layout.addWidget(self.status)
        steps = QLabel(procedure())
        steps.setWordWrap(True)
        layout.addWidget(steps)

        form = QFormLayout()
        self.pack = self._volts(60.0)
        form.addRow(_("Pack at the output (V):"), self.pack)
        self.supply = self._volts(30.0)
        form.addRow(_("Supply (V, 0: keep):"), self.supply)
        self.cells = QLineEdit()
        self.cells.setPlaceholderText(_("e.g. 3.912, 3.920, 3.905 (empty: keep)"))
        form.addRow(_("Cells, cell 1 first (V):"), self.cells)
        layout.addLayout(form)

        self.question = QLabel()
        self.question.setWordWrap(True)
        self.reading = QLineEdit()      # empty at every question: never the previous step's reading
        self.reading.setPlaceholderText(_("mA, as the ammeter reads"))
        self.reading.setMinimumWidth(self.reading.fontMetrics().horizontalAdvance(self.reading.placeholderText()) + 24)
        self.use_reading = QPushButton(_("Use This Reading"))
        row = QHBoxLayout()
        row.addWidget(self.question, 1)
        row.addWidget(self.reading)
        row.addWidget(self.use_reading)
        layout.addLayout(row)

        self.log = QPlainTextEdit()
        self.log.setReadOnly(True)
        layout.addWidget(self.log, 1)
        buttons = QDialogButtonBox(QDialogButtonBox.StandardButton.Close)
        self.start_button = buttons.addButton(_("&Calibrate"), QDialogButtonBox.ButtonRole.ActionRole)
        self.start_button.clicked.connect(self.start)
        buttons.rejected.connect(self.reject)
        layout.addWidget(buttons)
        self.use_reading.clicked.connect(self._use_reading)
        self.reading.returnPressed.connect(self._use_reading)
        self.reading.textChanged.connect(lambda _text: self.use_reading.setEnabled(self._typed_ma() is not None))
        self.askCurrent.connect(self._ask)
        self.said.connect(self.log.appendPlainText)
        self._asking(False)
        connection.connected.connect(self._connection_changed)
        connection.disconnected.connect(self._connection_changed)
        self._connection_changed()
        self.resize(680, 560)

    def _connection_changed(self, *_args) -> None:
        """Nothing is asked before there is a charger: the form waits for the connection."""
        connected = self.connection.is_connected()
        self.status.setText("" if connected else
                            _("Connect to the charger first (an iMAX B6 with the ZUML firmware)."))
        self.status.setVisible(not connected)
        for widget in (self.pack, self.supply, self.cells):
            widget.setEnabled(connected)
        self.start_button.setEnabled(connected and self.meter is None)

    @staticmethod
    def _volts(top: float) -> QDoubleSpinBox:
        box = QDoubleSpinBox()
        box.setRange(0.0, top)
        box.setDecimals(3)
        box.setSuffix(" V")
        return box

    def busy(self) -> bool:
        return self.meter is not None

    def _asking(self, on: bool) -> None:
        self.reading.clear()
        for widget in (self.question, self.reading):
            widget.setEnabled(on)
        self.use_reading.setEnabled(False)
        if not on:
            self.question.setText(_("The currents are asked here while the charger holds them."))

    def _ask(self, question: str) -> None:
        self.question.setText(question)
        self._asking(True)
        self.reading.setFocus()

    def _typed_ma(self) -> float | None:
        try:
            value = float(self.reading.text().strip().replace(",", "."))
        except ValueError:
            return None
        return value if 0 < value <= MAX_MA else None

    def _use_reading(self) -> None:
        value = self._typed_ma()
        if value is not None and self.reading.isEnabled():
            self._answer(value)

    def _answer(self, value: float | None) -> None:
        self._asking(False)
        if self.meter is not None:
            self.meter.answer(value)

    def cells_mv(self) -> list[float] | None:
        try:
            return parse_cells(self.cells.text())
        except CalibrationError as exc:
            raise CalibrationError(_("the cells: {reason}").format(reason=exc)) from None

    def start(self) -> None:
        self.log.clear()
        if not self.connection.is_connected():
            self.log.appendPlainText(_("Connect to the charger first (an iMAX B6 with the ZUML firmware)."))
            return
        try:
            cells = self.cells_mv()
            if self.pack.value() <= 0:
                raise CalibrationError(_("enter the pack's voltage as the meter reads it"))
        except CalibrationError as exc:
            self.log.appendPlainText(str(exc))
            return
        self.meter = _GuiMeter(self, self.pack.value() * 1000, self.supply.value() * 1000 or None, cells)
        meter = self.meter
        self.start_button.setEnabled(False)

        def job(client, _progress):
            calibrator = Calibrator(client, self.said.emit)
            block = calibrator.run(meter)
            return block, calibrator.measure()
        self.job = self.connection.call(job, self._done, self._failed)

    def _done(self, result) -> None:
        block, readings = result
        self._finish(_("Calibrated and stored. The charger now reads:"))
        for name, reading, (zero, full) in zip(INPUTS, readings, block.pairs):
            self.log.appendPlainText(f"  {name:<12} {reading.value:>7}   zero {zero:>5}  full {full:>5}")

    def _failed(self, exc) -> None:
        self._finish(_("Stopped: {reason}").format(reason=exc))

    def _finish(self, line: str) -> None:
        self.meter = None
        self._asking(False)
        self._connection_changed()
        self.log.appendPlainText(line)

    def reject(self) -> None:
        if self.meter is not None:          # the worker waits for a reading: cancel it, the output goes off
            self.meter.answer(None)
            return
        super().reject()
