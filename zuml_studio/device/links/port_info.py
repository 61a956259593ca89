"""One port as the port list shows it: a module of its own because both the list (`ports`) and the
HID scan it calls (`hid_link`) make them."""
from __future__ import annotations

from dataclasses import dataclass

from ...i18n import _

VIRTUAL = "virtual"
SIMULATED_B6 = "simulated-b6"      # the window's simulated iMAX B6 (virtual/simulated_b6.py)


@dataclass(frozen=True)
class PortInfo:
    device: str               # what ChargerClient opens: /dev/ttyUSB0, COM3, socket://..., or "virtual"
    description: str
    hwid: str = ""
    vid: int | None = None
    pid: int | None = None
    virtual: bool = False

    def label(self) -> str:
        ids = f" [{self.vid:04X}:{self.pid:04X}]" if self.vid is not None and self.pid is not None else ""
        return f"{self.device} - {_(self.description) if self.virtual else self.description}{ids}"
