"""Opening a serial port (a device path or a pyserial URL) with its failures turned into DeviceLinkErrors a
user can act on: the ZUML firmware's client and the monitor link both open their line here."""
from __future__ import annotations

import errno

from ...i18n import _
from ..errors import DeviceLinkError, PermissionDenied, PortBusy, PortNotFound
from .port_access import vanished_hint
from .port_url import check_port_url

READ_POLL_S = 0.02


def open_serial(url: str, baudrate: int, exclusive: bool = True):
    """``serial.serial_for_url`` with its failures turned into DeviceLinkErrors."""
    import serial
    check_port_url(url)
    kwargs = dict(baudrate=baudrate, timeout=READ_POLL_S, write_timeout=5)
    try:
        try:
            return serial.serial_for_url(url, exclusive=exclusive, **kwargs)
        except TypeError:             # a URL handler without the exclusive option
            return serial.serial_for_url(url, **kwargs)
    except serial.SerialException as exc:
        raise _open_error(url, exc) from None
    except (ValueError, OSError) as exc:
        raise DeviceLinkError(_("{url}: cannot open: {exc}").format(url=url, exc=exc)) from None


def _open_error(url: str, exc: Exception) -> DeviceLinkError:
    code = getattr(exc, "errno", None)
    text = str(exc)
    low = text.lower()
    if "access is denied" in low:                       # Windows: another program has the port
        return PortBusy(url, text)
    if code == errno.EACCES or "permission denied" in low or "errno 13" in low:
        return PermissionDenied(url, text)
    if code in (errno.EBUSY, errno.EAGAIN) or "busy" in low or "exclusively lock" in low or "errno 16" in low:
        return PortBusy(url, text)
    if code == errno.ENOENT or "no such file" in low or "errno 2]" in low or "filenotfound" in low:
        return PortNotFound(_("{url}: no such port (unplugged? run `zuml ports`).{vanished_hint}").format(
                url=url, vanished_hint=vanished_hint(url)))
    if "refused" in low or code == errno.ECONNREFUSED:
        return PortNotFound(_("{url}: nothing listens there (is the virtual charger running?)").format(url=url))
    return DeviceLinkError(_("{url}: cannot open: {text}").format(url=url, text=text))
