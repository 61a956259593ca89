"""The simulated iMAX B6 (the ZUML firmware's image on simavr, `zuml firmware-sim --board imaxb6`) as a
device the window starts and stops: its pty, its LCD as the firmware writes it, its four buttons.

The EEPROM (macros, templates and the calibration the simulator finds for its board) is kept in a file,
so the charger holds them the next time, as a real one does. The receive wire is connected: the window
talks to it with the request protocol. No Qt here: the device panel turns ``on_lcd`` into a signal.
"""
from __future__ import annotations

import subprocess
import threading
from pathlib import Path
from typing import Callable

from ..i18n import _
from ..device.errors import DeviceLinkError
from . import firmware_sim

BAUD = 57600               # the B6's line (docs/firmware.md, Line); a pty ignores it
BUTTONS = ("start", "stop", "inc", "dec")
MIN_PRESS_S = 0.1          # a click is at least a finger's press: the firmware debounces 30 ms
BOOT_S = 60.0              # a bound on the firmware's start-up (its display's first line), on a loaded PC


class SimulatedB6:
    """Started at once; ``port`` is its pty. ``on_lcd(line1, line2)`` runs on a reader thread at every
    change of the display. ``press``/``release`` work the front panel's buttons live."""

    def __init__(self, eeprom: Path, *, speed: float = 1.0,
                 on_lcd: Callable[[str, str], None] | None = None) -> None:
        try:
            argv = firmware_sim.build_device("imaxb6")
        except firmware_sim.FirmwareBuildError as exc:
            raise DeviceLinkError(str(exc)) from None
        eeprom.parent.mkdir(parents=True, exist_ok=True)
        self._on_lcd = on_lcd or (lambda line1, line2: None)
        self.lcd = ("", "")
        self._last_words: list[str] = []
        self._stdin_lock = threading.Lock()
        self._booted = threading.Event()
        self._ended = False
        # --end-with-stdin: a window that goes away without stopping it (a crash) closes its stdin: it ends too
        self.proc = subprocess.Popen(argv + ["--eeprom", str(eeprom), "--lcd", "--speed", f"{speed:g}",
                                             "--end-with-stdin"],
                                     stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                                     text=True)
        self.port = self.proc.stdout.readline().strip()
        self._reader = threading.Thread(target=self._read, name="simulated B6", daemon=True)
        self._reader.start()
        # the firmware listens once it is up: its display's first line says so (a request sent before
        # would wait in the USART's ring while the display starts, and a client may give up on it)
        if not self.port or not self._booted.wait(BOOT_S) or self._ended:
            self.close()
            raise DeviceLinkError(_("the simulated iMAX B6 did not start: {why}").format(
                why=" ".join(self._last_words[-3:]) or _("exit status {code}").format(code=self.proc.returncode)))

    def _read(self) -> None:
        for line in self.proc.stderr:       # ends when it does: then nobody waits for its start any more
            line = line.rstrip("\n")
            if line.startswith("LCD|"):
                parts = line.split("|")
                self.lcd = (parts[1], parts[2] if len(parts) > 2 else "")
                self._booted.set()
                self._on_lcd(*self.lcd)
            elif line.startswith("zuml_b6_sim"):
                self._last_words.append(line)
        self._ended = True
        self._booted.set()

    def _send(self, line: str) -> None:
        with self._stdin_lock:
            if self.proc.poll() is not None:
                return
            try:
                self.proc.stdin.write(line + "\n")
                self.proc.stdin.flush()
            except (BrokenPipeError, ValueError):       # it ended meanwhile: nothing to press
                pass

    def press(self, button: str) -> None:
        """``button`` goes down now and stays down until ``release``."""
        if button not in BUTTONS:
            raise ValueError(_("no such button {button!r} ({buttons})").format(button=button,
                                                                                buttons=", ".join(BUTTONS)))
        self._send(f"{button} down")

    def release(self, button: str, held_s: float) -> None:
        """``button`` lets go, once it has been down ``held_s`` seconds of the B6's own time (the time the
        user held it, also when the simulation runs slower than the wall; a click at least MIN_PRESS_S)."""
        if button not in BUTTONS:
            raise ValueError(_("no such button {button!r} ({buttons})").format(button=button,
                                                                                buttons=", ".join(BUTTONS)))
        self._send(f"{button} up {max(MIN_PRESS_S, held_s):.3f}")

    def close(self) -> None:
        """Stop it (its EEPROM is saved on the way out). Idempotent."""
        if self.proc.poll() is None:
            self.proc.terminate()
            try:
                self.proc.wait(30)
            except subprocess.TimeoutExpired:
                self.proc.kill()
                self.proc.wait()
        for stream in (self.proc.stdin, self.proc.stdout):
            try:
                stream.close()
            except (OSError, ValueError):
                pass
        self._reader.join(5)
