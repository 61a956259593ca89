"""The live view: the readout of the newest frame (two lines over the plot), following the last minutes, All, Clear,
and the live plot below them."""
from __future__ import annotations

from PySide6.QtCore import Qt, Signal
from PySide6.QtWidgets import QCheckBox, QComboBox, QHBoxLayout, QLabel, QSizePolicy, QToolButton, QVBoxLayout, QWidget

from ..plot_cursor import CursorReadout
from .device_style import field_spin
from .live_plot import DEFAULT_FOLLOW_MIN, LivePlot, LiveSeries


RUNS_TIP = "Each Start begins a new run, plotted from 0; earlier runs stay here to look at"


class LiveView(QWidget):
    runChosen = Signal(int)             # index in the run chooser (the last: the current run)

    def __init__(self, series: LiveSeries, parent: QWidget | None = None):
        super().__init__(parent)
        self.plot = LivePlot(series)
        self.plot.setMinimumWidth(280)
        self.readings = QLabel("")
        self.readings.setObjectName("readings")
        self.readings.setTextInteractionFlags(Qt.TextInteractionFlag.TextSelectableByMouse)
        self.readings.setSizePolicy(QSizePolicy.Policy.Ignored, QSizePolicy.Policy.Preferred)
        self.readings.setText("<br>")      # its two lines from the start: the plot does not jump at the first frame
        self.follow = QCheckBox("Follow last")
        self.follow.setObjectName("followCheck")
        self.follow.setChecked(True)
        self.follow.setToolTip("Keep the newest minutes in view; zooming or panning the plot turns this off")
        self.follow_minutes = field_spin(1, 24 * 60, DEFAULT_FOLLOW_MIN, " min", "how much of the run to keep in view")
        self.follow_minutes.setMaximumWidth(80)
        self.all_button = QToolButton()
        self.all_button.setText("All")
        self.all_button.setToolTip("Show the whole session (stops following)")
        self.clear_button = QToolButton()
        self.clear_button.setText("Clear")
        self.clear_button.setToolTip("Forget the plotted session (the session CSV keeps everything)")
        self.run_choice = QComboBox()
        self.run_choice.setObjectName("runChoice")
        self.run_choice.setToolTip(RUNS_TIP)
        # Narrow (the readout needs the room); the list shows the runs' whole names.
        self.run_choice.setSizeAdjustPolicy(QComboBox.SizeAdjustPolicy.AdjustToMinimumContentsLengthWithIcon)
        self.run_choice.setMinimumContentsLength(6)
        self.run_choice.setVisible(False)
        self.run_choice.activated.connect(self.runChosen)
        self.run_choice.currentTextChanged.connect(lambda text: self.run_choice.setToolTip(f"{text}\n{RUNS_TIP}"))
        plot_bar = QHBoxLayout()
        plot_bar.setContentsMargins(4, 0, 0, 0)
        plot_bar.setSpacing(4)
        plot_bar.addStretch(1)
        plot_bar.addWidget(self.run_choice)
        plot_bar.addWidget(self.follow)
        plot_bar.addWidget(self.follow_minutes)
        plot_bar.addWidget(self.all_button)
        plot_bar.addWidget(self.clear_button)
        pv = QVBoxLayout(self)
        pv.setContentsMargins(0, 0, 0, 0)
        pv.setSpacing(0)
        self.readings.setContentsMargins(4, 2, 4, 0)
        pv.addWidget(self.readings)
        pv.addLayout(plot_bar)
        pv.addWidget(self.plot, 1)
        self.readout = CursorReadout(self.plot, self._cursor_samples)
        self.follow.toggled.connect(lambda on: self.plot.set_follow(on, self.follow_minutes.value()))
        self.follow_minutes.valueChanged.connect(lambda v: self.plot.set_follow(self.plot.follow, v))
        self.plot.followChanged.connect(self._plot_follow_changed)
        self.all_button.clicked.connect(self._show_all)

    def _cursor_samples(self):
        """The drawn session's samples under the cursor readout's names."""
        _, cols = self.plot.series.buffer.snapshot()
        return cols["t"], {"voltage_v": cols["voltage"], "current_a": cols["current"], "temp_c": cols["temp"]}

    def show_readings(self, tel) -> None:
        """The newest frame's values, in the plot's colours."""
        t = "—" if tel.temp_c is None else f"{tel.temp_c:.1f} °C"
        tc = "—" if tel.heatsink_c is None else f"{tel.heatsink_c:.1f} °C"
        self.readings.setText(
            f"<span style='color:#1f4e9c;'><b>{tel.voltage_v:.3f} V</b></span>&nbsp;&nbsp;"
            f"<span style='color:#23803a;'><b>{tel.current_a:+.3f} A</b></span>&nbsp;&nbsp;"
            f"<span style='color:#d0481c;'>T {t}</span>&nbsp;&nbsp;"
            f"<span style='color:#7b5ea7;'>Tc {tc}</span><br>"
            f"charged in {tel.mah_in:.0f} mAh · discharged out {tel.mah_out:.0f} mAh")
        # Two lines in a row of its own: whole at 1366 px; the tooltip says what T and Tc are.
        self.readings.setToolTip(f"{tel.voltage_v:.3f} V · {tel.current_a:+.3f} A · battery T {t} · heat sink "
                                 f"Tc {tc} · charged in {tel.mah_in:.0f} mAh · discharged out {tel.mah_out:.0f} mAh")

    def set_runs(self, labels: list[str]) -> None:
        """The runs of the session, the current one last (and chosen); shown from the second run."""
        self.run_choice.blockSignals(True)
        self.run_choice.clear()
        self.run_choice.addItems(labels)
        self.run_choice.setCurrentIndex(len(labels) - 1)
        for i, label in enumerate(labels):
            self.run_choice.setItemData(i, label, Qt.ItemDataRole.ToolTipRole)
        self.run_choice.blockSignals(False)
        self.run_choice.setVisible(len(labels) > 1)
        self.run_choice.setToolTip(f"{labels[-1]}\n{RUNS_TIP}" if labels else RUNS_TIP)

    def follow_again(self) -> None:
        if not self.plot.follow:
            self.follow.setChecked(True)

    def _plot_follow_changed(self, on: bool) -> None:
        if self.follow.isChecked() != on:
            self.follow.blockSignals(True)
            self.follow.setChecked(on)
            self.follow.blockSignals(False)

    def _show_all(self) -> None:
        self.follow.setChecked(False)
        self.plot.show_all()
