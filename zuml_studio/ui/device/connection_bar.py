"""The connection bar: the port, the driver, Connect and Replay; for the built-in virtual
charger its battery, passport chip and speed; what the charger said about itself; the
telemetry rate."""
from __future__ import annotations

from typing import Callable

from PySide6.QtWidgets import QComboBox, QHBoxLayout, QLabel, QPushButton, QVBoxLayout, QWidget

from ...device.drivers import AUTO, DRIVERS, ZUML
from ...device.passport import akk_name
from .device_style import colour, DEFAULT_BATTERY, FIELD_WIDTH, ElidedLabel, field_spin
from .port_chooser import PortChooser

NAMED_BATTERY = "battery:"      # virtual chemistry box data of a saved fitted battery
MATCH = "match"


def chemistry_names() -> list[str]:
    from ...sim.chemistry import chemistry_names as names
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

        self.v_chem = QComboBox()
        self.v_chem.setObjectName("virtualChemistry")
        self.v_chem.addItem("from the macro", None)
        for name in chemistry_names():
            self.v_chem.addItem(name, name)
        self.add_named_batteries()
        self.v_chem.setToolTip("The virtual battery's chemistry; 'from the macro' uses the editor macro's "
                               "AKK_TYPE (NiMh if it has none); a saved fitted battery brings its own "
                               "capacity and cells")
        self.v_mah = field_spin(100, 65000, DEFAULT_BATTERY[1], " mAh", "the virtual battery's capacity")
        self.v_mah.setSingleStep(100)
        self.v_cells = field_spin(1, 24, DEFAULT_BATTERY[2], " cells", "cells in series in the virtual battery")
        self.v_passport = QComboBox()
        self.v_passport.setObjectName("virtualPassport")
        self.v_passport.addItem("as battery", MATCH)
        for name in chemistry_names():
            self.v_passport.addItem(name, name)
        self.v_passport.addItem("none", "none")
        self.v_passport.setToolTip("The battery passport chip (spec §4): its chemistry as the battery's, "
                                   "another one (to see the lockout), or no chip")
        self.v_speed = field_spin(1, 100000, 60, "×", "the virtual charger runs the macro this many times "
                                  "faster than real time (changes at once)")
        self.v_speed.setObjectName("virtualSpeed")
        self.v_speed.setMaximumWidth(FIELD_WIDTH)
        self.rate = field_spin(1, 50, 10, " Hz", "telemetry frames per second the charger sends")
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
        self.info_label.setStyleSheet(f"color:{colour(self, 'info')};")
        for box in (self.v_mah, self.v_cells):
            box.setMinimumWidth(box.sizeHint().width())     # the note gives way, not the numbers
        self.battery_note = ElidedLabel("")
        self.battery_note.setObjectName("virtualBatteryNote")
        self.battery_note.setMinimumWidth(60)
        vrow.insertWidget(4, self.battery_note, 1)
        second.addWidget(self.virtual_box, 2)
        second.addWidget(self.info_label, 3)
        second.addWidget(QLabel("Telemetry"))
        second.addWidget(self.rate)

        layout = QVBoxLayout(self)
        layout.setContentsMargins(0, 0, 0, 0)
        layout.setSpacing(3)
        layout.addLayout(top)
        layout.addLayout(second)

    def add_named_batteries(self) -> None:
        """Offer the saved fitted batteries (docs/fit.md) after the chemistries."""
        from ...sim.batteries import battery_names
        for name in battery_names():
            if self.v_chem.findData(NAMED_BATTERY + name) < 0:
                self.v_chem.addItem(f"{name} (fitted)", NAMED_BATTERY + name)

    def virtual_battery(self, record: bytes | None, entered_mah: int, entered_cells: int) -> str:
        """``CHEM:MAH:CELLS`` for the built-in virtual charger; ``battery:NAME`` for a saved fitted
        battery. "From the macro": the chemistry, cells and capacity the editor's macro
        (``record``) declares; what it leaves to the start, the values entered for the run
        (``entered_*``, which the battery's fields set; cells 0: the cells field); NiMh without an
        AKK_TYPE. The note beside the fields says which values the battery uses."""
        chem = self.v_chem.currentData()
        from_macro = chem is None
        if isinstance(chem, str) and chem.startswith(NAMED_BATTERY):
            self.battery_note.set_full_text("capacity and cells: the fitted battery's")
            return chem
        if not from_macro:
            self.battery_note.set_full_text("")
            return f"{chem}:{self.v_mah.value()}:{self.v_cells.value()}"
        akk, cells, mah = record_battery(record) if record is not None else (None, None, None)
        chem = akk if akk in chemistry_names() else DEFAULT_BATTERY[0]
        mah_used = mah or entered_mah or self.v_mah.value()
        cells_used = cells or entered_cells or self.v_cells.value()
        def source(declared) -> str:
            return "the macro's" if declared else "as entered for the run"
        self.battery_note.set_full_text(
            f"{chem} {cells_used}S {mah_used} mAh: chemistry "
            + ("the macro's" if akk in chemistry_names() else "NiMh (the macro names none)")
            + f", cells {source(cells)}, capacity {source(mah)}")
        return f"{chem}:{mah_used}:{cells_used}"
