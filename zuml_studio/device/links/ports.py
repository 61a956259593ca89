"""Which ports there are: real serial ports (``serial.tools.list_ports``), USB-HID chargers
(``hid_link``, when hidapi is installed) and the built-in virtual charger. pyserial never lists ptys, so a virtual charger served on a pty (or TCP)
is reached by the path or URL it prints. Scanning can take a while on some systems: call
this off the GUI thread or on a slow timer (>= 1 s)."""
from __future__ import annotations

from ...i18n import N_, _
from .port_info import SIMULATED_B6, VIRTUAL, PortInfo  # noqa: F401 - the names callers take from here

# Its description is shown through _() (PortInfo.label), so the list follows the installed language.
VIRTUAL_PORT = PortInfo(VIRTUAL, N_("built-in virtual charger (the simulator behind the protocol)"), virtual=True)


def list_ports(include_virtual: bool = True, include_hid: bool = True) -> list[PortInfo]:
    """Real serial ports sorted by name, the HID chargers plugged in, then the virtual charger entry."""
    out: list[PortInfo] = []
    try:
        from serial.tools import list_ports as lp
        found = lp.comports()
    except Exception:   # noqa: BLE001 - a platform quirk must not break the port list
        found = []
    for p in sorted(found, key=lambda p: p.device):
        desc = p.description if p.description and p.description != "n/a" else (p.product or _("serial port"))
        out.append(PortInfo(p.device, desc, p.hwid or "", p.vid, p.pid))
    if include_hid:
        from .hid_link import list_hid_chargers
        out += list_hid_chargers()
    if include_virtual:
        out.append(VIRTUAL_PORT)
    return out
