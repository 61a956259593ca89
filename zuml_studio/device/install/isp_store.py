"""The macro store of an iMAX B6 running the ZUML firmware, read and written through the ISP programmer
(avrdude, a USBasp by default) instead of the serial line: the path for a B6 whose 3-pin port carries only
TXD. ``zuml flash/slots/backup/restore --programmer`` and the window's "iMAX B6 (ZUML) through a USBasp" use it.

The EEPROM as the firmware lays it out (firmware/core/store.c on the B6's 970 store bytes; docs/firmware.md,
*Calibration*): the image 0..403 (records back to back, IDENTIFY's ``eeprom_size`` 404), the staging copy
404..807, 16 start templates of 9 bytes and a check byte 808..967, the templates' set-up flag 968, the commit
journal 969, the calibration block 970..1023. A write here puts the new image in both the image and the
staging copy (a journal left at "committing" then copies the same bytes) and leaves 808..1023 alone: the
templates and the calibration stay byte-identical, which the read-back after the write checks.

The programmer holds the processor in reset while avrdude runs: the firmware stops and, until it starts
again, nothing switches the power stage off or watches a pack. A charge in progress is lost (the firmware
starts idle after the reset), which is why the battery must be disconnected first."""
from __future__ import annotations

import tempfile
import time
from collections.abc import Callable, Iterable
from dataclasses import dataclass
from pathlib import Path

from ...i18n import _
from ...lang.eeprom import Slot, slots
from ...domain.start_templates import StartTemplate, TemplateError, factory_templates
from ...protocol import messages as m
from .avr_install import EEPROM_SIZE, ZUML_IMAGE
from .avrdude import Programmer, ProgrammerError, read_file_written, run_avrdude
from ..zuml.calibration import BLOCK_SIZE, Block, CalibrationError
from ..zuml.client import DeviceInfo, WriteResult, check_image
from ..errors import DeviceError, ImageTooLarge

CALIBRATION_AT = EEPROM_SIZE - BLOCK_SIZE           # 970: the store's bytes are the ones below it
TEMPLATES, TEMPLATE_SIZE = 16, 9                     # firmware/core/store.h, zuml.h
TEMPLATE_STORED = TEMPLATE_SIZE + 1                  # and its check byte (XOR)
IMAGE_SIZE = (CALIBRATION_AT - 2 - TEMPLATES * TEMPLATE_STORED) // 2     # 404
TEMPLATES_AT = 2 * IMAGE_SIZE                        # 808
TEMPLATES_FLAG_AT, TEMPLATES_READY = TEMPLATES_AT + TEMPLATES * TEMPLATE_STORED, 0x5A
MODEL = "iMAX B6 (ZUML firmware)"
SCHEME = "isp:"                 # a port "isp:usbasp" or "isp:stk500v1@/dev/ttyUSB0": the B6 through a programmer
USBASP = SCHEME + "usbasp"
# The B6 board's limits (firmware/boards/imaxb6: 5 A / 50 W charge, 1 A / 5 W discharge, 27 V), for the window's
# display; a start is never made through the programmer.
B6_LIMITS = dict(protocol=0, model=MODEL, eeprom_size=IMAGE_SIZE, max_data=0, max_charge_a=5.0, max_charge_w=50.0,
                 max_discharge_a=1.0, max_discharge_w=5.0, max_v=27.0, write_s_per_byte=0.0085)

Say = Callable[[str], None]


def disconnect_warning() -> str:
    """What the window and the command line say before the programmer writes (docs/firmware.md says it too)."""
    return _("Disconnect the battery first: while the programmer works it holds the charger's processor in reset, "
             "so nothing switches the power stage off or watches a pack, and a charge in progress is ended (the "
             "firmware starts idle afterwards, it does not resume).")


@dataclass(frozen=True)
class ChipInfo:
    """What the slot lists' check needs of a charger: its charge limit is only used for a start, never made
    through the programmer."""
    model: str = MODEL
    eeprom_size: int = IMAGE_SIZE
    max_charge_a: float | None = None


@dataclass(frozen=True)
class ChipStore:
    """A B6's whole EEPROM as read through the programmer (and the firmware's name from its flash). It answers
    what ``safety.judge_slots`` asks of a charger: no passport (the B6's passport line is not wired) and its own
    start templates."""
    data: bytes
    firmware: str = ""
    info: ChipInfo = ChipInfo()

    @property
    def image(self) -> bytes:
        return self.data[:IMAGE_SIZE]

    def slots(self) -> list[Slot]:
        return slots(self.image)

    @property
    def templates_ready(self) -> bool:
        return self.data[TEMPLATES_FLAG_AT] == TEMPLATES_READY

    def templates(self) -> dict[int, StartTemplate]:
        """The templates the charger starts with: the stored ones, or, while the flag says they were never set
        up (a freshly installed chip), the factory table the firmware stores at its next start."""
        if not self.templates_ready:
            return dict(factory_templates())
        table = {}
        for number in range(1, TEMPLATES + 1):
            at = TEMPLATES_AT + (number - 1) * TEMPLATE_STORED
            stored, check = self.data[at:at + TEMPLATE_SIZE], self.data[at + TEMPLATE_SIZE]
            xor = 0
            for byte in stored:
                xor ^= byte
            if stored[0] > 2 or xor != check:       # task 0xFF: none; a torn write: none, as store.c reads it
                continue
            try:
                table[number] = m.template_of(m.decode_response(0x16, bytes((number,)) + stored))[1]
            except (TemplateError, m.PayloadError):
                continue
        return table

    def templates_named(self, numbers: Iterable[int | None]) -> dict[int, StartTemplate]:
        held = self.templates()
        return {n: held[n] for n in numbers if n is not None and n in held}

    def passport_if_any(self) -> None:
        return None

    def calibration_problem(self) -> str:
        """Why the charger counts itself uncalibrated ("" when its block is valid), as board.c decides."""
        try:
            block = Block.decode(self.data[CALIBRATION_AT:])
        except CalibrationError:
            return _("not calibrated (no valid calibration block): the charger refuses to start until `zuml "
                     "calibrate`")
        if any(full == 0 for __, full in block.pairs):
            return _("not calibrated (a full scale of 0): the charger refuses to start until `zuml calibrate`")
        return ""

    def with_image(self, image: bytes) -> bytes:
        """The EEPROM with ``image`` as the store's image and staging copy; templates and calibration as they are."""
        if len(image) != IMAGE_SIZE:
            raise ValueError(f"the B6's image is {IMAGE_SIZE} bytes, not {len(image)}")
        return image + image + self.data[TEMPLATES_AT:]


def _read(programmer: Programmer, with_flash: bool) -> tuple[bytes, bytes]:
    with tempfile.TemporaryDirectory() as scratch:
        flash, eeprom = Path(scratch) / "flash.bin", Path(scratch) / "eeprom.bin"
        run_avrdude(programmer, [f"flash:r:{flash}:r"] * with_flash + [f"eeprom:r:{eeprom}:r"])
        data = read_file_written(eeprom, "EEPROM").ljust(EEPROM_SIZE, b"\xff")   # avrdude may trim erased bytes
        return (read_file_written(flash, "flash") if with_flash else b""), data[:EEPROM_SIZE]


def read_chip(programmer: Programmer, say: Say) -> ChipStore:
    """The chip's EEPROM, once its flash shows the ZUML imaxb6 image (the store's layout means nothing to another
    firmware, whose own settings it would overwrite)."""
    say(_("Reading the charger's flash and EEPROM through the programmer…"))
    flash, data = _read(programmer, with_flash=True)
    found = ZUML_IMAGE.search(flash)
    if not found:
        raise ProgrammerError(_("the charger does not run the ZUML firmware (its flash holds no ZUML imaxb6 image): "
                                "its EEPROM is another firmware's; install ZUML first (zuml firmware install); "
                                "nothing was written"))
    return ChipStore(data, found.group().rstrip(b"\0").decode("ascii"))


def write_image(programmer: Programmer, chip: ChipStore, image: bytes, say: Say) -> int:
    """Write ``image`` into the store (image and staging copy, bytes 0..807 only), then read the whole EEPROM
    back: the store must hold the new bytes and 808..1023 (templates, calibration) the ones read before.
    Returns how many of the image's bytes changed."""
    wanted = chip.with_image(image)
    changed = sum(a != b for a, b in zip(chip.image, image))
    say(_("Writing the macro store ({n} bytes, templates and calibration left alone)…").format(n=TEMPLATES_AT))
    with tempfile.TemporaryDirectory() as scratch:
        store = Path(scratch) / "store.bin"
        store.write_bytes(wanted[:TEMPLATES_AT])
        run_avrdude(programmer, [f"eeprom:w:{store}:r"])
    say(_("Reading the EEPROM back…"))
    __, now = _read(programmer, with_flash=False)
    if now[:TEMPLATES_AT] != wanted[:TEMPLATES_AT]:
        at = next(k for k in range(TEMPLATES_AT) if now[k] != wanted[k])
        raise ProgrammerError(_("the EEPROM read back differs from what was written at byte {at}: the store is not "
                                "verified; write again, or put a backup back (zuml restore --programmer)").format(at=at))
    if now[TEMPLATES_AT:] != chip.data[TEMPLATES_AT:]:
        at = next(k for k in range(TEMPLATES_AT, EEPROM_SIZE) if now[k] != chip.data[k])
        raise ProgrammerError(_("the templates or the calibration changed during the write (byte {at}): did the "
                                "firmware run in between? Check with zuml slots --programmer").format(at=at))
    return changed


def programmer_of(url: str) -> Programmer | None:
    """The programmer an "isp:" port names (None for any other port)."""
    if not url.startswith(SCHEME):
        return None
    name, __, port = url[len(SCHEME):].partition("@")
    return Programmer(name.strip() or "usbasp", port.strip() or None)


class ProgrammerClient:
    """The B6 through its programmer, answering what the window's slot jobs ask of a ``ChargerClient``: the
    image read and written (each write after a read of the flash that shows the ZUML image), the start
    templates from the EEPROM, no passport. Nothing here runs a macro or streams telemetry: the processor is
    held in reset while avrdude works, so runs are started on the front panel."""

    connected = True

    def __init__(self, url: str, say: Say | None = None):
        """Reads the chip at once (as a serial client's IDENTIFY): one that does not run ZUML is refused here."""
        programmer = programmer_of(url)
        if programmer is None:
            raise ValueError(f"not a programmer port: {url}")
        self.programmer = programmer
        self._say = say or (lambda line: None)
        self._chip = read_chip(programmer, self._say)
        self.info = DeviceInfo(firmware=self._chip.firmware, **B6_LIMITS)

    def close(self) -> None:
        self.connected = False

    def on_telemetry(self, callback) -> None:
        pass

    def on_event(self, callback) -> None:
        pass

    def on_disconnect(self, callback) -> None:
        pass

    def set_telemetry_rate(self, hz: int) -> int:
        raise self._no_run()

    def read_image(self, progress=None, *, stage: str = "read") -> bytes:
        """The store's image, the flash read first (its ZUML image checked); ``progress`` before and after."""
        step = progress or (lambda stage, done, total: None)
        step(stage, 0, IMAGE_SIZE)
        self._chip = read_chip(self.programmer, self._say)
        step(stage, IMAGE_SIZE, IMAGE_SIZE)
        return self._chip.image

    def templates_named(self, numbers: Iterable[int | None]) -> dict[int, StartTemplate]:
        __, data = _read(self.programmer, with_flash=False)
        return ChipStore(data).templates_named(numbers)

    def passport_if_any(self) -> None:
        return None

    def passport_read(self):
        raise DeviceError(m.ErrorCode.NO_PASSPORT, _("the iMAX B6 has no passport line"))

    def write_image(self, image: bytes, progress=None, *, validate: bool = True,
                    current: bytes | None = None) -> WriteResult:
        if len(image) > IMAGE_SIZE:
            raise ImageTooLarge(len(image), IMAGE_SIZE)
        image = bytes(image) + b"\xff" * (IMAGE_SIZE - len(image))
        if validate:
            check_image(image)
        if current is None or current != self._chip.image:
            self.read_image(progress)
        step = progress or (lambda stage, done, total: None)
        step("write", 0, TEMPLATES_AT)
        started = time.monotonic()
        changed = write_image(self.programmer, self._chip, image, self._say)
        step("verify", TEMPLATES_AT, TEMPLATES_AT)
        self._chip = ChipStore(self._chip.with_image(image), self._chip.firmware)
        return WriteResult(IMAGE_SIZE, changed, TEMPLATES_AT, 1, time.monotonic() - started)

    def start(self, *args, **kwargs) -> str:
        raise self._no_run()

    def request(self, name: str, *args, **kwargs) -> bytes:
        """The serial requests (calibration among them) do not go through a programmer."""
        raise DeviceError(m.ErrorCode.UNKNOWN_TYPE, _("{request} needs the charger's serial requests; through the "
                                                      "programmer only its macro store is reached").format(
                                                          request=name))

    def stop(self) -> str:
        raise self._no_run()

    def status(self):
        raise self._no_run()

    @staticmethod
    def _no_run() -> DeviceError:
        return DeviceError(m.ErrorCode.UNKNOWN_TYPE, no_run_text())


def no_run_text() -> str:
    """Why nothing is started through the programmer (the window's Start says it too)."""
    return _("Through the programmer the charger is held in reset: remove the programmer and start the macro on "
             "the charger's front panel (START held)")
