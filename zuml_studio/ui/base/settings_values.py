"""Values read back from settings.ini, which a user may have edited by hand: QSettings gives a
list for a value with a comma, a string for a byte array without its @ByteArray(...) wrapper,
and whatever type a garbled @Variant(...) says. A value of the wrong type reads as the default."""
from __future__ import annotations

from PySide6.QtCore import QByteArray, QSettings


def text_value(settings: QSettings, key: str, default: str) -> str:
    value = settings.value(key, default)
    return value if isinstance(value, str) else default


def bytes_value(settings: QSettings, key: str) -> QByteArray | None:
    """A saved geometry or window state, None when missing or not bytes."""
    value = settings.value(key)
    return value if isinstance(value, QByteArray) else None
