"""The battery's passport (spec §4): serial and vendor, type and temperature, limits and the
error counts, as the charger last read them (on connecting, on ⟳, and every few seconds)."""
from __future__ import annotations

from PySide6.QtCore import Qt, QTimer, Signal
from PySide6.QtWidgets import QGridLayout, QLabel, QToolButton, QVBoxLayout, QWidget

from ...protocol import messages as msg
from ...device.errors import DeviceError
from ...protocol.passport import printable
from ...i18n import _
from .connection import DeviceConnection, describe_error
from .device_style import heading_row, tint

POLL_MS = 5000


class PassportView(QWidget):
    operationFinished = Signal(str, bool, str)      # "passport", ok, message

    def __init__(self, connection: DeviceConnection, parent: QWidget | None = None):
        super().__init__(parent)
        self.connection = connection
        self.poll_timer = QTimer(self, interval=POLL_MS)
        self.poll_timer.timeout.connect(self._poll)
        self.pp_refresh = QToolButton()
        self.pp_refresh.setText("⟳")
        self.pp_refresh.setToolTip(_("Read the battery's passport again"))
        self.pp_labels = {k: QLabel("—") for k in ("serial", "type", "limits")}
        for k, lab in self.pp_labels.items():
            lab.setObjectName(f"passport_{k}")
            lab.setTextInteractionFlags(Qt.TextInteractionFlag.TextSelectableByMouse)
            lab.setTextFormat(Qt.TextFormat.PlainText)      # a battery's bytes are never markup
        b = QVBoxLayout(self)
        b.setContentsMargins(0, 0, 0, 0)
        b.setSpacing(3)
        b.addLayout(heading_row(_("Battery passport"), self.pp_refresh))
        pp = QGridLayout()
        pp.setHorizontalSpacing(6)
        pp.setVerticalSpacing(1)
        for r, (key, text) in enumerate((("serial", _("Serial")), ("type", _("Type")), ("limits", _("Limits")))):
            name = QLabel(text)
            tint(name, "info")
            pp.addWidget(name, r, 0)
            pp.addWidget(self.pp_labels[key], r, 1)
        pp.setColumnStretch(1, 1)
        b.addLayout(pp)
        self.pp_refresh.clicked.connect(self.refresh_passport)

    def show_passport(self, passport, error: str = "", connected: bool = False) -> None:
        if passport is None:
            text = error or (_("no passport chip") if connected else "—")
            self.pp_labels["serial"].setText(text)
            self.pp_labels["serial"].setToolTip(error)
            for key in ("type", "limits"):
                self.pp_labels[key].setText("—")
            return
        vendor = f" · {printable(passport.vendor)}" if passport.vendor else ""
        odd = passport.unprintable_fields
        self.pp_labels["serial"].setText(f"{printable(passport.serial) or '—'}{vendor}" + (" ⚠" if odd else ""))
        fields = {"serial": _("serial"), "vendor": _("vendor")}
        self.pp_labels["serial"].setToolTip(
            _("serial · vendor. ⚠ The {fields} hold non-printable bytes (shown as \\xNN): a damaged or forged "
              "passport").format(fields=_(" and ").join(fields.get(f, f) for f in odd))
            if odd else _("serial · vendor"))
        tint(self.pp_labels["serial"], "warn" if odd else "none")
        self.pp_labels["type"].setText(f"{passport.type_name} · TEMP {passport.temp} °C")
        v = f"{passport.v_limit} V" if passport.v_limit else _("V not set")
        a = f"{passport.a_limit} A" if passport.a_limit else _("A not set")
        err = (f" · ERR {passport.err}" if passport.err else "") + \
            (" · " + _("CRIT {crit}: not fit for use").format(crit=passport.crit) if passport.crit else "")
        self.pp_labels["limits"].setText(f"{v} · {a}{err}")

    def refresh_passport(self) -> None:
        """Read the passport again; ``operationFinished("passport", ok, message)``."""
        if not self.connection.is_connected():
            return

        def job(client, progress):
            try:
                return client.passport_read()
            except DeviceError as exc:
                if exc.code == msg.ErrorCode.NO_PASSPORT:
                    return None
                raise

        def done(passport):
            self.show_passport(passport, "", True)
            self.operationFinished.emit("passport", True, "")

        def failed(exc):
            self.show_passport(None, describe_error(exc), True)
            self.operationFinished.emit("passport", False, describe_error(exc))

        self.connection.call(job, done, failed)

    def _poll(self) -> None:
        if self.connection.is_connected() and not self.connection.busy and self.isVisible():
            def job(client, progress):
                try:
                    return client.passport_read()
                except DeviceError:
                    return None
            self.connection.call(job, lambda p: self.show_passport(p, "", True), lambda exc: None)
