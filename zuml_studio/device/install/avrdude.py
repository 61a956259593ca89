"""Running avrdude: one run of it with a programmer, watched so that it always ends, and its failure as one
line. The firmware install (avr_install.py) and the macro store written through the programmer
(isp_store.py) both go through ``run_avrdude``.

While avrdude runs, the programmer holds the ATmega32 in reset: the firmware stops at once and its pins
float (the stage's disable lines too) until avrdude lets go, when the firmware starts afresh."""
from __future__ import annotations

import shutil
import subprocess
import threading
import time
from dataclasses import dataclass
from pathlib import Path

from ...i18n import _
from ..errors import DeviceLinkError

PART = "m32"
AVRDUDE_INSTALL = "apt-get install avrdude"
# avrdude quiet this long is stuck (its programmer gone), not slow: see _watched
SILENCE_S = 60.0
# No run of ours lasts this long (a USBasp reads or writes the whole 32 KB flash, verify included, in well
# under a minute): an avrdude that keeps printing (retrying a programmer that does not answer) is stopped.
TOTAL_S = 300.0


class ProgrammerError(DeviceLinkError):
    """A precise one-line reason an operation through the programmer stopped (and what was already done): the
    programmer is the link to the charger here."""


class AvrdudeStopped(ProgrammerError):
    """avrdude was stopped by us (silent or running too long): whatever it was writing is half-written."""


@dataclass(frozen=True)
class Programmer:
    """How avrdude reaches the chip: its programmer id (``-c``: usbasp, stk500v1, ...), port and baud."""
    name: str = "usbasp"
    port: str | None = None
    baud: int | None = None

    def options(self) -> str:
        """The command-line options that name this programmer (the defaults left out), for a command to retype."""
        given = [] if self.name == "usbasp" else [f"--programmer {self.name}"]
        given += [f"--port {self.port}"] * bool(self.port) + [f"--baud {self.baud}"] * bool(self.baud)
        return " ".join(given)


def avrdude_path() -> str:
    path = shutil.which("avrdude")
    if path is None:
        raise ProgrammerError(_("avrdude not found: install it ({install})").format(install=AVRDUDE_INSTALL))
    return path


def run_avrdude(programmer: Programmer, operations: list[str], erase: bool = False) -> str:
    """One avrdude run (its own verify after every write included); its output, or ProgrammerError with the
    line where avrdude says what went wrong."""
    argv = [avrdude_path(), "-c", programmer.name, "-p", PART]
    if programmer.port:
        argv += ["-P", programmer.port]
    if programmer.baud:
        argv += ["-b", str(programmer.baud)]
    argv += ["-e"] * erase
    for operation in operations:
        argv += ["-U", operation]
    try:
        returncode, stdout, stderr = _watched(argv)
    except OSError as exc:
        raise ProgrammerError(_("avrdude could not be run: {error}").format(error=exc)) from exc
    if returncode == "silent":
        raise AvrdudeStopped(_("avrdude stopped answering: nothing from it for {seconds:g} s, so it was stopped (is "
                               "the programmer still plugged in?)").format(seconds=SILENCE_S))
    if returncode == "too long":
        raise AvrdudeStopped(_("avrdude was still running after {seconds:g} s (its last words: {last}), so it was "
                               "stopped (is the programmer plugged in and the chip powered?)").format(
                                   seconds=TOTAL_S, last=avrdude_reason(stderr)))
    if returncode != 0:
        raise ProgrammerError(_("avrdude failed: {reason}").format(reason=avrdude_reason(stderr)))
    return stdout + stderr


def _watched(argv: list[str]) -> tuple[int | str, str, str]:
    """Run avrdude, reading what it says as it says it; a run silent for SILENCE_S ("silent") or running for
    TOTAL_S ("too long") is killed. avrdude draws its progress bars byte by byte, so a working run is never
    that quiet; one whose programmer vanished can wait on the port for ever, or retry and say so for ever."""
    proc = subprocess.Popen(argv, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    started = time.monotonic()
    heard = [started]
    parts: dict[str, list[bytes]] = {"out": [], "err": []}

    def read(stream, into: list[bytes]) -> None:
        while chunk := stream.read1(4096):
            into.append(chunk)
            heard[0] = time.monotonic()

    readers = [threading.Thread(target=read, args=(stream, parts[key]), daemon=True)
               for stream, key in ((proc.stdout, "out"), (proc.stderr, "err"))]
    for reader in readers:
        reader.start()
    returncode: int | str
    while True:
        try:
            returncode = proc.wait(timeout=0.2)
            break
        except subprocess.TimeoutExpired:
            now = time.monotonic()
            stuck = "silent" if now - heard[0] > SILENCE_S else "too long" if now - started > TOTAL_S else None
            if stuck:
                proc.kill()
                proc.wait()
                returncode = stuck
                break
    for reader in readers:
        reader.join()
    text = lambda key: b"".join(parts[key]).decode(errors="replace")  # noqa: E731
    return returncode, text("out"), text("err")


def avrdude_reason(stderr: str) -> str:
    lines = [line.strip() for line in stderr.splitlines() if line.strip().startswith("avrdude")]
    wanted = [line for line in lines if any(word in line.lower() for word in ("error", "mismatch", "expected",
                                                                               "not in sync", "cannot", "failed"))]
    reason = (wanted or lines or [stderr.strip() or "?"])[0].removeprefix("avrdude: ")
    return "".join(c if c.isprintable() else "?" for c in reason)[:200]


def read_file_written(path: Path, what: str) -> bytes:
    """A file avrdude was asked to write; one line when it did not (an avrdude that exits 0 having done nothing)."""
    try:
        return path.read_bytes()
    except OSError:
        raise ProgrammerError(_("avrdude said it read the {what} but wrote no {file} (is it really avrdude, and the "
                                "programmer connected?)").format(
                                    what=what, file=path.name)) from None
