"""The connection bar: the port, the driver, Connect and Replay; for the built-in virtual
charger its battery, passport chip and speed; what the charger said about itself; the
telemetry rate. It owns the virtual battery's choice and the line about the connected charger."""
from __future__ import annotations

from pathlib import Path
from typing import Callable

from PySide6.QtCore import Qt
from PySide6.QtWidgets import (QComboBox, QFileDialog, QGridLayout, QHBoxLayout, QLabel, QMenu, QPushButton,
                               QSizePolicy, QStyle, QToolButton, QVBoxLayout, QWidget, QWidgetAction)

from ...streams.drivers import AUTO, DRIVERS, ZUML
from ...protocol.passport import akk_name
from ...device.links.ports import VIRTUAL
from ...i18n import _
from ..base.cell_fields import CellFields
from ..base.number_boxes import form_field
from .connection import VirtualSpec
from .device_style import DEFAULT_BATTERY, FIELD_WIDTH, ElidedCombo, ElidedLabel, field_spin, tint
from .port_chooser import PortChooser

NAMED_BATTERY = "battery:"      # virtual chemistry box data of a saved fitted battery
CELLS_TEXT_PX = 110             # the cells button's text at most
MATCH = "match"


def chemistry_names() -> list[str]:
    from ...domain.chemistry import chemistry_names as names
    return names()


def record_chemistry(record: bytes) -> str:
    """The AKK_TYPE a record declares ("NiMh"), "Undef" without one, "?" if it does not decode."""
    try:
        from ...lang.opcodes import AKK_TYPE
        from ...sim.program import Program
        return akk_name(Program(record).intro.declarations.get(AKK_TYPE.code, 0))
    except Exception:   # noqa: BLE001 - a record that does not decode
        return "?"


def record_battery(record: bytes) -> tuple[str | None, int | None, int | None]:
    """The chemistry, cells and capacity a record declares (AKK_TYPE, SERIES, CAPACITY; None
    for what it leaves out or sets at start, or all None if it does not decode)."""
    try:
        from ...lang.opcodes import AKK_TYPE, CAPACITY, SERIES
        from ...sim.program import Program
        declared = Program(record).intro.declarations
    except Exception:   # noqa: BLE001 - a record that does not decode
        return None, None, None
    akk = akk_name(declared[AKK_TYPE.code]) if AKK_TYPE.code in declared else None
    cells = declared.get(SERIES.code) or None
    mah = declared.get(CAPACITY.code)
    return akk, cells if cells and cells < 255 else None, mah if mah and mah < 0xFFFF else None


class ConnectionBar(QWidget):
    """Two rows above the panel's columns. It owns the virtual battery's choice."""

    def __init__(self, port_lister: Callable | None = None, parent: QWidget | None = None):
        super().__init__(parent)
        self.ports = PortChooser(port_lister)
        self.connect_button = QPushButton(_("Connect"))
        self.connect_button.setObjectName("connectButton")
        self.connect_button.setToolTip(_("Connect to the charger on the chosen port (or Disconnect)"))
        self.connect_button.setMinimumWidth(96)
        port_label = QLabel(_("Port"))
        port_label.setBuddy(self.ports.combo)
        top = QHBoxLayout()
        top.setContentsMargins(0, 0, 0, 0)
        top.setSpacing(6)
        self.driver_combo = ElidedCombo()
        self.driver_combo.setObjectName("driverCombo")
        self.driver_combo.addItem(_("Auto"), AUTO)
        self.driver_combo.addItem(_("ZUML charger"), ZUML)
        for d in DRIVERS.values():
            self.driver_combo.addItem(_(d.title), d.name)
        self.driver_combo.setSizeAdjustPolicy(QComboBox.SizeAdjustPolicy.AdjustToMinimumContentsLengthWithIcon)
        self.driver_combo.setMinimumContentsLength(10)
        self.driver_combo.setToolTip(_("The charger's protocol. Auto: a ZUML charger if one answers, else a "
                                       "monitor-only charger (cheali, iCharger, iMAX B6, Ultramat, SkyRC, ISDT) "
                                       "recognised from what it sends"))
        self.replay_button = QPushButton(_("Replay a recording…"))
        self.replay_button.setObjectName("replayButton")
        self.replay_button.setToolTip(_("Play a charger recording ($ lines, {…} frames, Ultramat frames, a HID "
                                        "report dump, an iCharger DUO/X log) onto a port and watch it here, at the "
                                        "virtual charger's speed ×"))
        top.addWidget(port_label)
        top.addWidget(self.ports, 1)
        top.addWidget(self.driver_combo)
        top.addWidget(self.connect_button)
        top.addWidget(self.replay_button)

        self.v_chem = ElidedCombo()
        self.v_chem.setObjectName("virtualChemistry")
        self.v_chem.addItem(_("from the macro"), None)
        for name in chemistry_names():
            self.v_chem.addItem(name, name)
        self.add_named_batteries()
        # As wide as "from the macro" or a chemistry: a saved battery's long name elides.
        self.v_chem.size_by(self.v_chem.itemText(i) for i in range(1 + len(chemistry_names())))
        self.v_chem.setToolTip(_("The virtual battery's chemistry; 'from the macro' uses the editor macro's "
                                 "AKK_TYPE (NiMh if it has none); a saved fitted battery brings its own "
                                 "capacity and cells"))
        self.v_mah = field_spin(100, 65000, DEFAULT_BATTERY[1], " mAh", _("the virtual battery's capacity"))
        self.v_mah.setSingleStep(100)
        self.v_cells = field_spin(1, 24, DEFAULT_BATTERY[2], _(" cells"), _("cells in series in the virtual battery"))
        self._cell_choice()
        self.v_passport = ElidedCombo()
        self.v_passport.setObjectName("virtualPassport")
        self.v_passport.addItem(_("as battery"), MATCH)
        for name in chemistry_names():
            self.v_passport.addItem(name, name)
        self.v_passport.addItem(_("none"), "none")
        self.v_passport.setToolTip(_("The battery passport chip (ZUML 2.0 §4): its chemistry as the battery's, "
                                     "another one (to see the lockout), or no chip"))
        self.v_speed = field_spin(1, 100000, 60, "×", _("the virtual charger runs the macro this many times "
                                                           "faster than real time (changes at once)"))
        self.v_speed.setObjectName("virtualSpeed")
        self.v_speed.setMaximumWidth(FIELD_WIDTH)
        self.rate = field_spin(1, 50, 10, " Hz", _("telemetry frames per second the charger sends"))
        self.rate.setObjectName("telemetryRate")
        self.virtual_box = QWidget()
        vrow = QHBoxLayout(self.virtual_box)
        vrow.setContentsMargins(0, 0, 0, 0)
        vrow.setSpacing(4)
        cells_label = QLabel(_("Cells"))
        cells_label.setToolTip(self.cells_button.toolTip())
        for w in (QLabel(_("Pack")), self.v_chem, self.v_mah, self.v_cells, cells_label, self.cells_button,
                  QLabel(_("Passport")), self.v_passport,
                  QLabel(_("Speed")), self.v_speed):
            vrow.addWidget(w)
        second = QHBoxLayout()
        second.setContentsMargins(0, 0, 0, 0)
        second.setSpacing(6)
        self.info_label = ElidedLabel("")
        self.info_label.setObjectName("deviceInfo")
        tint(self.info_label, "info")
        for box in (self.v_mah, self.v_cells):
            box.setMinimumWidth(box.sizeHint().width())     # the note gives way, not the numbers
        self.battery_note = ElidedLabel("")
        self.battery_note.setObjectName("virtualBatteryNote")
        self.battery_note.setMinimumWidth(60)
        # The charger's state at its whole text's width, the battery's note in the rest of the row: the
        # note was cut to "LiPo 4S…" at 1920 px while "not connected" beside it stood in 700 px of its own.
        for label in (self.battery_note, self.info_label):
            label.setSizePolicy(QSizePolicy.Policy.Preferred, QSizePolicy.Policy.Preferred)
        vrow.insertWidget(4, self.battery_note, 1)
        second.addWidget(self.virtual_box, 1)
        second.addWidget(self.info_label)
        # The telemetry rate ends the first row, the shorter one: on the second, beside the battery's
        # fields, it made the panel 1100 px wide at least in Russian, squeezing the Problems beside it.
        top.addWidget(QLabel(_("Telemetry")))
        top.addWidget(self.rate)

        layout = QVBoxLayout(self)
        layout.setContentsMargins(0, 0, 0, 0)
        layout.setSpacing(3)
        layout.addLayout(top)
        layout.addLayout(second)

    def _cell_choice(self) -> None:
        """The virtual battery's cells as ``zuml simulate`` takes them (the simulator's fields), in a
        pop-up under a button that says what is chosen: the row has no room for four more fields."""
        self.cells = CellFields()
        self.v_weak, self.v_weak_cell, self.v_spread, self.v_seed = (
            self.cells.weak_pct, self.cells.weak_cell, self.cells.spread, self.cells.seed)
        self.v_weak.setObjectName("virtualWeakCell")
        self.cells_form = QWidget()
        self.cells_form.setObjectName("virtualCellsForm")
        grid = QGridLayout(self.cells_form)
        grid.setContentsMargins(8, 6, 8, 6)
        grid.setHorizontalSpacing(6)
        grid.setVerticalSpacing(4)
        for row, (text, widget) in enumerate(((_("Weak cell"), self.v_weak), (_("Which"), self.v_weak_cell),
                                              (_("Spread"), self.v_spread), (_("Seed"), self.v_seed))):
            label = QLabel(text)
            label.setBuddy(widget)
            label.setToolTip(widget.toolTip())
            grid.addWidget(label, row, 0)
            grid.addWidget(form_field(widget, min_width=FIELD_WIDTH), row, 1)
        menu = QMenu(self)
        action = QWidgetAction(menu)
        action.setDefaultWidget(self.cells_form)
        menu.addAction(action)
        self.cells_button = QToolButton()
        self.cells_button.setObjectName("virtualCells")
        self.cells_button.setPopupMode(QToolButton.ToolButtonPopupMode.InstantPopup)
        self.cells_button.setMenu(menu)
        self._cells_tip = _("The virtual battery's cells: equal, or one weak cell (which one, how much less "
                            "capacity) and a spread of capacity, resistance and start charge drawn with a seed, as "
                            "the simulator takes them; the live view shows the cells and the balancer at work")
        self.cells_button.setToolTip(self._cells_tip)
        for signal in (self.v_weak.valueChanged, self.v_weak_cell.valueChanged, self.v_spread.textChanged,
                       self.v_seed.valueChanged):
            signal.connect(self._show_cells)
        self._show_cells()

    def _show_cells(self, *_args) -> None:
        """The choice on the button, cut to CELLS_TEXT_PX (whole in its tooltip): a spread must not
        widen the row past the dock."""
        full = self.cells.summary()
        shown = self.cells_button.fontMetrics().elidedText(full, Qt.TextElideMode.ElideRight, CELLS_TEXT_PX)
        self.cells_button.setText(shown)
        self.cells_button.setToolTip(f"{full}\n\n{self._cells_tip}")
        # The pop-up's arrow is drawn over the text's end unless there is room for it beside.
        arrow = self.cells_button.style().pixelMetric(QStyle.PixelMetric.PM_MenuButtonIndicator, None,
                                                      self.cells_button)
        self.cells_button.setMinimumWidth(self.cells_button.sizeHint().width() + arrow)

    def add_named_batteries(self) -> None:
        """Offer the saved fitted batteries (docs/fit.md) after the chemistries."""
        from ...sim.batteries import battery_names
        for name in battery_names():
            if self.v_chem.findData(NAMED_BATTERY + name) < 0:
                self.v_chem.addItem(_("{name} (fitted)").format(name=name), NAMED_BATTERY + name)

    def virtual_battery(self, record: bytes | None, entered_mah: int, entered_cells: int) -> str:
        """``CHEM:MAH:CELLS`` for the built-in virtual charger; ``battery:NAME`` for a saved fitted
        battery. "From the macro": the chemistry, cells and capacity the editor's macro
        (``record``) declares; what it leaves to the start, the values entered for the run
        (``entered_*``, which the battery's fields set; cells 0: the cells field); NiMh without an
        AKK_TYPE. The note beside the fields says which values the battery uses."""
        chem = self.v_chem.currentData()
        from_macro = chem is None
        if isinstance(chem, str) and chem.startswith(NAMED_BATTERY):
            self.battery_note.set_full_text(_("capacity and cells: the fitted battery's"))
            return chem
        if not from_macro:
            self.battery_note.set_full_text("")
            return f"{chem}:{self.v_mah.value()}:{self.v_cells.value()}"
        akk, cells, mah = record_battery(record) if record is not None else (None, None, None)
        chem = akk if akk in chemistry_names() else DEFAULT_BATTERY[0]
        mah_used = mah or entered_mah or self.v_mah.value()
        cells_used = cells or entered_cells or self.v_cells.value()
        macro, entered = _("the macro's"), _("as entered for the run")
        self.battery_note.set_full_text(
            _("{chem} {cells}S {mah} mAh: chemistry {chem_source}, cells {cells_source}, capacity {mah_source}").format(
                chem=chem, cells=cells_used, mah=mah_used,
                chem_source=macro if akk in chemistry_names() else _("NiMh (the macro names none)"),
                cells_source=macro if cells else entered, mah_source=macro if mah else entered))
        return f"{chem}:{mah_used}:{cells_used}"

    def monitor_driver(self, target: str) -> str | None:
        """The driver to watch ``target`` with, or None to talk to a ZUML charger there."""
        driver = self.driver_combo.currentData() or AUTO
        if target.startswith("hid:"):
            # ZUML chargers are serial: a HID charger is watched with its chosen driver, or by its USB ids
            return driver if driver in DRIVERS else AUTO
        return driver if target != VIRTUAL and driver in DRIVERS else None

    def virtual_spec(self, battery: str, eeprom: Path) -> VirtualSpec:
        """The built-in virtual charger as chosen here, with ``battery`` and its EEPROM file;
        ValueError says in words what is typed wrong in the cells' fields."""
        return VirtualSpec(battery, float(self.v_speed.value()), self.v_passport.currentData() or MATCH, eeprom,
                           float(self.v_weak.value()), self.cells.weak_cell_number(), self.cells.cell_spread(),
                           self.v_seed.value())

    # -- the connected charger ----------------------------------------------------------------
    def set_link_state(self, state: str, monitoring: bool, shut: bool) -> None:
        """What may change in this state ("disconnected", "connecting", "connected")."""
        free = state == "disconnected" and not monitoring
        self.connect_button.setText(_("Connect") if free else _("Disconnect"))
        self.connect_button.setEnabled(not shut and state != "disconnecting")
        self.replay_button.setEnabled(free and not shut)
        self.driver_combo.setEnabled(free and not self.ports.is_virtual())
        for w in (self.ports, self.v_chem, self.v_mah, self.v_cells, self.cells_button, self.cells_form,
                  self.v_passport):
            w.setEnabled(free)
        self.rate.setEnabled(not monitoring)
        self.virtual_box.setVisible(self.ports.is_virtual())

    def show_charger(self, opened) -> None:
        """What a ZUML charger said about itself (``connection.Opened``)."""
        info = opened.info
        where = _("built-in virtual charger") if opened.virtual else opened.url
        limits = _("charge {ca:g} A/{cw:g} W, discharge {da:g} A/{dw:g} W, {v:g} V max").format(
            ca=info.max_charge_a, cw=info.max_charge_w, da=info.max_discharge_a, dw=info.max_discharge_w,
            v=info.max_v)
        tint(self.info_label, "info")
        self.info_label.set_full_text(_("{model} · {firmware} · EEPROM {size} bytes · {limits}").format(
            model=info.model, firmware=info.firmware, size=info.eeprom_size, limits=limits))
        self.info_label.setToolTip(
            _("{where}: {model}, firmware {firmware}, protocol {protocol}").format(
                where=where, model=info.model, firmware=info.firmware, protocol=info.protocol) + "\n"
            + _("EEPROM {size} bytes; {limits}").format(size=info.eeprom_size, limits=limits) + "\n"
            + _("{hz} telemetry frames/s").format(hz=opened.telemetry_hz))

    def show_monitor(self, link) -> None:
        """A monitor-only charger's link (``device.links.monitor_link.MonitorLink``, None: none): what it
        is, its counts."""
        if link is None:
            return
        name = _(link.driver.title) if link.driver else _("recognising…")
        self.info_label.set_full_text(_("{name} · monitor-only · {good} records · {bad} bad").format(
            name=name, good=link.good, bad=link.bad))
        self.info_label.setToolTip(
            _("{port}: {name}").format(port=link.port, name=name) + "\n"
            + _("{good} records decoded; {bad} bad (checksum, torn line or garbage: counted, never plotted)")
            .format(good=link.good, bad=link.bad))
        tint(self.info_label, "warn" if link.bad else "info")

    def show_disconnected(self) -> None:
        tint(self.info_label, "info")
        self.info_label.set_full_text(_("not connected"))

    def ask_recording(self) -> str:
        """The recording to replay ("" if the user cancels)."""
        path, _filter = QFileDialog.getOpenFileName(
            self, _("Replay a charger recording"), "",
            _("Recordings (*.txt *.log *.bin *.hex *.csv *.lov);;All files (*)"))
        return path
