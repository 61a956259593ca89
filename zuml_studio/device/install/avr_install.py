"""Installing the ZUML firmware on an iMAX B6 (ATmega32) with avrdude, and putting the original back.

``install`` first reads the charger's fuses, lock byte, flash and EEPROM into a backup folder (a new or
empty one: a backup is never written over) and has avrdude verify the saved files against the chip; only
then does it check the fuses and write. What it read decides what the backup is: the charger's
**original** (the first original of a chip, by its signature and its flash's hash, is also kept in the
settings folder's ``firmware-backups/originals``, never replaced), ZUML's own image (an update), an empty
chip, or **unreadable** (lock bits set, or a flash that reads as one short pattern repeated: a locked
chip's answer). An unreadable original is said before anything is written, and installed over only when
the caller says the user accepted that there is no way back.

Fuses (ATmega32 datasheet, *Memory Programming*, tables "Fuse High Byte" and "Fuse Low Byte"; a bit is
programmed at 0), the ones the B6 needs, which ``--fix-fuses`` sets, the others kept:
- low BODLEVEL (7) and BODEN (6) programmed: brown-out detection at 4.0 V (docs/firmware.md);
- low CKSEL3..1 (3..1) = 101/110/111 with high CKOPT (4) programmed: the external crystal, full swing,
  as a 16 MHz crystal needs (table "Crystal Oscillator Operating Modes"); a wrong clock is set to
  CKSEL 1111, SUT 11 (crystal, slowly rising power), i.e. low 0x3F with the BOD bits;
- high JTAGEN (6) and OCDEN (7) unprogrammed: JTAG off, or PC2..PC5, the LCD's lines, stay JTAG pins
  (cheali-charger's README: "squares on the display" -> hfuse 0xC5, lfuse 0x3F).

``restore`` writes a backup's flash and EEPROM back, then its fuses where they differ, and says
"verified" only once the fuses read back are the saved ones; it names a backup of ZUML's own image as
such, never as the original."""
from __future__ import annotations

import hashlib
import json
import re
import shutil
import tempfile
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path

from ...i18n import _
from ...user_dirs import config_dir
from .avrdude import AvrdudeStopped, Programmer, ProgrammerError, avrdude_path, read_file_written, run_avrdude

PART = "m32"
SIGNATURE = "1e9502"                    # ATmega32
FLASH_SIZE, EEPROM_SIZE = 32 * 1024, 1024
BOD_BITS = 0xC0                         # low fuse: BODLEVEL | BODEN, programmed = 0 -> BOD on at 4.0 V
CKSEL_CRYSTAL = (0x0A, 0x0C, 0x0E)      # low fuse CKSEL3..1 (mask 0x0E): an external crystal
CKOPT, JTAGEN, OCDEN = 0x10, 0x40, 0x80  # high fuse bits
B6_CLOCK = 0x3F                         # low fuse bits 5..0 the fix writes: SUT 11, CKSEL 1111
READ_PROTECTED = 0x03                   # lock byte: LB2 | LB1; either programmed: flash and EEPROM unreadable
LONGEST_PATTERN = 256                   # a flash that repeats a pattern this short (or shorter) was not read
MANIFEST = "backup.json"
# The imaxb6 image's firmware name, in its flash (boards/imaxb6/board.c): how ZUML's own image is told apart
ZUML_IMAGE = re.compile(rb"zuml-fw [ -~]{1,16} imaxb6(?: [ -~]{1,64})?\x00")   # a note may follow (the RX wire)
FIRMWARE = Path(__file__).resolve().parents[3] / "firmware"
IMAGE = FIRMWARE / "build" / "imaxb6" / "zuml.elf"
FORMATS = {".hex": "i", ".ihex": "i", ".elf": "e", ".bin": "r"}

Say = Callable[[str], None]


class OriginalUnreadable(ProgrammerError):
    """The charger's original firmware cannot be read (so not saved): nothing was written; installing means
    there is no way back. The window asks the user; the command line wants an explicit flag."""


@dataclass(frozen=True)
class Fuses:
    low: int
    high: int
    lock: int

    @property
    def brown_out_ok(self) -> bool:
        return self.low & BOD_BITS == 0

    @property
    def clock_ok(self) -> bool:
        return self.low & 0x0E in CKSEL_CRYSTAL and not self.high & CKOPT

    @property
    def jtag_off(self) -> bool:
        return self.high & (JTAGEN | OCDEN) == JTAGEN | OCDEN

    @property
    def read_protected(self) -> bool:
        return self.lock & READ_PROTECTED != READ_PROTECTED

    def problems(self) -> list[str]:
        """Why these fuses cannot run the B6 image, one line each ([] when they can)."""
        found = []
        if not self.brown_out_ok:
            found.append(_("brown-out detection is off (low fuse 0x{low:02X}): the firmware needs it at 4.0 V").format(
                low=self.low) if self.low & 0x40 else
                _("brown-out detection is at 2.7 V (low fuse 0x{low:02X}): the firmware needs it at 4.0 V").format(
                low=self.low))
        if not self.clock_ok:
            found.append(_("the clock fuses do not select the B6's 16 MHz crystal (low fuse 0x{low:02X}, high fuse "
                           "0x{high:02X}: CKSEL3..1 must be 101..111 and CKOPT programmed)").format(
                               low=self.low, high=self.high))
        if not self.jtag_off:
            found.append(_("JTAG is enabled (high fuse 0x{high:02X}): the LCD is on the JTAG pins PC2..PC5 and would "
                           "show squares").format(high=self.high))
        return found

    def fixed(self) -> Fuses:
        """What ``--fix-fuses`` writes: BOD at 4.0 V, the crystal, JTAG off; every other bit as it is."""
        low = self.low & ~BOD_BITS & 0xFF
        if not self.clock_ok:
            low = B6_CLOCK
        return Fuses(low, (self.high | JTAGEN | OCDEN) & ~CKOPT & 0xFF, self.lock)


def warnings() -> list[str]:
    """What a user must know before the charger's firmware is replaced (the CLI and the Device menu show it)."""
    return [
        _("This replaces the charger's own firmware. ZUML's iMAX B6 image has been proven on a simulated board "
          "only: watch the first charges and keep a fire-safe place."),
        _("Only for the original iMAX B6 (ATmega32, 16 MHz crystal); clones with another chip or board differ."),
        _("Disconnect the battery and keep the charger powered from its DC input while the ISP programmer is "
          "on its 10-pin header: the programmer holds the charger's processor in reset, and then nothing "
          "watches a pack. Do not unplug anything until it is done."),
        _("The original flash, EEPROM and fuses are saved first, into a new folder, and checked; `zuml firmware "
          "restore BACKUP` puts them back. A locked charger's original cannot be read: you are told so before "
          "anything is written."),
        _("After installing, calibrate the charger (`zuml calibrate --port PORT`): until then it refuses to "
          "charge."),
    ]


def ihex_bytes(text: str, size: int) -> bytes:
    """An Intel HEX file's data records laid on an erased memory of ``size`` bytes."""
    data = bytearray(b"\xff" * size)
    base = 0
    for line in text.split():
        try:
            record = bytes.fromhex(line.removeprefix(":"))
            count, address, kind = record[0], record[1] << 8 | record[2], record[3]
        except (ValueError, IndexError):
            raise ProgrammerError(_("not an Intel HEX line: {line!r}").format(line=line[:40])) from None
        if kind == 0 and base + address + count <= size:
            data[base + address:base + address + count] = record[4:4 + count]
        elif kind in (2, 4) and count == 2:
            base = (record[4] << 8 | record[5]) << (4 if kind == 2 else 16)
    return bytes(data)


def what_flash_holds(flash: bytes) -> str:
    """"empty" (erased), "unreadable" (one short pattern over the whole flash: a locked chip's answer),
    "zuml" (ZUML's imaxb6 image) or "original" (anything else: the charger's own firmware)."""
    if flash == b"\xff" * len(flash):
        return "empty"
    for period in range(1, LONGEST_PATTERN + 1):
        if flash == flash[:period] * (len(flash) // period) + flash[:len(flash) % period]:
            return "unreadable"
    return "zuml" if ZUML_IMAGE.search(flash) else "original"


def read_fuses(programmer: Programmer, folder: Path) -> Fuses:
    memories = ("lfuse", "hfuse", "lock")
    run_avrdude(programmer, [f"{memory}:r:{folder / memory}.hex:h" for memory in memories])
    values = []
    for memory in memories:
        text = read_file_written(folder / f"{memory}.hex", memory).decode(errors="replace").split()
        try:
            values.append(int(text[0], 16))
            assert 0 <= values[-1] <= 0xFF
        except (IndexError, ValueError, AssertionError):
            raise ProgrammerError(_("avrdude's {memory} file holds no fuse value ({text!r}): the fuses are not "
                                    "known").format(memory=memory, text=" ".join(text)[:20])) from None
    return Fuses(*values)


def sha256(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


@dataclass(frozen=True)
class Saved:
    """What ``backup`` found: the fuses, what the flash holds (``what_flash_holds``, or "unreadable" for a
    read-protected chip, then with ``why``), the flash's hash."""
    fuses: Fuses
    kind: str
    flash_sha256: str = ""
    why: str = ""


def new_backup_folder(folder: Path) -> None:
    """``folder`` made, or refused when it already holds anything: a backup is never written over."""
    if folder.exists() and (not folder.is_dir() or any(folder.iterdir())):
        raise ProgrammerError(_("{folder} is not a new or empty folder: a backup is never written over (an earlier "
                                "backup there may be the charger's only original); give a new folder, or leave "
                                "--backup-dir out for a new one; nothing was written").format(folder=folder))
    try:
        folder.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        raise ProgrammerError(_("{folder}: cannot make the backup folder: {error}; nothing was written").format(
            folder=folder, error=exc.strerror or exc)) from None


def backup(programmer: Programmer, folder: Path, say: Say) -> Saved:
    """Read the chip into ``folder`` (fuses, flash.hex, eeprom.hex, backup.json), verify the files against it
    and say what the flash holds. A read-protected chip's memories are not read (they would be garbage)."""
    say(_("Reading the fuses and lock bits…"))
    fuses = read_fuses(programmer, folder)
    manifest = {"part": PART, "signature": SIGNATURE, "lfuse": fuses.low, "hfuse": fuses.high, "lock": fuses.lock,
                "saved": time.strftime("%Y-%m-%dT%H:%M:%S%z")}
    if fuses.read_protected:
        saved = Saved(fuses, "unreadable", why=_("its lock bits are set (lock byte 0x{lock:02X})").format(
            lock=fuses.lock))
    else:
        say(_("Saving the flash and EEPROM to {folder}…").format(folder=folder))
        flash, eeprom = folder / "flash.hex", folder / "eeprom.hex"
        run_avrdude(programmer, [f"flash:r:{flash}:i", f"eeprom:r:{eeprom}:i"])
        say(_("Checking the saved copy against the charger…"))
        run_avrdude(programmer, [f"flash:v:{flash}:i", f"eeprom:v:{eeprom}:i"])
        content = ihex_bytes(read_file_written(flash, "flash").decode(errors="replace"), FLASH_SIZE)
        read_file_written(eeprom, "EEPROM")
        kind = what_flash_holds(content)
        saved = Saved(fuses, kind, hashlib.sha256(content).hexdigest(),
                      _("its flash reads as one short pattern repeated (lock bits it does not report?)")
                      if kind == "unreadable" else "")
        manifest["files"] = {name: sha256(folder / name) for name in ("flash.hex", "eeprom.hex")}
        manifest["flash_sha256"] = saved.flash_sha256
    manifest["holds"] = saved.kind
    (folder / MANIFEST).write_text(json.dumps(manifest, indent=2) + "\n", encoding="utf-8")
    return saved


def backups_root() -> Path:
    return config_dir() / "firmware-backups"


def original_folder(flash_sha256: str) -> Path:
    """Where the first backup of a chip's original is kept: named by the part's signature and the flash's hash."""
    return backups_root() / "originals" / f"original-{PART}-{SIGNATURE}-{flash_sha256[:16]}"


def keep_original(folder: Path, saved: Saved, say: Say) -> None:
    """The first backup of this chip's original also in the originals folder; a later one never replaces it."""
    kept = original_folder(saved.flash_sha256)
    if kept.exists():
        say(_("This charger's original firmware is already kept in {kept}").format(kept=kept))
        return
    try:
        shutil.copytree(folder, kept)
    except OSError as exc:
        say(_("The original could not be kept a second time in {kept} ({error}): keep {folder} safe").format(
            kept=kept, error=exc.strerror or exc, folder=folder))
        return
    say(_("The first backup of this charger's original firmware: kept also as {kept}").format(kept=kept))


def default_backup_folder() -> Path:
    """A new folder in the settings folder, never one that exists."""
    return fresh_folder(backups_root() / time.strftime("imaxb6-%Y%m%d-%H%M%S"))


def fresh_folder(base: Path) -> Path:
    """``base``, or ``base-2``, ``base-3``…: the first that does not exist."""
    folder, n = base, 1
    while folder.exists():
        n += 1
        folder = base.with_name(f"{base.name}-{n}")
    return folder


def build_image() -> Path:
    """The imaxb6 image, made first (a no-op when up to date)."""
    import subprocess
    try:
        done = subprocess.run(["make", "-s", "-C", str(FIRMWARE), "imaxb6"], capture_output=True, text=True)
    except OSError as exc:
        raise ProgrammerError(_("the imaxb6 image cannot be built ({error}): give the image file").format(
            error=exc)) from None
    if done.returncode != 0 or not IMAGE.is_file():
        raise ProgrammerError(_("the imaxb6 image did not build (make -C {firmware} imaxb6): give the image "
                                "file").format(firmware=FIRMWARE))
    return IMAGE


def image_operation(image: Path) -> str:
    kind = FORMATS.get(image.suffix.lower())
    if kind is None:
        raise ProgrammerError(_("{image}: the firmware image must be .hex, .elf or .bin").format(image=image))
    if not image.is_file():
        raise ProgrammerError(_("{image}: no such firmware image").format(image=image))
    return f"flash:w:{image}:{kind}"


def restore_command(programmer: Programmer, folder: Path) -> str:
    return " ".join(["zuml firmware restore", str(folder), programmer.options()]).strip()


@contextmanager
def then(next_step: str) -> Iterator[None]:
    """A ProgrammerError inside, with what it leaves and what to do next added to its line."""
    try:
        yield
    except OriginalUnreadable:
        raise
    except ProgrammerError as exc:
        raise type(exc)(f"{exc}; {next_step}") from None


def install(programmer: Programmer, image: Path, backup_folder: Path, fix_fuses: bool, say: Say,
            no_way_back: bool = False) -> Fuses:
    """Back up, check the fuses, write and verify the image and an erased EEPROM; the fuses it leaves.
    ``no_way_back``: the user accepted that an original which cannot be read is lost."""
    write_flash = image_operation(image)
    avrdude_path()
    new_backup_folder(backup_folder)
    with then(_("nothing was written to the charger: check the programmer's cable and the charger's power, "
                "then try again")):
        saved = backup(programmer, backup_folder, say)
    fuses = saved.fuses
    if saved.kind == "unreadable" and not no_way_back:
        raise OriginalUnreadable(_("the charger's original firmware cannot be read: {why}; a backup of it would be "
                                   "worthless, so after installing there is no way back to it. Nothing was written. "
                                   "To install anyway, accept that (command line: --no-way-back)").format(
                                       why=saved.why))
    say({"original": _("Backup of the original firmware saved and verified: {folder}"),
         "zuml": _("Backup saved and verified: {folder} (it holds ZUML's own image, not the charger's original)"),
         "empty": _("The chip's flash was empty: there is no original to save ({folder} holds its EEPROM and "
                    "fuses)"),
         "unreadable": _("No way back, as accepted: the original could not be read ({folder} holds the fuses "
                         "only)")}[saved.kind].format(folder=backup_folder))
    if saved.kind == "original":
        keep_original(backup_folder, saved, say)
    problems, target = fuses.problems(), fuses.fixed()
    if problems and not fix_fuses:
        raise ProgrammerError(_("{problems}; nothing was written (--fix-fuses sets them: low fuse 0x{low:02X}, high "
                                "fuse 0x{high:02X})").format(problems="; ".join(problems), low=target.low,
                                                             high=target.high))
    back = (_("put the backup back: {command}").format(command=restore_command(programmer, backup_folder))
            if saved.kind != "unreadable" else _("install again (the original could not be read)"))
    say(_("Writing and verifying the ZUML firmware…"))
    with tempfile.TemporaryDirectory() as scratch:
        blank = Path(scratch) / "eeprom.bin"
        blank.write_bytes(b"\xff" * EEPROM_SIZE)    # an erased EEPROM: empty store, not calibrated
        with then(_("the chip was erased and is half-written: {back}").format(back=back)):
            run_avrdude(programmer, [write_flash, f"eeprom:w:{blank}:r"], erase=True)
        with then(_("the ZUML firmware is written and verified but the fuses are not as it needs: install again "
                    "with --fix-fuses, or {back}").format(back=back)):
            for memory, now, wanted in (("lfuse", fuses.low, target.low), ("hfuse", fuses.high, target.high)):
                if now != wanted:
                    say(_("Setting the {fuse} fuse: 0x{now:02X} → 0x{wanted:02X}…").format(
                        fuse=memory, now=now, wanted=wanted))
                    run_avrdude(programmer, [f"{memory}:w:0x{wanted:02x}:m"])
            after = read_fuses(programmer, Path(scratch))
    if after.problems():
        raise ProgrammerError(_("the fuses read back after writing: {problems}; {back}").format(
            problems="; ".join(after.problems()), back=back))
    say(_("Installed and verified; fuses low 0x{low:02X}, high 0x{high:02X}: brown-out at 4.0 V, the crystal, "
          "JTAG off").format(low=after.low, high=after.high))
    return after


def load_manifest(folder: Path) -> dict:
    """A backup's manifest, checked: the part, its files present and unchanged since they were saved."""
    try:
        manifest = json.loads((folder / MANIFEST).read_text(encoding="utf-8"))
        low, high = int(manifest["lfuse"]), int(manifest["hfuse"])
    except (OSError, ValueError, KeyError, TypeError) as exc:
        raise ProgrammerError(_("{folder}: not a firmware backup ({error})").format(folder=folder, error=exc)) from exc
    if manifest.get("part") != PART or not (0 <= low <= 0xFF and 0 <= high <= 0xFF):
        raise ProgrammerError(_("{folder}: not an ATmega32 backup").format(folder=folder))
    files = manifest.get("files")
    if manifest.get("holds") == "unreadable" or not isinstance(files, dict):
        raise ProgrammerError(_("{folder}: the charger's firmware could not be read when this backup was made "
                                "(locked): there is nothing to put back").format(folder=folder))
    for name in ("flash.hex", "eeprom.hex"):
        if not (folder / name).is_file() or sha256(folder / name) != files.get(name):
            raise ProgrammerError(_("{file}: missing or changed since the backup was saved").format(file=folder / name))
    return manifest


def originals_kept() -> list[Path]:
    root = backups_root() / "originals"
    return sorted(root.glob(f"original-{PART}-{SIGNATURE}-*")) if root.is_dir() else []


def restore(programmer: Programmer, folder: Path, say: Say) -> Fuses:
    """Write a backup's flash and EEPROM back (verified), then its fuses where they differ, and compare the
    fuses read back with the saved ones; what is back is named by what the saved flash holds."""
    manifest = load_manifest(folder)
    holds = what_flash_holds(ihex_bytes((folder / "flash.hex").read_text(errors="replace"), FLASH_SIZE))
    if holds == "unreadable":
        raise ProgrammerError(_("{folder}: its flash is one short pattern repeated, a locked chip's answer, not a "
                                "firmware: there is nothing to put back").format(folder=folder))
    avrdude_path()
    again = _("restore again: {command}").format(command=restore_command(programmer, folder))
    say(_("Writing the saved flash and EEPROM back…"))
    with then(_("the chip may be erased and half-written: {again}").format(again=again)):
        run_avrdude(programmer, [f"flash:w:{folder / 'flash.hex'}:i", f"eeprom:w:{folder / 'eeprom.hex'}:i"],
                    erase=True)
    with tempfile.TemporaryDirectory() as scratch, then(_("the flash and EEPROM are back and verified, the fuses "
                                                          "not: {again}").format(again=again)):
        now = read_fuses(programmer, Path(scratch))
        for memory, saved, present in (("lfuse", manifest["lfuse"], now.low), ("hfuse", manifest["hfuse"], now.high)):
            if saved != present:
                say(_("Restoring the {fuse} fuse: 0x{present:02X} → 0x{saved:02X}…").format(
                    fuse=memory, present=present, saved=saved))
                run_avrdude(programmer, [f"{memory}:w:0x{saved:02x}:m"])
        after = read_fuses(programmer, Path(scratch))
    if (after.low, after.high) != (manifest["lfuse"], manifest["hfuse"]):
        raise ProgrammerError(_("the flash and EEPROM are back, but the fuses read back (low 0x{low:02X}, high "
                                "0x{high:02X}) are not the saved ones (low 0x{s_low:02X}, high 0x{s_high:02X}): not "
                                "verified; {again}").format(low=after.low, high=after.high, s_low=manifest["lfuse"],
                                                            s_high=manifest["hfuse"], again=again))
    if holds == "original":
        say(_("The original firmware is back (verified: flash, EEPROM and fuses)"))
    elif holds == "zuml":
        kept = originals_kept()
        where = (_("; the charger's original is kept in {kept}").format(kept=", ".join(map(str, kept))) if kept else
                 _("; no original of this chip is kept here"))
        say(_("The firmware saved in {folder} is back (verified), but it is ZUML's own image, not the charger's "
              "original{where}").format(folder=folder, where=where))
    else:
        say(_("The chip is as it was when {folder} was saved: an empty flash (verified)").format(folder=folder))
    return after
