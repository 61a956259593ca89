"""Where to connect: the built-in virtual charger (first, the default), the simulated iMAX B6
(the ZUML firmware on simavr, started by the window), the serial ports found, or a port path /
URL typed in; and the baud rate.

Port scans run on a thread pool, never on the GUI thread (a scan can take a while on some
systems): once when the chooser is shown, then every 2 s while it is visible and
``auto_refresh`` is on (the panel turns it off while connected)."""
from __future__ import annotations

import logging
from typing import Callable

from PySide6.QtCore import QObject, QRunnable, QThreadPool, QTimer, Signal
from PySide6.QtWidgets import QComboBox, QHBoxLayout, QLineEdit, QSizePolicy, QWidget

from ...device.install.isp_store import SCHEME as ISP_SCHEME, USBASP
from ...device.links.ports import SIMULATED_B6, VIRTUAL, PortInfo, list_ports
from ...i18n import N_, _
from .device_style import ElidedCombo

log = logging.getLogger(__name__)

VIRTUAL_LABEL = N_("Virtual charger (built-in)")
SIMULATED_B6_LABEL = N_("Simulated iMAX B6 (ZUML firmware)")
USBASP_LABEL = N_("iMAX B6 (ZUML) through a USBasp")
FIXED = 3               # the entries before the ports found: the virtual charger, the simulated B6, the B6 through a USBasp
BAUDS = (9600, 19200, 38400, 57600, 115200, 128000, 230400, 460800, 921600)
DEFAULT_BAUD = 115200
REFRESH_MS = 2000


class _ScanSignals(QObject):
    done = Signal(object)           # list[PortInfo]


class _Scan(QRunnable):
    def __init__(self, lister: Callable[[], list[PortInfo]], signals: _ScanSignals):
        super().__init__()
        self.lister = lister
        self.signals = signals

    def run(self) -> None:
        try:
            found = [p for p in self.lister() if not p.virtual and p.device not in (VIRTUAL, SIMULATED_B6)]
        except Exception:   # noqa: BLE001 - a platform quirk must not break the chooser
            log.exception("port scan failed")
            found = []
        self.signals.done.emit(found)


class PortChooser(QWidget):
    """Combo (virtual first, then real ports) + URL field + baud combo."""
    portsScanned = Signal(int)          # number of real ports found (after each scan)
    changed = Signal()

    def __init__(self, lister: Callable[[], list[PortInfo]] | None = None, parent: QWidget | None = None):
        super().__init__(parent)
        self.setObjectName("portChooser")
        self._lister = lister or (lambda: list_ports(include_virtual=False))
        self._pool = QThreadPool(self)
        self._pool.setMaxThreadCount(1)
        self._pool.setExpiryTimeout(3000)
        self._signals = _ScanSignals(self)
        self._signals.done.connect(self._scanned)
        self._scanning = False
        self._closed = False
        self.auto_refresh = True
        self.scans = 0

        self.combo = ElidedCombo()
        self.combo.setObjectName("portCombo")
        self.combo.addItem(_(VIRTUAL_LABEL), VIRTUAL)
        self.combo.addItem(_(SIMULATED_B6_LABEL), SIMULATED_B6)
        self.combo.addItem(_(USBASP_LABEL), USBASP)
        self.combo.setToolTip(_("The charger's port. The built-in virtual charger runs the simulator behind a "
                                "real serial line (a pty), so everything works without hardware. The simulated "
                                "iMAX B6 runs the ZUML firmware's own image on a model of the B6, with its display "
                                "and buttons. An iMAX B6 with the ZUML firmware can also be reached through the ISP "
                                "programmer it was installed with (macros only; runs start on its front panel; the "
                                "battery disconnected)."))
        self.combo.setSizeAdjustPolicy(QComboBox.SizeAdjustPolicy.AdjustToMinimumContentsLengthWithIcon)
        self.combo.setMinimumContentsLength(16)
        self.combo.setSizePolicy(QSizePolicy.Policy.Expanding, QSizePolicy.Policy.Fixed)
        self.url = QLineEdit()
        self.url.setObjectName("portUrl")
        self.url.setPlaceholderText(_("or a port / URL"))      # the examples are in the tooltip
        self.url.setToolTip(_("A port path or URL to use instead of the list: {examples}. Empty: use the list.").format(
            examples="/dev/ttyUSB0, COM3, /dev/pts/3 (`zuml virtual-charger`), socket://127.0.0.1:7777, "
                     "isp:stk500v1@/dev/ttyUSB0 (an avrdude programmer and its port)"))
        self.url.setClearButtonEnabled(True)
        self.url.setSizePolicy(QSizePolicy.Policy.Expanding, QSizePolicy.Policy.Fixed)
        self.baud = QComboBox()
        self.baud.setObjectName("baudCombo")
        for b in BAUDS:
            self.baud.addItem(str(b), b)
        self.baud.setCurrentIndex(BAUDS.index(DEFAULT_BAUD))
        self.baud.setToolTip(_("Baud rate (8N1). ZUML chargers use 115200."))

        layout = QHBoxLayout(self)
        layout.setContentsMargins(0, 0, 0, 0)
        layout.setSpacing(4)
        layout.addWidget(self.combo, 3)
        layout.addWidget(self.url, 3)
        layout.addWidget(self.baud, 0)

        self.combo.activated.connect(self._picked)
        self.combo.currentIndexChanged.connect(lambda _value: self.changed.emit())
        self.url.textChanged.connect(lambda _value: self.changed.emit())
        self._timer = QTimer(self, interval=REFRESH_MS)
        self._timer.timeout.connect(self._tick)

    # -- what the user chose --------------------------------------------------------------------
    def target(self) -> str:
        """``"virtual"`` for the built-in virtual charger, else the port path or URL."""
        typed = self.url.text().strip()
        if typed:
            return typed
        return self.combo.currentData() or VIRTUAL

    def is_virtual(self) -> bool:
        return self.target() == VIRTUAL

    def is_simulated_b6(self) -> bool:
        return self.target() == SIMULATED_B6
    def is_programmer(self) -> bool:
        """The B6 through its ISP programmer (avrdude), not a serial line."""
        return self.target().startswith(ISP_SCHEME)

    def baudrate(self) -> int:
        return int(self.baud.currentData() or DEFAULT_BAUD)

    def set_target(self, text: str) -> None:
        """Pick ``"virtual"`` or a listed port, or type anything else into the URL field."""
        if text in (VIRTUAL, SIMULATED_B6) or not text:
            self.url.clear()
            self.combo.setCurrentIndex(self.combo.findData(text or VIRTUAL))
            return
        index = self.combo.findData(text)
        if index >= 0:
            self.url.clear()
            self.combo.setCurrentIndex(index)
        else:
            self.url.setText(text)

    def _picked(self, _index: int) -> None:
        self.url.clear()                # picking from the list means: use the list

    def ports(self) -> list[str]:
        return [self.combo.itemData(i) for i in range(FIXED, self.combo.count())]

    # -- scanning ---------------------------------------------------------------------------------
    def refresh(self) -> bool:
        """Start a scan in the background (False if one is running)."""
        if self._scanning or self._closed:
            return False
        self._scanning = True
        self._pool.start(_Scan(self._lister, self._signals))
        return True

    def _tick(self) -> None:
        if self.auto_refresh and self.isVisible():
            self.refresh()

    def _scanned(self, found: list[PortInfo]) -> None:
        self._scanning = False
        if self._closed:
            return
        self.scans += 1
        current = self.combo.currentData()
        wanted = [(p.label(), p.device) for p in found]
        have = [(self.combo.itemText(i), self.combo.itemData(i)) for i in range(FIXED, self.combo.count())]
        if wanted != have:
            self.combo.blockSignals(True)
            while self.combo.count() > FIXED:
                self.combo.removeItem(FIXED)
            for label, device in wanted:
                self.combo.addItem(label, device)
                self.combo.setItemData(self.combo.count() - 1, label, 3)     # Qt.ToolTipRole
            index = self.combo.findData(current)
            self.combo.setCurrentIndex(index if index >= 0 else 0)
            self.combo.blockSignals(False)
            if index < 0:
                self.changed.emit()
        self.portsScanned.emit(len(found))

    def showEvent(self, event) -> None:  # noqa: N802
        super().showEvent(event)
        if not self._closed:
            self.refresh()
            self._timer.start()

    def hideEvent(self, event) -> None:  # noqa: N802
        super().hideEvent(event)
        self._timer.stop()

    def shutdown(self, wait_ms: int = 3000) -> None:
        """Stop scanning and wait for a scan in flight."""
        self._closed = True
        self._timer.stop()
        self._pool.clear()
        self._pool.waitForDone(wait_ms)
