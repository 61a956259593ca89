"""Installing the ZUML firmware on an iMAX B6 (ATmega32) with avrdude, and putting the original back.

``install`` first reads the charger's flash, EEPROM, fuses and lock byte into a backup folder and has
avrdude verify the saved files against the chip; only then does it check the fuses and write. Brown-out
detection must be on at 4.0 V (docs/firmware.md): in the ATmega32's low fuse, BODLEVEL (bit 7) and BODEN
(bit 6) both programmed, i.e. 0 (ATmega32 datasheet, *Fuse Bits*, table "Fuse Low Byte"). A charger
without it is refused before anything is written unless the caller lets it program those two bits
(the clock bits stay as they are). avrdude verifies every memory it writes; a mismatch is an error.
``restore`` writes a backup's flash and EEPROM back, then its fuses if they differ."""
from __future__ import annotations

import hashlib
import json
import shutil
import subprocess
import tempfile
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

from ..i18n import _
from ..user_dirs import config_dir

PART = "m32"
SIGNATURE = "1e9502"                    # ATmega32
FLASH_SIZE, EEPROM_SIZE = 32 * 1024, 1024
BOD_BITS = 0xC0                         # low fuse: BODLEVEL | BODEN, programmed = 0 -> BOD on at 4.0 V
READ_PROTECTED = 0x03                   # lock byte: LB2 | LB1; either programmed: flash and EEPROM unreadable
AVRDUDE_INSTALL = "apt-get install avrdude"
MANIFEST = "backup.json"
# avrdude quiet this long is stuck (its programmer gone), not slow: see _watched
SILENCE_S = 60.0
FIRMWARE = Path(__file__).resolve().parents[2] / "firmware"
IMAGE = FIRMWARE / "build" / "imaxb6" / "zuml.elf"
FORMATS = {".hex": "i", ".ihex": "i", ".elf": "e", ".bin": "r"}

Say = Callable[[str], None]


class InstallError(Exception):
    """A precise one-line reason the install or restore stopped (and what was already done)."""


@dataclass(frozen=True)
class Programmer:
    """How avrdude reaches the chip: its programmer id (``-c``: usbasp, stk500v1, ...), port and baud."""
    name: str = "usbasp"
    port: str | None = None
    baud: int | None = None


@dataclass(frozen=True)
class Fuses:
    low: int
    high: int
    lock: int

    @property
    def brown_out_ok(self) -> bool:
        return self.low & BOD_BITS == 0

    @property
    def read_protected(self) -> bool:
        return self.lock & READ_PROTECTED != READ_PROTECTED


def warnings() -> list[str]:
    """What a user must know before the charger's firmware is replaced (the CLI and the Device menu show it)."""
    return [
        _("This replaces the charger's own firmware. ZUML's iMAX B6 image has been proven on a simulated board "
          "only: watch the first charges and keep a fire-safe place."),
        _("Only for the original iMAX B6 (ATmega32, 16 MHz crystal); clones with another chip or board differ."),
        _("Disconnect the battery and keep the charger powered from its DC input while the ISP programmer is "
          "on its 10-pin header; do not unplug anything until it is done."),
        _("The original flash and EEPROM are saved first and checked; `zuml firmware restore BACKUP` puts them "
          "back. A read-protected charger cannot be saved and is refused."),
        _("After installing, calibrate the charger (`zuml calibrate --port PORT`): until then it refuses to "
          "charge."),
    ]


def bod_fixed(low: int) -> int:
    """The low fuse with BODEN and BODLEVEL programmed and every other bit (the clock's) kept."""
    return low & ~BOD_BITS & 0xFF


def avrdude_path() -> str:
    path = shutil.which("avrdude")
    if path is None:
        raise InstallError(_("avrdude not found: install it ({install})").format(install=AVRDUDE_INSTALL))
    return path


def run_avrdude(programmer: Programmer, operations: list[str], erase: bool = False) -> str:
    """One avrdude run (its own verify after every write included); its output, or InstallError with the
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
        raise InstallError(_("avrdude could not be run: {error}").format(error=exc)) from exc
    if returncode is None:
        raise InstallError(_("avrdude stopped answering: nothing from it for {seconds:g} s, so it was stopped (is "
                             "the programmer still plugged in?); if it was writing, the chip is half-written: "
                             "install again, or put the backup back with `zuml firmware restore`").format(
                seconds=SILENCE_S))
    if returncode != 0:
        raise InstallError(_("avrdude failed: {reason}").format(reason=avrdude_reason(stderr)))
    return stdout + stderr


def _watched(argv: list[str]) -> tuple[int | None, str, str]:
    """Run avrdude, reading what it says as it says it; a run silent for SILENCE_S is killed (return code None).
    avrdude draws its progress bars byte by byte, so a working run is never that quiet; one whose programmer
    vanished (a USB serial port gone) can wait on the port for ever."""
    proc = subprocess.Popen(argv, stdin=subprocess.DEVNULL, stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    heard = [time.monotonic()]
    parts: dict[str, list[bytes]] = {"out": [], "err": []}

    def read(stream, into: list[bytes]) -> None:
        while chunk := stream.read1(4096):
            into.append(chunk)
            heard[0] = time.monotonic()

    readers = [threading.Thread(target=read, args=(stream, parts[key]), daemon=True)
               for stream, key in ((proc.stdout, "out"), (proc.stderr, "err"))]
    for reader in readers:
        reader.start()
    while True:
        try:
            returncode: int | None = proc.wait(timeout=0.2)
            break
        except subprocess.TimeoutExpired:
            if time.monotonic() - heard[0] > SILENCE_S:
                proc.kill()
                proc.wait()
                returncode = None
                break
    for reader in readers:
        reader.join()
    text = lambda key: b"".join(parts[key]).decode(errors="replace")  # noqa: E731
    return returncode, text("out"), text("err")


def avrdude_reason(stderr: str) -> str:
    lines = [line.strip() for line in stderr.splitlines() if line.strip().startswith("avrdude")]
    wanted = [line for line in lines if any(word in line.lower() for word in ("error", "mismatch", "expected",
                                                                               "not in sync", "cannot", "failed"))]
    return (wanted or lines or [stderr.strip() or "?"])[0].removeprefix("avrdude: ")


def read_fuses(programmer: Programmer, folder: Path) -> Fuses:
    memories = ("lfuse", "hfuse", "lock")
    run_avrdude(programmer, [f"{memory}:r:{folder / memory}.hex:h" for memory in memories])
    low, high, lock = (int((folder / f"{memory}.hex").read_text().split()[0], 16) for memory in memories)
    return Fuses(low, high, lock)


def sha256(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def backup(programmer: Programmer, folder: Path, say: Say) -> Fuses:
    """Read the chip into ``folder`` (flash.hex, eeprom.hex, backup.json) and verify the files against it."""
    folder.mkdir(parents=True, exist_ok=True)
    say(_("Reading the fuses and lock bits…"))
    with tempfile.TemporaryDirectory() as scratch:
        fuses = read_fuses(programmer, Path(scratch))
    if fuses.read_protected:
        raise InstallError(_("the charger's memory is read-protected (lock byte 0x{lock:02X}): its original "
                             "firmware cannot be saved, so it could not be restored; nothing was written").format(
                                 lock=fuses.lock))
    say(_("Saving the original flash and EEPROM to {folder}…").format(folder=folder))
    flash, eeprom = folder / "flash.hex", folder / "eeprom.hex"
    run_avrdude(programmer, [f"flash:r:{flash}:i", f"eeprom:r:{eeprom}:i"])
    say(_("Checking the saved copy against the charger…"))
    run_avrdude(programmer, [f"flash:v:{flash}:i", f"eeprom:v:{eeprom}:i"])
    manifest = {"part": PART, "signature": SIGNATURE, "lfuse": fuses.low, "hfuse": fuses.high, "lock": fuses.lock,
                "saved": time.strftime("%Y-%m-%dT%H:%M:%S%z"),
                "files": {name: sha256(folder / name) for name in ("flash.hex", "eeprom.hex")}}
    (folder / MANIFEST).write_text(json.dumps(manifest, indent=2) + "\n", encoding="utf-8")
    return fuses


def default_backup_folder() -> Path:
    return config_dir() / "firmware-backups" / time.strftime("imaxb6-%Y%m%d-%H%M%S")


def build_image() -> Path:
    """The imaxb6 image, made first (a no-op when up to date)."""
    try:
        done = subprocess.run(["make", "-s", "-C", str(FIRMWARE), "imaxb6"], capture_output=True, text=True)
    except OSError as exc:
        raise InstallError(_("the imaxb6 image cannot be built ({error}): give the image file").format(
            error=exc)) from None
    if done.returncode != 0 or not IMAGE.is_file():
        raise InstallError(_("the imaxb6 image did not build (make -C {firmware} imaxb6): give the image file").format(
            firmware=FIRMWARE))
    return IMAGE


def image_operation(image: Path) -> str:
    kind = FORMATS.get(image.suffix.lower())
    if kind is None:
        raise InstallError(_("{image}: the firmware image must be .hex, .elf or .bin").format(image=image))
    if not image.is_file():
        raise InstallError(_("{image}: no such firmware image").format(image=image))
    return f"flash:w:{image}:{kind}"


def install(programmer: Programmer, image: Path, backup_folder: Path, fix_fuses: bool, say: Say) -> Fuses:
    """Back up, check the fuses, write and verify the image and an erased EEPROM; the fuses it leaves."""
    write_flash = image_operation(image)
    avrdude_path()
    fuses = backup(programmer, backup_folder, say)
    say(_("Backup saved and verified: {folder}").format(folder=backup_folder))
    if not fuses.brown_out_ok and not fix_fuses:
        raise InstallError(_("brown-out detection is off (low fuse 0x{low:02X}): the firmware needs it at 4.0 V; "
                             "nothing was written (allow setting it: low fuse 0x{fixed:02X})").format(
                                 low=fuses.low, fixed=bod_fixed(fuses.low)))
    say(_("Writing and verifying the ZUML firmware…"))
    with tempfile.TemporaryDirectory() as scratch:
        blank = Path(scratch) / "eeprom.bin"
        blank.write_bytes(b"\xff" * EEPROM_SIZE)    # an erased EEPROM: empty store, not calibrated
        run_avrdude(programmer, [write_flash, f"eeprom:w:{blank}:r"], erase=True)
        if not fuses.brown_out_ok:
            say(_("Setting brown-out detection at 4.0 V (low fuse 0x{low:02X} → 0x{fixed:02X})…").format(
                low=fuses.low, fixed=bod_fixed(fuses.low)))
            run_avrdude(programmer, [f"lfuse:w:0x{bod_fixed(fuses.low):02x}:m"])
        after = read_fuses(programmer, Path(scratch))
    if not after.brown_out_ok:
        raise InstallError(_("the low fuse reads 0x{low:02X} after writing: brown-out detection is still off").format(
            low=after.low))
    say(_("Installed and verified; brown-out detection on at 4.0 V (low fuse 0x{low:02X})").format(low=after.low))
    return after


def load_manifest(folder: Path) -> dict:
    """A backup's manifest, checked: the part, its files present and unchanged since they were saved."""
    try:
        manifest = json.loads((folder / MANIFEST).read_text(encoding="utf-8"))
        files, low, high = manifest["files"], int(manifest["lfuse"]), int(manifest["hfuse"])
    except (OSError, ValueError, KeyError, TypeError) as exc:
        raise InstallError(_("{folder}: not a firmware backup ({error})").format(folder=folder, error=exc)) from exc
    if manifest.get("part") != PART or not (0 <= low <= 0xFF and 0 <= high <= 0xFF):
        raise InstallError(_("{folder}: not an ATmega32 backup").format(folder=folder))
    for name in ("flash.hex", "eeprom.hex"):
        if not (folder / name).is_file() or sha256(folder / name) != files.get(name):
            raise InstallError(_("{file}: missing or changed since the backup was saved").format(file=folder / name))
    return manifest


def restore(programmer: Programmer, folder: Path, say: Say) -> Fuses:
    """Write a backup's flash and EEPROM back (verified), then its fuses where they differ."""
    manifest = load_manifest(folder)
    avrdude_path()
    say(_("Writing the saved flash and EEPROM back…"))
    run_avrdude(programmer, [f"flash:w:{folder / 'flash.hex'}:i", f"eeprom:w:{folder / 'eeprom.hex'}:i"],
                erase=True)
    with tempfile.TemporaryDirectory() as scratch:
        now = read_fuses(programmer, Path(scratch))
        for memory, saved, present in (("lfuse", manifest["lfuse"], now.low), ("hfuse", manifest["hfuse"], now.high)):
            if saved != present:
                say(_("Restoring the {fuse} fuse: 0x{present:02X} → 0x{saved:02X}…").format(
                    fuse=memory, present=present, saved=saved))
                run_avrdude(programmer, [f"{memory}:w:0x{saved:02x}:m"])
        after = read_fuses(programmer, Path(scratch))
    say(_("The original firmware is back (verified)"))
    return after
