"""Which reader reads a file: recognised by its bytes (``sniff``), the name only as a hint.

Adding a format is one ``LogReader`` entry in ``FORMATS``: a name, ``sniff(first bytes, file
name) -> bool`` and ``read(bytes) -> Log``. A reader that gets ready samples from elsewhere
(a live driver's decoder: ``raw_capture``, ``lov``) builds its Log with
``model.from_samples(format, device, samples, bad_records)``. More specific formats come
first: the first that recognises the bytes reads them (the raw capture reader comes late:
DUO/X logs and LogView text are ``$`` lines too; any CSV with a header comes last)."""
from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from ..file_errors import FileReadError, read_file_bytes
from . import csv_import, dataexplorer_csv, junsi, logview_open, lov, osd, raw_capture, session_csv
from .model import Log, LogFormatError
from ..i18n import _

HEAD_BYTES = 4096


@dataclass(frozen=True)
class LogReader:
    name: str
    description: str
    sniff: Callable[[bytes, str], bool]
    read: Callable[[bytes], Log]
    # A reader that can tell how far it is: read(bytes, progress(done, total)).
    read_with_progress: Callable[[bytes, Callable[[int, int], None]], Log] | None = None


FORMATS: tuple[LogReader, ...] = (
    LogReader("logview-lov", "LogView .lov (iCharger serial models, cheali, iMAX B6, Ultramat)", lov.sniff,
              lov.read),
    LogReader("dataexplorer-osd", "DataExplorer .osd", osd.sniff, osd.read),
    LogReader("session-csv", "ZUML Studio session CSV", session_csv.sniff, session_csv.read),
    LogReader("icharger-duo-txt", "Junsi iCharger DUO/X/S text log", junsi.sniff_duo, junsi.read_duo),
    LogReader("logview-open", "LogView open format text", logview_open.sniff, logview_open.read),
    LogReader("dataexplorer-csv", "DataExplorer CSV export", dataexplorer_csv.sniff, dataexplorer_csv.read),
    LogReader(raw_capture.FORMAT, "raw capture of a charger's serial stream or HID reports", raw_capture.sniff,
              raw_capture.read, raw_capture.read),
    LogReader(csv_import.FORMAT, "CSV with a header (columns guessed)", csv_import.sniff, csv_import.read,
              lambda data, progress: csv_import.read(data, None, progress)),
)
BY_NAME = {f.name: f for f in FORMATS}


def detect(data: bytes, name: str = "") -> LogReader:
    head = data[:HEAD_BYTES]
    for reader in FORMATS:
        if reader.sniff(head, name):
            return reader
    tried = ", ".join(f.description for f in FORMATS)
    raise LogFormatError(_("not a log file ZUML Studio reads (tried: {tried})").format(tried=tried))


def read_log(data: bytes, name: str = "", fmt: str | None = None,
             progress: Callable[[int, int], None] | None = None) -> Log:
    """Read a log; ``fmt`` forces a format by name. Raises ``LogFormatError`` with the reason.
    ``progress(done, total)`` is called as the reading goes where the reader can tell (raw captures:
    the long reads)."""
    if fmt is not None:
        reader = BY_NAME.get(fmt)
        if reader is None:
            raise LogFormatError(_("unknown log format '{fmt}' (known: {by_name})").format(
                    fmt=fmt, by_name=', '.join(BY_NAME)))
    else:
        if not data:
            raise LogFormatError(_("the file is empty"))
        reader = detect(data, name)
    if progress is not None and reader.read_with_progress is not None:
        return reader.read_with_progress(data, progress)
    return reader.read(data)


def read_log_file(path: str | Path, fmt: str | None = None,
                  progress: Callable[[int, int], None] | None = None) -> Log:
    """``read_log`` of a file; a file that cannot be read or decoded raises ``LogFormatError``
    whose message starts with the path."""
    try:
        data = read_file_bytes(path, pipes=False)
    except FileReadError as exc:
        raise LogFormatError(str(exc)) from None
    try:
        return read_log(data, Path(path).name, fmt, progress)
    except LogFormatError as exc:
        raise LogFormatError(f"{path}: {exc}") from None
