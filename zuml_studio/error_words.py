"""The one wording of any error for a user, shared by the window and the command line (no Qt).

ZUML Studio's own errors (`errors.ZumlError`) carry their words; this module adds only what
concerns every error alike and those of other libraries: Python's OSError (pyserial's
``SerialException`` and hidapi's failures are OSErrors too), a ValueError, and anything else, which is
a bug and said as one. It sits just above `i18n` (which it needs for its words) and knows no package
that raises the errors, so that every package's user interface may call it."""
from __future__ import annotations

from .errors import ZumlError, error_text
from .i18n import _


def describe_error(exc: BaseException, action: str = "", sentence: bool = True) -> str:
    """One clear sentence (or a few lines) for an error, never a traceback.

    ``action``: what the user was doing: connect, flash, restore, backup, start, stop, passport, link
    (the link went away by itself), slots; "" for none. ``sentence``: start with a capital, as the
    window shows it; False keeps the message's own case, as the command line prints it after
    ``zuml: error:``."""
    text = error_text(exc)
    if action == "link":
        return _("Disconnected: {error}").format(error=text)
    if action == "connect" and isinstance(exc, ValueError):       # a virtual charger set up wrong (battery, speed)
        words = _("Cannot start the virtual charger: {error}").format(error=text)
    elif isinstance(exc, ZumlError):
        words = exc.words(action)
    elif isinstance(exc, OSError):
        if action == "connect":
            return _("Cannot connect: {error}").format(error=exc.strerror or text)
        return f"{getattr(exc, 'filename', '') or ''} {exc.strerror or text}".strip()
    elif isinstance(exc, ValueError):
        words = text
    else:
        return _("Internal error: {error}").format(error=f"{type(exc).__name__}: {text}")
    return words[:1].upper() + words[1:] if sentence else words
