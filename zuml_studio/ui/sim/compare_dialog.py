"""Simulate > Compare with Log…: a real charge log and the simulation of the open macro (or the
fitted model) on the same axes, their difference below, and the figures; Fit fits the model to
the log, Save Battery… keeps the fit as a named battery for the Model box."""
from __future__ import annotations

from collections.abc import Callable

import numpy as np
from PySide6.QtCore import Qt, Signal
from PySide6.QtWidgets import (QComboBox, QDialog, QFileDialog, QFormLayout, QHBoxLayout,
                               QInputDialog, QLabel, QPushButton, QSizePolicy, QSpinBox, QVBoxLayout, QWidget)

from ...file_errors import FileReadError
from ...i18n import _
from ...logs import LogFormatError, gaps
from ...sim.batteries import BatteryFileError, save_battery
from ...sim.chemistry import chemistry_names
from ...sim.curve import DIRECTIONS, Curve, CurveError, log_directions, read_curve_and_log
from ...sim.fit import FitResult, guess_series
from ...sim.fit_cells import taps_per_cell
from ...sim.fit_discharge import fit_curve
from ...sim.fit_predict import predict_own, prediction_line, trust_words
from ...sim.fit_report import figure_lines, param_lines, resistance_words
from ...sim.interpreter import StartError
from ..base import theme
from ..base.background import BackgroundCall
from ..plots.cell_curves import legend_name
from .compare_plots import ComparePlots, cell_role
from ..plots.plot_data import cell_curves


CELLS_DIFFER_V = 0.002     # cells within this of each other all along: one line would do


class CompareDialog(QDialog):
    # A fit or a simulation ended (its figures or its error shown); they run off the GUI thread.
    workDone = Signal()

    def __init__(self, record: Callable[[], bytes | None], parent: QWidget | None = None,
                 on_saved: Callable[[], None] | None = None, chemistry: str | None = None):
        super().__init__(parent)
        self.setWindowTitle(_("Compare with Log"))
        self.setObjectName("compareDialog")
        self._record, self._on_saved = record, on_saved
        self.curve: Curve | None = None
        self._log = None             # the whole log the curve came from: its rests give the pack's resistance
        self.fitted: FitResult | None = None
        self._job: BackgroundCall | None = None

        self.log_label = QLabel(_("no log chosen"))
        self.log_label.setTextInteractionFlags(Qt.TextSelectableByMouse)
        open_button = QPushButton(_("Log…"))
        open_button.clicked.connect(self._choose)
        self.chemistry = QComboBox()
        for name in chemistry_names():
            self.chemistry.addItem(name, name)
        self.chemistry.setCurrentIndex(max(0, self.chemistry.findData(chemistry or "NiMh")))
        # The cell count is guessed with the chosen model (a LiPo log read as NiMH is 12 cells, not 4).
        self.chemistry.currentIndexChanged.connect(self._guess_cells)
        # A cycle log holds a charge and a discharge: each is fitted and compared on its own.
        self.direction = QComboBox()
        for name in DIRECTIONS:
            self.direction.addItem(_(name), name)
        self.direction.setEnabled(False)
        self.direction.setToolTip(_("A log holding both: its charge or its discharge"))
        self.direction.activated.connect(lambda _index: self.load_log(self._path, self.direction.currentData()))
        self._path = ""
        self.cells = QSpinBox()
        self.cells.setRange(1, 255)
        self.capacity = QSpinBox()
        self.capacity.setRange(0, 65534)
        self.capacity.setSuffix(" mAh")
        self.capacity.setSpecialValueText(_("from the log"))
        self.simulate_button = QPushButton(_("Simulate Macro"))
        self.simulate_button.setToolTip(_("Run the open macro from the log's start and compare"))
        self.simulate_button.clicked.connect(self.compare_macro)
        self.fit_button = QPushButton(_("Fit"))
        self.fit_button.setToolTip(_("Fit the battery model to the log (seconds)"))
        self.fit_button.clicked.connect(self.fit_log)
        self.save_button = QPushButton(_("Save Battery…"))
        self.save_button.setToolTip(_("Keep the fitted model as a named battery for the Model box"))
        self.save_button.clicked.connect(self.save_fitted)
        for b in (self.simulate_button, self.fit_button, self.save_button):
            b.setEnabled(False)

        form = QFormLayout()
        # The boxes at their own width; only the log's path takes the dialog's.
        form.setFieldGrowthPolicy(QFormLayout.FieldGrowthPolicy.ExpandingFieldsGrow)
        self.log_label.setSizePolicy(QSizePolicy.Policy.Expanding, QSizePolicy.Policy.Preferred)
        row = QHBoxLayout()
        row.addWidget(open_button)
        row.addWidget(self.log_label, 1)
        form.addRow(_("Log"), row)
        form.addRow(_("Direction"), self.direction)
        form.addRow(_("Chemistry"), self.chemistry)
        form.addRow(_("Cells"), self.cells)
        form.addRow(_("Capacity"), self.capacity)

        self.plots = ComparePlots()
        self.v_plot, self.d_plot = self.plots.v_plot, self.plots.d_plot

        self.figures = QLabel(_("Choose a charge log, then Simulate Macro or Fit."))
        self.figures.setTextInteractionFlags(Qt.TextSelectableByMouse)
        self.figures.setWordWrap(True)
        buttons = QHBoxLayout()
        for b in (self.simulate_button, self.fit_button, self.save_button):
            buttons.addWidget(b)
        buttons.addStretch(1)
        layout = QVBoxLayout(self)
        layout.addLayout(form)
        layout.addWidget(self.plots, 1)
        layout.addWidget(self.figures)
        layout.addLayout(buttons)
        self.resize(900, 640)

    # -- actions -----------------------------------------------------------------------
    def _choose(self) -> None:
        path = QFileDialog.getOpenFileName(self, _("Charge Log"), "", _("Logs") + " (*.txt *.csv *.osd *.lov);;"
                                           + _("All files") + " (*)")[0]
        if path:
            self.load_log(path)

    def load_log(self, path: str, direction: str | None = None) -> bool:
        try:
            self.curve, self._log = read_curve_and_log(path, direction)
        except (FileReadError, LogFormatError, CurveError) as exc:
            self._error(str(exc))
            return False
        self._path = path
        self.direction.setCurrentIndex(self.direction.findData(self.curve.direction))
        self.direction.setEnabled(self._log is not None and len(log_directions(self._log)) > 1)
        self.fitted = None
        named = [c for c in chemistry_names() if c.lower() == self.curve.chemistry.lower()]
        if named:
            self.chemistry.setCurrentIndex(self.chemistry.findData(named[0]))   # iCharger logs name it
        if self.curve.direction == "charge":
            what = _("{minutes} min of charge, {mah} mAh in")
        else:
            what = _("{minutes} min of discharge, {mah} mAh out")
        mah = self.curve.mah[-1] if self.curve.direction == "charge" else self.curve.delivered_mah[-1]
        self.log_label.setText(f"{path}  ({what.format(minutes=f'{self.curve.t[-1] / 60:.0f}', mah=f'{mah:.0f}')})")
        self._guess_cells()
        self.simulate_button.setEnabled(True)
        self.fit_button.setEnabled(True)
        self.save_button.setEnabled(False)
        self._draw(None, None, "")
        self.figures.setText(_("Simulate Macro or Fit."))
        return True

    def _guess_cells(self) -> None:
        if self.curve is not None:
            self.cells.setValue(guess_series(self.curve, self.chemistry.currentData()))

    def fit_log(self) -> None:
        """Fit the model to the log (seconds): off the GUI thread, the figures when it ends."""
        if self.curve is None or self._job is not None:
            return
        curve, chemistry, cells = self.curve, self.chemistry.currentData(), self.cells.value()
        def job() -> tuple[FitResult, dict | None]:
            fitted = fit_curve(curve, chemistry, cells)
            return fitted, predict_own(fitted)

        self._run(_("Fitting the model to the log…"), job, self._fitted)

    def _fitted(self, made: tuple[FitResult, dict | None]) -> None:
        fitted, prediction = made
        self.fitted = fitted
        self._draw(self.curve.t, fitted.run.v, _("fitted model"))
        params = "; ".join(param_lines(fitted.params, fitted.battery, fitted.figures))
        lines = figure_lines(fitted.figures) + [_("fitted: {parameters}").format(parameters=params)]
        # What the fitted model predicts on the log's own program, and whether to trust it (sim/fit_predict.py).
        if prediction is not None:
            lines += [prediction_line(prediction)] + ([trust_words(prediction)] if trust_words(prediction) else [])
        self.figures.setText("\n".join(lines))
        self.save_button.setEnabled(True)

    def compare_macro(self) -> None:
        from ...sim.compare import compare
        from ...sim.measured_r import measure_curve

        record = self._record()
        if self.curve is None or self._job is not None:
            return
        if record is None:
            self._error(_("the open macro has errors: fix them to compare it with the log"))
            return
        curve, chemistry, cells = self.curve, self.chemistry.currentData(), self.cells.value()
        capacity, log = self.capacity.value() or None, self._log
        self._run(_("Simulating the macro from the log's start…"),
                  lambda: compare(curve, record, chemistry, cells, capacity,
                                  measured_r=measure_curve(log, curve, cells)), self._compared)

    def _compared(self, result) -> None:
        self._draw(result.t, result.run.v, _("simulation"))
        said = resistance_words(result.report)
        self.figures.setText("\n".join(([said] if said else []) + figure_lines(result.report)))

    def _run(self, what: str, fn, on_done) -> None:
        for b in (self.simulate_button, self.fit_button, self.save_button):
            b.setEnabled(False)
        self.figures.setText(what)
        self._job = job = BackgroundCall(fn, self)
        job.done.connect(on_done)
        job.failed.connect(self._failed)
        job.finished.connect(self._job_ended)
        job.start()

    def _failed(self, exc: Exception) -> None:
        expected = (StartError, ValueError, KeyError, ArithmeticError)
        self._error(str(exc) if isinstance(exc, expected)
                    else _("internal error: {error}").format(error=f"{type(exc).__name__}: {exc}"))

    def _job_ended(self) -> None:
        self._job = None
        self.simulate_button.setEnabled(self.curve is not None)
        self.fit_button.setEnabled(self.curve is not None)
        self.save_button.setEnabled(self.fitted is not None)
        self.workDone.emit()

    def closeEvent(self, event) -> None:  # noqa: N802
        if self._job is not None:       # a fit cannot be interrupted; it ends in seconds
            self._job.wait()
        super().closeEvent(event)

    def save_fitted(self) -> None:
        if self.fitted is None:
            return
        name, ok = QInputDialog.getText(self, _("Save Battery"), _("Name (e.g. 4S 2000 NiMH receiver pack):"))
        if ok and name.strip():
            self.save_as(name.strip())

    def save_as(self, name: str) -> bool:
        try:
            save_battery(name, self.fitted.battery, self.log_label.text())
        except (BatteryFileError, OSError) as exc:
            self._error(str(exc))
            return False
        self.figures.setText(self.figures.text() + "\n" + _("saved as '{name}'").format(name=name))
        if self._on_saved:
            self._on_saved()
        return True

    # -- drawing -----------------------------------------------------------------------
    def _draw(self, t: np.ndarray | None, v_model: np.ndarray | None, label: str) -> None:
        lines = []
        if self.curve is not None:
            n = self.cells.value()
            lines += self._cell_lines(n)
            lines.append((self.v_plot, self.curve.t / 60.0, self.curve.v / n, "real", _("log")))
            if t is not None and v_model is not None:
                real = np.interp(t, self.curve.t, self.curve.v)
                real[gaps.outside(self.curve.t, t)] = np.nan        # no difference where the log has no sample
                lines += [(self.v_plot, t / 60.0, v_model / n, "model", label),
                          (self.d_plot, t / 60.0, (v_model - real) / n * 1000.0, "diff", None)]
        self.plots.show_lines(lines)

    def _cell_lines(self, series: int) -> list:
        """The log's cells where it has a balance tap per cell of the pack and they differ, drawn under the
        pack's line as the simulator draws a pack's cells (each up to eight in its hue, else the lowest and
        the highest)."""
        if not taps_per_cell(self.curve, series):
            return []
        taps = self.curve.cells_v
        spread = np.nanmax(taps, axis=1) - np.nanmin(taps, axis=1)
        if not np.any(spread >= CELLS_DIFFER_V):
            return []                       # equal cells: N lines on the pack's own, nothing to read
        data = {f"cell{k}_v": taps[:, k - 1] for k in range(1, series + 1)}
        minutes = self.curve.t / 60.0
        return [(self.v_plot, minutes, data[c.column], cell_role(c), legend_name(c))
                for c in cell_curves(data, tuple(data))]

    def _error(self, message: str) -> None:
        self.figures.setText(f"<span style='color:{theme.colours(self.palette()).error}'>{message}</span>")
