"""USB-HID chargers through the ``hidapi`` package, imported only when a HID port is listed
or opened: a machine without hidapi/libusb runs everything else.

A HID charger's port is written ``hid:VVVV:PPPP`` (hex vendor and product id), with ``:N``
for the N-th of several identical devices. SkyRC's chargers report the unregistered ids
0000:0001, so devices are matched on exact ids, never by enumerating with a zero filter.
"""
from __future__ import annotations

from ...streams.drivers import HID_DRIVERS, Driver
from ..errors import DeviceLinkError, PortNotFound, line_closed
from .port_info import PortInfo
from ...i18n import _

PREFIX = "hid:"
REPORT = 64


def _hid():
    try:
        import hid
    except ImportError as exc:
        raise DeviceLinkError(_("USB-HID chargers need the hidapi package (pip install hidapi): {exc}").format(
                exc=exc)) from None
    return hid


def driver_for(vid: int, pid: int) -> Driver | None:
    for d in HID_DRIVERS:
        if (vid, pid) in d.vid_pids:
            return d
    return None


def _matching() -> list[dict]:
    try:
        found = _hid().enumerate()
    except DeviceLinkError:
        return []
    except Exception:   # noqa: BLE001 - a platform quirk must not break the port list
        return []
    return [d for d in found if driver_for(d.get("vendor_id", -1), d.get("product_id", -1)) is not None]


def list_hid_chargers() -> list[PortInfo]:
    """The HID chargers plugged in now (empty without hidapi)."""
    out: list[PortInfo] = []
    seen: dict[tuple[int, int], int] = {}
    for d in _matching():
        vid, pid = d["vendor_id"], d["product_id"]
        n = seen.get((vid, pid), 0)
        seen[(vid, pid)] = n + 1
        drv = driver_for(vid, pid)
        name = d.get("product_string") or drv.title
        out.append(PortInfo(f"{PREFIX}{vid:04x}:{pid:04x}" + (f":{n}" if n else ""), f"{name} (USB HID)",
                            f"USB VID:PID={vid:04X}:{pid:04X}", vid, pid))
    return out


def parse_port(port: str) -> tuple[int, int, int]:
    parts = port[len(PREFIX):].split(":")
    try:
        vid, pid = int(parts[0], 16), int(parts[1], 16)
        index = int(parts[2]) if len(parts) > 2 else 0
        if len(parts) > 3 or not (0 <= vid <= 0xFFFF and 0 <= pid <= 0xFFFF) or index < 0:
            raise ValueError
    except (ValueError, IndexError):
        raise DeviceLinkError(_("{port}: write a HID port as hid:VVVV:PPPP (hex ids), e.g. hid:0483:5751").format(
                port=port)) from None
    return vid, pid, index


class HidPort:
    """One open HID charger: ``read(timeout_s) -> bytes`` (a report or b""), ``write(bytes)``."""

    def __init__(self, port: str):
        vid, pid, index = parse_port(port)
        hid = _hid()
        found = [d for d in hid.enumerate() if d.get("vendor_id") == vid and d.get("product_id") == pid]
        if index >= len(found):
            raise PortNotFound(_("{port}: no such USB device plugged in (run `zuml ports`)").format(port=port))
        self.port = port
        self.vid, self.pid = vid, pid
        self._dev = hid.device()
        try:
            self._dev.open_path(found[index]["path"])
        except (OSError, IOError) as exc:
            raise DeviceLinkError(_("{port}: cannot open: {exc} (on Linux a udev rule gives your user access to "
                                    "{vid:04x}:{pid:04x})").format(port=port, exc=exc, vid=vid, pid=pid)) from None

    def read(self, timeout_s: float) -> bytes:
        try:
            return bytes(self._dev.read(REPORT, max(1, int(timeout_s * 1000))))
        except (OSError, IOError, ValueError) as exc:
            # hidapi's words ("read error") say nothing more: the same sentence as every other link.
            raise DeviceLinkError(f"{self.port}: {line_closed()}") from None

    def write(self, data: bytes) -> None:
        try:
            self._dev.write(b"\x00" + bytes(data).ljust(REPORT, b"\x00"))
        except (OSError, IOError, ValueError) as exc:
            raise DeviceLinkError(_("{port}: cannot write: {exc}").format(port=self.port, exc=exc)) from None

    def close(self) -> None:
        try:
            self._dev.close()
        except Exception:   # noqa: BLE001
            pass
