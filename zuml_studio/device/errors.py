"""What can go wrong on the device link, each with a message a user can act on.

Every error is a ``DeviceLinkError`` and says itself (``ZumlError.words``): the CLI prints it on one
line, the GUI shows it in a dialog, both through ``error_words.describe_error``. None of them carries
a traceback-worthy surprise.
"""
from __future__ import annotations

import errno

from .links.port_access import refused_advice
from ..errors import ZumlError, error_text
from ..i18n import _


class DeviceLinkError(ZumlError):
    """Base class of every device-link failure."""

    def words(self, action: str = "") -> str:
        if action == "connect":
            return _("Cannot connect: {error}").format(error=error_text(self))
        return super().words(action)


class PortNotFound(DeviceLinkError):
    """The port does not exist (unplugged, mistyped) or nothing listens at a socket:// address."""


class PermissionDenied(DeviceLinkError):
    """errno 13 opening the port."""

    def __init__(self, port: str, detail: str = ""):
        super().__init__(_("{port}: permission denied; {refused_advice}").format(
                port=port, refused_advice=refused_advice(port)))
        self.port = port
        self.detail = detail


class PortBusy(DeviceLinkError):
    """errno 16, or another program holds the port's exclusive lock."""

    def __init__(self, port: str, detail: str = ""):
        super().__init__(_("{port}: the port is busy: another program (a serial monitor, another ZUML Studio?) "
                           "has it open; close it and try again").format(port=port))
        self.port = port
        self.detail = detail


class NotACharger(DeviceLinkError):
    """The port opened, but nothing answered IDENTIFY the way a ZUML charger does."""


class NoisyLine(DeviceLinkError):
    """The charger answers IDENTIFY, but its answers arrive damaged: the line, not the port, is wrong."""


class DeviceTimeout(DeviceLinkError):
    """A request got no valid answer after every retry."""

    def words(self, action: str = "") -> str:
        text = error_text(self)
        if action == "flash":
            return _("The charger stopped answering while flashing: nothing was written, the charger keeps its "
                     "previous image. ({error})").format(error=text)
        if action == "restore":
            return _("The charger stopped answering while restoring: nothing was written, the charger keeps its "
                     "previous image. ({error})").format(error=text)
        if action == "connect":
            return super().words(action)
        return _("the charger does not answer: {error}").format(error=text)


class Disconnected(DeviceLinkError):
    """The link went away (cable pulled, the virtual charger stopped, the port closed)."""

    def words(self, action: str = "") -> str:
        text = error_text(self)
        if action == "flash":
            return _("The connection was lost while flashing: nothing was written, the charger keeps its "
                     "previous image. ({error})").format(error=text)
        if action == "restore":
            return _("The connection was lost while restoring: nothing was written, the charger keeps its "
                     "previous image. ({error})").format(error=text)
        if action == "connect":
            return super().words(action)
        return _("not connected: {error}").format(error=text)


class _AfterCommit(DeviceLinkError):
    """A link failure once COMMIT had gone out: ``image`` is what was written, ``previous`` what
    the EEPROM held before; ``settle`` tells from a fresh read (after reconnecting) which is there.
    ``token``: the write's token, the host's random nonce when the charger took it (``nonce_taken``),
    so that ``ChargerClient.committed`` can ask a charger whether it is the one that committed it."""

    holds = "either"

    def __init__(self, message: str, image: bytes = b"", previous: bytes = b"", token: int = 0,
                 nonce_taken: bool = False):
        super().__init__(message)
        self.image = image
        self.previous = previous
        self.token = token
        self.nonce_taken = nonce_taken

    def settle(self, now: bytes) -> str:
        """"new", "previous" or "other" (the EEPROM changed since, by another hand)."""
        if now == self.image:
            return "new"
        return "previous" if now == self.previous else "other"


class CommitUncertain(_AfterCommit):
    """The link failed after COMMIT went out and before the charger confirmed it. A commit is
    all or nothing, so the charger holds either the new image or its previous one; which, only
    a fresh read can tell."""

    def words(self, action: str = "") -> str:
        if action in ("flash", "restore"):
            return _("The connection was lost just as the charger committed the new image: it holds either the "
                     "new image or its previous one, never a mix. Reconnect: the image is read back then and "
                     "which one said. ({error})").format(error=error_text(self))
        return super().words(action)


class CommitUnverified(_AfterCommit):
    """The charger confirmed COMMIT (it holds the new image), then the link failed during the
    read-back that verifies it."""

    holds = "new"

    def words(self, action: str = "") -> str:
        if action in ("flash", "restore"):
            return _("The charger confirmed the new image, then the connection was lost while reading it back to "
                     "verify it. Reconnect: the image is read back then and the result said. ({error})").format(
                         error=error_text(self))
        return super().words(action)


class ImageTooLarge(DeviceLinkError):
    """An EEPROM image larger than the device's EEPROM."""

    def __init__(self, size: int, eeprom_size: int):
        super().__init__(_("the image is {size} bytes; the charger's EEPROM holds {eeprom_size}").format(
                size=size, eeprom_size=eeprom_size))
        self.size = size
        self.eeprom_size = eeprom_size

    def words(self, action: str = "") -> str:
        if action in ("flash", "restore"):
            return _("The image needs {needed} bytes; the charger has {size}. Nothing was written.").format(
                needed=self.size, size=self.eeprom_size)
        return super().words(action)


class InvalidImage(DeviceLinkError):
    """An image whose records do not decode (refused before anything is written)."""

    def words(self, action: str = "") -> str:
        if action in ("flash", "restore"):
            return _("Nothing was written: {error}").format(error=error_text(self))
        return super().words(action)


class VerifyFailed(DeviceLinkError):
    """The EEPROM read back after a write differs from the image written."""

    def words(self, action: str = "") -> str:
        if action in ("flash", "restore"):
            return _("The write did not verify: {error}. Flash again, or restore a backup.").format(
                error=error_text(self))
        return super().words(action)


class DeviceError(DeviceLinkError):
    """The charger answered a request with an ERROR frame.

    ``code`` is one of ``messages.ErrorCode``; ``lines`` is the message split into its
    sentences (a refused START lists one passport conflict per line).
    """

    def __init__(self, code: int, message: str, request_type: int = 0):
        self.code = code
        self.message = message
        self.request_type = request_type
        self.lines = [line for line in message.split("\n") if line]
        super().__init__("; ".join(self.lines) or _("device error {code}").format(code=code))

    def words(self, action: str = "") -> str:
        text = error_text(self)
        if action in ("flash", "restore"):
            return _("The charger refused the write: {error}. Nothing was written.").format(error=text)
        if action == "start":
            return _("The charger refused to start:") + "\n" + "\n".join(f"• {line}" for line in self.lines or [text])
        if action == "connect":
            return super().words(action)
        return _("the charger refused: {exc}").format(exc=text)

    @property
    def code_name(self) -> str:
        from ..protocol.messages import ErrorCode
        try:
            return ErrorCode(self.code).name
        except ValueError:
            return f"ERROR_{self.code}"


def why_lost(exc: Exception) -> str:
    """Why a link ended, without pyserial's guess: "returned no data (device disconnected or multiple
    access on port?)" is what any closed pty or socket says, and nothing here shares a port; EIO is
    what a pty or USB adapter whose other end went away says on the next read."""
    text = str(exc)
    if "returned no data" in text or "multiple access" in text or getattr(exc, "errno", None) == errno.EIO \
            or "[Errno 5]" in text:
        return line_closed()
    return text


def line_closed() -> str:
    """The one sentence for a charger that went away, whatever link it was on (serial, pty, USB-HID)."""
    return _("the charger closed the line: it stopped, or its cable was pulled")
