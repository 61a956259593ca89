"""Crash recovery for unsaved editor text, without Qt.

While a document has unsaved changes its text is written after every change (once typing
pauses: the editor's debounced check) to
``<config>/recovery/<key>.zuml`` with a small JSON note beside it (which file it
belongs to, when). A clean save or close removes both. Whatever is still there
at the next start was left by a crash and is offered back.
"""
from __future__ import annotations

import hashlib
import io
import json
import logging
import math
import os
import stat
import threading
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import BinaryIO, TextIO

from .user_dirs import config_dir


log = logging.getLogger(__name__)


def atomic_write(path: Path, data: bytes, sync: bool = True, parents: bool = True) -> None:
    """Write beside the target, then rename over it: a crash never leaves half a file (see ``atomic_file``)."""
    with atomic_file(path, sync=sync, parents=parents) as fh:
        fh.write(data)


@contextmanager
def atomic_file(path: str | Path, sync: bool = True, parents: bool = False) -> Iterator[BinaryIO]:
    """A binary file to write that replaces ``path`` only when the block ends without an error:
    a failure (a full disk) leaves the old file whole and no temporary file behind. With ``sync``
    the data reaches the disk before the rename (survives the system crashing too). A symbolic
    link is followed (the link stays, the file it names is replaced). A target that is no regular
    file (/dev/stdout, a device, a pipe) is written into: renaming over it would replace the device
    node itself (``zuml new -o /dev/full`` run as root did). ``parents``: make missing folders
    (the configuration's), else a missing folder is the error it is (a mistyped output path)."""
    path = Path(os.path.realpath(path))
    try:
        mode = path.stat().st_mode
    except FileNotFoundError:
        mode = None
    if mode is not None and not stat.S_ISREG(mode):
        with open(path, "wb") as fh:
            yield fh
        return
    if parents:
        path.parent.mkdir(parents=True, exist_ok=True)
    tmp = path.with_name(f".{path.name}.{os.getpid()}.tmp")
    try:
        with open(tmp, "wb") as fh:
            yield fh
            fh.flush()
            if sync:
                os.fsync(fh.fileno())
        os.replace(tmp, path)
    except BaseException:
        try:
            tmp.unlink()
        except OSError:
            pass                # never made, or gone with its directory: nothing left behind
        raise


@contextmanager
def atomic_text_file(path: str | Path, sync: bool = True) -> Iterator[TextIO]:
    """``atomic_file`` as UTF-8 text, lines ended as written (what ``csv`` needs); no folder is made."""
    with atomic_file(path, sync) as fh:
        text = io.TextIOWrapper(fh, encoding="utf-8", newline="")
        try:
            yield text
        finally:
            text.detach()       # flushes; the binary file stays open for atomic_file to finish


def _alive(pid: int) -> bool:
    if not 0 < pid < 2 ** 31:          # no such process can exist (and os.kill would overflow or signal a group)
        return False
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except (PermissionError, OSError):
        return True
    return True


def _seconds(value: object) -> float:
    """A note's time, NaN when it is no number (a bool, a string, an integer past any float)."""
    try:
        return float(value) if type(value) in (int, float) else math.nan
    except OverflowError:
        return math.nan


@dataclass(frozen=True)
class Recovered:
    key: str
    text: str
    original: str | None        # the file the text belongs to, None for an untitled document
    saved_at: float


class RecoveryStore:
    def __init__(self, root: Path | None = None):
        self.root = (root or config_dir()) / "recovery"

    @staticmethod
    def key_for(original: str | None, untitled_id: str) -> str:
        seed = os.path.abspath(original) if original else f"untitled:{untitled_id}"
        return hashlib.sha1(seed.encode("utf-8")).hexdigest()[:16]

    def save(self, key: str, text: str, original: str | None) -> None:
        # Not synced: the window saves on the GUI thread after every pause in typing, and an
        # fsync there took up to 13 ms on a busy disk. What this guards against is the
        # program crashing, which the written file survives; the user's own saves are synced.
        atomic_write(self.root / f"{key}.zuml", text.encode("utf-8"), sync=False)
        note = {"original": original, "saved_at": time.time(), "pid": os.getpid()}
        atomic_write(self.root / f"{key}.json", json.dumps(note).encode("utf-8"), sync=False)

    def discard(self, key: str) -> None:
        for suffix in (".zuml", ".json"):
            try:
                (self.root / f"{key}{suffix}").unlink()
            except OSError:         # gone already, or unreachable: at worst it is offered back once
                pass

    def pending(self, own_key: str = "") -> list[Recovered]:
        """Texts left behind, newest first; a damaged note still gives its text back (a field of
        the wrong type reads as missing). Texts of another ZUML Studio still running (its process
        alive) are not left behind, nor is ``own_key``."""
        found: list[Recovered] = []
        if not self.root.is_dir():
            return found
        for text_file in self.root.glob("*.zuml"):
            key = text_file.stem
            note: dict = {}
            try:
                note = json.loads((self.root / f"{key}.json").read_text(encoding="utf-8"))
            except (OSError, ValueError):
                pass
            if not isinstance(note, dict):
                note = {}
            pid = note.get("pid")
            if key == own_key or (type(pid) is int and pid != os.getpid() and _alive(pid)):
                continue
            try:
                text = text_file.read_bytes().decode("utf-8", errors="replace")
            except OSError:
                continue
            saved_at, original = _seconds(note.get("saved_at")), note.get("original")
            if not math.isfinite(saved_at):
                try:
                    saved_at = text_file.stat().st_mtime
                except OSError:
                    continue
            found.append(Recovered(key, text, original if isinstance(original, str) and original else None,
                                   saved_at))
        return sorted(found, key=lambda r: -r.saved_at)


class BackgroundSaver:
    """A store's saves on a thread of their own, so typing never waits for the disk (a write and
    a rename took up to 13 ms each on a busy one). The newest text of a key replaces one not yet
    written; a discard waits for the writes before it. ``on_error`` gets an OSError, on the
    saver's thread."""

    def __init__(self, store: RecoveryStore, on_error: Callable[[OSError], None]):
        self.store = store
        self._on_error = on_error
        self._pending: dict[str, tuple[str, str | None]] = {}
        self._writing = False
        self._cond = threading.Condition()
        self._thread: threading.Thread | None = None

    def save(self, key: str, text: str, original: str | None) -> None:
        with self._cond:
            self._pending[key] = (text, original)
            if self._thread is None:
                self._thread = threading.Thread(target=self._run, name="recovery-saver", daemon=True)
                self._thread.start()
            self._cond.notify_all()

    def wait(self) -> None:
        """Until every text handed over has been written (or has failed)."""
        with self._cond:
            while self._pending or self._writing:
                self._cond.wait()

    def discard(self, key: str) -> None:
        self.wait()
        self.store.discard(key)

    def close(self) -> None:
        """Write what is pending, then end the thread (a later save starts another)."""
        with self._cond:
            thread, self._thread = self._thread, None
            self._cond.notify_all()
        if thread is not None:
            thread.join()

    def _run(self) -> None:
        me = threading.current_thread()
        while True:
            with self._cond:
                while not self._pending and self._thread is me:
                    self._cond.wait()
                if not self._pending:
                    return
                jobs, self._pending = self._pending, {}
                self._writing = True
            try:
                for key, (text, original) in jobs.items():
                    try:
                        self.store.save(key, text, original)
                    except OSError as exc:
                        self._said(exc)
            finally:
                with self._cond:
                    self._writing = False
                    self._cond.notify_all()

    def _said(self, exc: OSError) -> None:
        try:
            self._on_error(exc)
        except Exception:  # the receiver is gone (its window closed): the saver goes on
            log.exception("reporting a failed recovery write failed")
