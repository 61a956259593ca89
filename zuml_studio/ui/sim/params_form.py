"""What the user enters at start on the charger, and the simulated battery: a compact
two-column form for the simulator panel's left side, with Simulate/Cancel and the
progress of the running simulation."""
from __future__ import annotations

from PySide6.QtCore import Qt, Signal
from PySide6.QtWidgets import (QCheckBox, QComboBox, QDoubleSpinBox, QGridLayout, QHBoxLayout,
                               QLabel, QLineEdit, QProgressBar, QPushButton, QSpinBox, QWidget)

from ... import data
from ...i18n import N_, _
from ...sim.batteries import battery_names
from ...sim.battery import AMBIENT_MAX_C, AMBIENT_MIN_C
from ...sim.chemistry import chemistry_names
from ...sim.interpreter import StartParams
from ...sim.program import TASK_LABELS
from ...sim.charger_model import load_charger
from ...sim.simulate import BatterySetup
from ...sim.start_templates import factory_templates
from ..base.cell_fields import DEFAULT_SEED, CellFields
from ..base.number_boxes import double_spin_box, form_field, spin_box
from ..base.timefmt import elapsed

FROM_AKK = N_("from AKK_TYPE")
NAMED = "battery:"      # Model box data of a saved fitted battery
MODEL_TIP = N_("the battery model; 'from AKK_TYPE' uses the chemistry the macro declares")
FIELD_WIDTH = 104

DEFAULTS = {"task": "charge", "repetitions": 3, "capacity_mah": 2000, "current_a": 2.0, "series": 4,
            "voltage_v": None, "chemistry": None, "soc_percent": None, "ambient_c": 25.0, "sensor": True,
            "auto": True, "template": None, "weak_cell_pct": 0, "weak_cell": None, "cell_spread": None,
            "seed": DEFAULT_SEED, "charger": "imax_b6"}
START_VALUES = ("task", "repetitions", "capacity_mah", "current_a", "series", "voltage_v", "sensor")


class ParamsForm(QWidget):
    simulateRequested = Signal()
    cancelRequested = Signal()
    changed = Signal()                  # the user changed a parameter of the run
    autoToggled = Signal(bool)

    def __init__(self, parent: QWidget | None = None):
        super().__init__(parent)
        self.setObjectName("simParams")
        self._programmatic = False
        self._edited: set[str] = set()      # fields the user changed: macro hints never override them
        self._declared_akk = ""

        self.task = QComboBox()
        for key, text in TASK_LABELS.items():
            self.task.addItem(_(text), key)
        self.task.setToolTip(_("What the charger is started for: charge, discharge, or training "
                               "(discharge + charge, repeated)"))
        self.repetitions = self._spin_box(1, 255, DEFAULTS["repetitions"], "",
                                          _("training: discharge+charge this many times"))
        self.repetitions.setPrefix("× ")
        self.capacity = self._spin_box(10, 65000, DEFAULTS["capacity_mah"], " mAh",
                                   _("the battery's capacity, entered at start (and the model's size)"))
        self.capacity.setSingleStep(100)
        self.current = self._double_box(0.01, 50.0, DEFAULTS["current_a"], " A", 2, 0.1,
                                   _("the current entered at start (CONSTANT_I=INPUT; the limit of a CONSTANT_V phase)"))
        self.series = self._spin_box(1, 255, DEFAULTS["series"], "",
                                     _("cells in series (used when the macro has no SERIES)"))
        self.series.setSuffix(" " + _("cells"))
        self.voltage = self._double_box(0.0, 100.0, 0.0, " V", 2, 0.1,
                                   _("the voltage entered at start, for macros that take one (INPUT); — none"))
        self.voltage.setSpecialValueText("—")
        self.model = QComboBox()
        self.model.addItem(_(FROM_AKK), None)
        for name in chemistry_names():
            self.model.addItem(name, name)
        self.add_named_batteries()
        self.model.setToolTip(_(MODEL_TIP))
        form_field(self.model, max_width=FIELD_WIDTH).setMaximumWidth(2 * FIELD_WIDTH)
        self.template = QComboBox()
        self.template.addItem("—", None)
        for number, template in sorted(factory_templates().items()):
            self.template.addItem(f"{number}: {template.describe()}", number)
        self.template.setToolTip(_("start with one of the charger's start templates (its values replace those "
                                   "above); a macro's START_SHABLON=n chooses its own"))
        form_field(self.template, max_width=FIELD_WIDTH).setMaximumWidth(2 * FIELD_WIDTH)
        form_field(self.task, max_width=FIELD_WIDTH)
        self.initial = self._spin_box(-1, 100, -1, " %", _("initial state of charge: auto = empty for a charge, "
                                                           "full for a discharge or a training"))
        self.initial.setSpecialValueText(_("auto"))
        self.ambient = self._double_box(AMBIENT_MIN_C, AMBIENT_MAX_C, DEFAULTS["ambient_c"], " °C", 0, 1.0, _("ambient temperature"))
        self.sensor = QCheckBox(_("T sensor"))
        self.sensor.setChecked(DEFAULTS["sensor"])
        self.sensor.setToolTip(_("a battery temperature sensor is connected (without one, the default "
                                 "T and dT/dt stops cannot act)"))
        self._cell_fields()
        self.auto = QCheckBox(_("Auto re-simulate"))
        self.auto.setChecked(DEFAULTS["auto"])
        self.auto.setToolTip(_("simulate again whenever the macro compiles to a new record or a parameter changes"))

        self.simulate_button = QPushButton(_("Simulate"))
        self.simulate_button.setToolTip(_("Run the macro against the battery model (F5)"))
        self.simulate_button.setDefault(True)
        self.cancel_button = QPushButton(_("Cancel"))
        self.cancel_button.setToolTip(_("Stop the running simulation (Shift+F5)"))
        self.cancel_button.setEnabled(False)
        self.progress = QProgressBar()
        self.progress.setObjectName("simProgress")
        self.progress.setTextVisible(False)
        self.progress.setFixedHeight(10)
        self.progress_label = QLabel("")
        self.progress_label.setObjectName("simProgressLabel")
        self.progress_label.setStyleSheet("color:#555;")
        self.set_running(False)

        grid = QGridLayout(self)
        grid.setContentsMargins(6, 4, 6, 4)
        grid.setHorizontalSpacing(6)
        grid.setVerticalSpacing(3)
        rows = (((_("Task"), self.task), (_("Reps"), self.repetitions)),
                ((_("Capacity"), self.capacity), (_("Current"), self.current)),
                ((_("Cells"), self.series), (_("Voltage"), self.voltage)),
                ((_("Model"), self.model),),
                ((_("Template"), self.template),),
                ((_("Initial"), self.initial), (_("Ambient"), self.ambient)),
                ((_("Weak cell"), self.weak_pct), (_("Which"), self.weak_cell)),
                ((_("Spread"), self.spread), (_("Seed"), self.seed)),
                ((_("Charger"), self.charger),),
                ((None, self.sensor), (None, self.auto)))
        for r, pair in enumerate(rows):
            for c, (text, widget) in enumerate(pair):
                span = 2 if len(pair) > 1 else 4
                if text:
                    label = QLabel(text)
                    label.setBuddy(widget)
                    label.setToolTip(widget.toolTip())
                    grid.addWidget(label, r, 2 * c)
                    grid.addWidget(widget, r, 2 * c + 1, 1, span - 1)
                else:
                    grid.addWidget(widget, r, 2 * c, 1, span)
        buttons = QHBoxLayout()
        buttons.setSpacing(4)
        buttons.addWidget(self.simulate_button)
        buttons.addWidget(self.cancel_button)
        buttons.addStretch(1)
        grid.addLayout(buttons, len(rows), 0, 1, 4)
        status = QHBoxLayout()
        status.setSpacing(6)
        status.addWidget(self.progress, 1)
        status.addWidget(self.progress_label)
        grid.addLayout(status, len(rows) + 1, 0, 1, 4)
        grid.setRowStretch(len(rows) + 2, 1)
        grid.setColumnStretch(1, 1)
        grid.setColumnStretch(3, 1)

        for name, widget in self._fields().items():
            self._watch(name, widget)
        self.task.currentIndexChanged.connect(self._task_changed)
        self.auto.toggled.connect(self.autoToggled)
        self.simulate_button.clicked.connect(self.simulateRequested)
        self.cancel_button.clicked.connect(self.cancelRequested)
        self._task_changed()

    # -- building --------------------------------------------------------------------------
    def _cell_fields(self) -> None:
        """The pack's cells (equal unless asked) and the charger whose balancer works on them."""
        self.cells = CellFields()
        self.weak_pct = form_field(self.cells.weak_pct, max_width=FIELD_WIDTH)
        self.weak_cell = form_field(self.cells.weak_cell, max_width=FIELD_WIDTH)
        self.spread = form_field(self.cells.spread, max_width=FIELD_WIDTH)
        self.seed = form_field(self.cells.seed, max_width=FIELD_WIDTH)
        self.charger = QComboBox()
        for name in data.names("chargers"):
            self.charger.addItem(load_charger(name).name, name)
        self.charger.setCurrentIndex(self.charger.findData(DEFAULTS["charger"]))
        self.charger.setToolTip(_("the charger whose limits and balancer the run uses: how much it bleeds a "
                                  "high cell, and the per-cell ceiling that ends a Li charge"))
        form_field(self.charger, max_width=FIELD_WIDTH).setMaximumWidth(2 * FIELD_WIDTH)

    @staticmethod
    def _spin_box(*args) -> QSpinBox:
        return form_field(spin_box(*args), max_width=FIELD_WIDTH)

    @staticmethod
    def _double_box(*args) -> QDoubleSpinBox:
        return form_field(double_spin_box(*args), max_width=FIELD_WIDTH)

    def _fields(self) -> dict[str, QWidget]:
        return {"task": self.task, "repetitions": self.repetitions, "capacity_mah": self.capacity,
                "current_a": self.current, "series": self.series, "voltage_v": self.voltage,
                "chemistry": self.model, "soc_percent": self.initial, "ambient_c": self.ambient,
                "sensor": self.sensor, "template": self.template, "weak_cell_pct": self.weak_pct,
                "weak_cell": self.weak_cell, "cell_spread": self.spread, "seed": self.seed, "charger": self.charger}

    def _watch(self, name: str, widget: QWidget) -> None:
        if isinstance(widget, QComboBox):
            signal = widget.currentIndexChanged
        elif isinstance(widget, QCheckBox):
            signal = widget.toggled
        elif isinstance(widget, QLineEdit):
            signal = widget.textChanged
        else:
            signal = widget.valueChanged
        signal.connect(lambda *_: self._user_changed(name))

    def _user_changed(self, name: str) -> None:
        if self._programmatic:
            return
        self._edited.add(name)
        self.changed.emit()

    def _task_changed(self) -> None:
        self.repetitions.setEnabled(self.task.currentData() == "train")

    # -- values ----------------------------------------------------------------------------
    def start_params(self) -> StartParams:
        voltage = self.voltage.value()
        return StartParams(task=self.task.currentData(), repetitions=self.repetitions.value(),
                           capacity_mah=float(self.capacity.value()), current_a=self.current.value(),
                           voltage_v=voltage if voltage > 0 else None, series=self.series.value(),
                           sensor=self.sensor.isChecked(), template=self.template.currentData())

    def add_named_batteries(self) -> None:
        """Offer the saved fitted batteries (zuml fit --save, Compare with Log > Save) after the chemistries."""
        for name in battery_names():
            if self.model.findData(NAMED + name) < 0:
                self.model.addItem(_("{name} (fitted)").format(name=name), NAMED + name)

    def battery_setup(self) -> BatterySetup:
        """The battery and charger of the run; ValueError says in words what is typed wrong."""
        soc = self.initial.value()
        model = self.model.currentData()
        named = model[len(NAMED):] if isinstance(model, str) and model.startswith(NAMED) else None
        return BatterySetup(chemistry=None if named else model, soc=None if soc < 0 else soc / 100.0,
                            ambient_c=self.ambient.value(), battery=named, charger=self.charger.currentData(),
                            cell_spread=self.cells.cell_spread(), seed=self.seed.value(),
                            weak_cell_pct=float(self.weak_pct.value()), weak_cell=self.cells.weak_cell_number())

    def auto_resimulate(self) -> bool:
        return self.auto.isChecked()

    def set_values(self, **values) -> None:
        """Set fields as if the user typed them (keys as in ``DEFAULTS``); emits ``changed`` once."""
        for name, value in values.items():
            self._set(name, value)
            self._edited.add(name)
        if values:
            self.changed.emit()

    def _set(self, name: str, value) -> None:
        widget = self._fields()[name]
        was, self._programmatic = self._programmatic, True
        try:
            if isinstance(widget, QComboBox):
                index = widget.findData(value)
                widget.setCurrentIndex(index if index >= 0 else 0)
            elif isinstance(widget, QCheckBox):
                widget.setChecked(bool(value))
            elif isinstance(widget, QLineEdit):
                widget.setText(",".join(f"{x:g}" for x in value) if isinstance(value, (tuple, list)) else value or "")
            elif name == "weak_cell":
                widget.setValue(value or 0)
            elif name == "soc_percent":
                widget.setValue(-1 if value is None else int(round(value)))
            elif name == "voltage_v":
                widget.setValue(value or 0.0)
            else:
                widget.setValue(value)
        finally:
            self._programmatic = was

    def reset_start_values(self) -> None:
        """Another macro opened: the values entered at start go back to the defaults (its own
        declarations then fill in), whatever was typed for the previous macro. The battery
        (model, charge, ambient) stays: it is the one on the bench."""
        for name in START_VALUES:
            self._set(name, DEFAULTS[name])
            self._edited.discard(name)

    def apply_declared(self, declared: dict | None) -> bool:
        """Prefill from the macro's own declarations, leaving alone whatever the user typed.
        Returns whether a value of the run changed."""
        declared = declared or {}
        changed = False
        for name in ("capacity_mah", "series"):
            value = declared.get(name)
            if value and name not in self._edited and self._fields()[name].value() != value:
                self._set(name, value)
                changed = True
        akk = str(declared.get("chemistry") or "")
        if akk != self._declared_akk:
            self._declared_akk = akk
            tip = _(MODEL_TIP) + (" " + _("(this one declares {declaration})").format(declaration=f"AKK_TYPE={akk}")
                                  if akk else "")
            self.model.setToolTip(tip)
            self.model.setItemData(0, tip, Qt.ItemDataRole.ToolTipRole)
        return changed

    def edited(self) -> frozenset[str]:
        return frozenset(self._edited)

    # -- running ---------------------------------------------------------------------------
    def set_running(self, running: bool) -> None:
        self.cancel_button.setEnabled(running)
        self.progress.setRange(0, 0 if running else 1)   # 0..0: the busy indicator
        self.progress.setValue(0)
        self.progress.setVisible(running)
        if running:
            self.progress_label.setText(_("starting…"))

    def set_progress(self, seconds: float) -> None:
        self.progress_label.setText(_("{time} simulated").format(time=elapsed(seconds)))
