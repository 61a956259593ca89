"""Raw captures of a monitor-only charger's stream (``$`` lines, ``{…}`` frames, Ultramat
frames, HID report dumps, the text forms of the shared samples): decoded by the live
drivers (``streams.drivers.decode_recording``), so a file and a port read the same.

Sniffed on the first bytes: a capture is recognised when a driver finds more records in them
that pass their checksum (decoded, or well-formed without a measurement: the first frames
of a file may be a model whose layout is not known) than bad ones. This reader comes last:
DUO/X logs and LogView text are ``$`` lines too."""
from __future__ import annotations

from collections.abc import Callable

from ..streams.drivers import DRIVERS, CaptureError, capture_streams, decode_recording
from .model import Log, LogFormatError, from_samples

FORMAT = "raw-capture"


def sniff(head: bytes, name: str) -> bool:
    for stream in capture_streams(head):
        for driver in DRIVERS.values():
            dec = driver.decoder()
            dec.feed(stream)
            if dec.good + dec.skipped > dec.bad:
                return True
    return False


def read(data: bytes, progress: Callable[[int, int], None] | None = None) -> Log:
    """``progress(bytes decoded, bytes)`` while a long capture is decoded (``decode_recording``)."""
    try:
        capture = decode_recording(data, progress=progress)
    except CaptureError as exc:
        raise LogFormatError(str(exc)) from None
    return from_samples(FORMAT, DRIVERS[capture.driver].title, capture.samples, capture.bad,
                        driver=capture.driver)
