"""A live run as a session: the telemetry of one run, from its START to its end, collected as it comes
(from the reader thread), written as a CSV the log readers read back (``logs.export``), and imported
into the pack its port or passport serial is attached to."""
from __future__ import annotations

import datetime as dt
import re
import threading
from pathlib import Path

from ..protocol.messages import Telemetry
from ..logs.export import write_csv
from ..logs.model import from_samples
from ..user_dirs import data_dir
from .db import Logbook
from .register import Pack
from .sessions import ImportResult, import_file
from ..i18n import _


def runs_dir() -> Path:
    return data_dir() / "runs"


class RunCollector:
    """The samples of the run being recorded; ``add`` is called from the reader thread."""

    def __init__(self) -> None:
        self._lock = threading.Lock()
        self._samples: list[Telemetry] = []
        self._on = False

    def start(self) -> None:
        with self._lock:
            self._samples, self._on = [], True

    def add(self, tel: Telemetry) -> None:
        with self._lock:
            if self._on:
                self._samples.append(tel)

    @property
    def collecting(self) -> bool:
        return self._on

    def take(self) -> list[Telemetry]:
        """The run's samples; collecting stops."""
        with self._lock:
            samples, self._samples, self._on = self._samples, [], False
        return samples


def record_run(book: Logbook, pack: Pack, samples: list[Telemetry], device: str, *,
               passport: tuple[int | None, int | None] = (None, None), folder: Path | None = None) -> ImportResult:
    """Write the run as ``<folder>/<pack> <UTC time>.csv`` and import it as a live session of ``pack``.
    The file is created, never overwritten: a second run in the same second, or a pack whose name
    reads the same once made safe for a file name, gets ``… (2).csv``."""
    if not samples:
        return ImportResult("", "error", _("the run recorded no sample"))
    folder = folder or runs_dir()
    stamp = dt.datetime.now(dt.timezone.utc).strftime("%Y-%m-%d %H%M%S")
    safe = re.sub(r"[^\w .,+()-]", "_", pack.name)
    path = folder / f"{safe} {stamp}.csv"
    try:
        folder.mkdir(parents=True, exist_ok=True)
        fh, path = _create(folder, f"{safe} {stamp}")
        with fh:
            write_csv(from_samples("live", device, samples), fh)
    except OSError as exc:
        return ImportResult(str(path), "error", _("{path}: cannot write: {error}").format(
                path=path, error=exc.strerror or exc))
    return import_file(book, pack, path, source="live", passport=passport)


def _create(folder: Path, stem: str, tries: int = 1000):
    """A new file ``stem.csv`` (``stem (2).csv``… where that exists), opened for writing: never one
    that is there already (exclusive create, so two writers at once cannot take the same name)."""
    for n in range(1, tries + 1):
        path = folder / (f"{stem}.csv" if n == 1 else f"{stem} ({n}).csv")
        try:
            return open(path, "x", encoding="utf-8", newline=""), path
        except FileExistsError:
            continue
    raise FileExistsError(f"{folder / stem}.csv and {tries - 1} numbered names")
