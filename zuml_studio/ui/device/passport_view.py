"""The battery's passport (spec §4): serial and vendor, type and temperature, limits and the
error counts, as the charger last read them."""
from __future__ import annotations

from PySide6.QtCore import Qt
from PySide6.QtWidgets import QGridLayout, QHBoxLayout, QLabel, QToolButton, QVBoxLayout, QWidget

from ...device.passport import printable
from .device_style import colour, heading


class PassportView(QWidget):
    def __init__(self, parent: QWidget | None = None):
        super().__init__(parent)
        self.pp_refresh = QToolButton()
        self.pp_refresh.setText("⟳")
        self.pp_refresh.setToolTip("Read the battery's passport again")
        self.pp_labels = {k: QLabel("—") for k in ("serial", "type", "limits")}
        for k, lab in self.pp_labels.items():
            lab.setObjectName(f"passport_{k}")
            lab.setTextInteractionFlags(Qt.TextInteractionFlag.TextSelectableByMouse)
            lab.setTextFormat(Qt.TextFormat.PlainText)      # a battery's bytes are never markup
        b = QVBoxLayout(self)
        b.setContentsMargins(0, 0, 0, 0)
        b.setSpacing(3)
        pp_head = QHBoxLayout()
        pp_head.setSpacing(4)
        pp_head.addWidget(heading("Battery passport"), 1)
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

    def show_passport(self, passport, error: str = "", connected: bool = False) -> None:
        if passport is None:
            text = error or ("no passport chip" if connected else "—")
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
        self.pp_labels["serial"].setStyleSheet(f"color:{colour(self, 'warn')};" if odd else "")
        self.pp_labels["type"].setText(f"{passport.type_name} · TEMP {passport.temp} °C")
        v = f"{passport.v_limit} V" if passport.v_limit else "V not set"
        a = f"{passport.a_limit} A" if passport.a_limit else "A not set"
        err = (f" · ERR {passport.err}" if passport.err else "") + \
            (f" · CRIT {passport.crit}: not fit for use" if passport.crit else "")
        self.pp_labels["limits"].setText(f"{v} · {a}{err}")
