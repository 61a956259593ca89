"""Installing and restoring the firmware with the real avrdude, against an emulated STK500v1 programmer
holding an ATmega32 (tests/stk500_chip.py): every outcome is asserted on the chip's memories."""
import hashlib
import json

import pytest

from tools import AVRDUDE, needs

from stk500_chip import EEPROM_SIZE, FLASH_SIZE, Atmega32, Stk500Programmer
from zuml_studio.device.install import avr_install, avrdude
from zuml_studio.device.install.avr_install import OriginalUnreadable
from zuml_studio.device.install.avrdude import Programmer, ProgrammerError

pytestmark = needs(AVRDUDE)

ORIGINAL_FLASH = bytes((i * 7 + (i >> 8)) & 0xFF for i in range(FLASH_SIZE))
ORIGINAL_EEPROM = bytes((i * 13 + 1) & 0xFF for i in range(EEPROM_SIZE))
OURS = bytes((i * 31 + 3) & 0xFF for i in range(20_000)) + b"zuml-fw 0.2 imaxb6\0"      # the name board.c puts in
B6_LFUSE = 0x3F             # external 16 MHz crystal, BOD on at 4.0 V (docs/firmware.md)
B6_HFUSE = 0xC9            # JTAG off (PORTC drives the LCD), CKOPT programmed for the crystal


def original_chip(**fuses) -> Atmega32:
    chip = Atmega32(flash=bytearray(ORIGINAL_FLASH), eeprom=bytearray(ORIGINAL_EEPROM))
    for name, value in {"lfuse": B6_LFUSE, "hfuse": B6_HFUSE, **fuses}.items():
        setattr(chip, name, value)
    return chip


@pytest.fixture
def image(tmp_path):
    path = tmp_path / "zuml.bin"
    path.write_bytes(OURS)
    return path


def lines():
    said = []
    return said, said.append


def test_install_saves_the_original_writes_ours_and_restore_puts_the_original_back(tmp_path, image):
    chip = original_chip()
    backup = tmp_path / "backup"
    said, say = lines()
    with Stk500Programmer(chip) as programmer:
        link = Programmer("stk500v1", programmer.port)
        fuses = avr_install.install(link, image, backup, False, say)
        assert chip.flash == OURS + b"\xff" * (FLASH_SIZE - len(OURS))
        assert chip.eeprom == b"\xff" * EEPROM_SIZE          # erased: empty store, not calibrated
        assert (chip.lfuse, chip.hfuse) == (B6_LFUSE, B6_HFUSE) and fuses.brown_out_ok
        manifest = json.loads((backup / "backup.json").read_text())
        assert (manifest["part"], manifest["lfuse"], manifest["hfuse"]) == ("m32", B6_LFUSE, B6_HFUSE)
        assert any("verified" in line for line in said)

        avr_install.restore(link, backup, say)
    assert chip.flash == ORIGINAL_FLASH and chip.eeprom == ORIGINAL_EEPROM
    assert (chip.lfuse, chip.hfuse) == (B6_LFUSE, B6_HFUSE)


def test_brown_out_off_is_refused_after_the_backup_and_before_anything_is_written(tmp_path, image):
    chip = original_chip(lfuse=0xFF)        # crystal, BODEN unprogrammed
    with Stk500Programmer(chip) as programmer:
        with pytest.raises(ProgrammerError, match=r"brown-out detection is off \(low fuse 0xFF\).*nothing was written"):
            avr_install.install(Programmer("stk500v1", programmer.port), image, tmp_path / "b", False, print)
    assert chip.erases == 0 and chip.flash == ORIGINAL_FLASH and chip.eeprom == ORIGINAL_EEPROM
    assert chip.lfuse == 0xFF and (tmp_path / "b" / "flash.hex").is_file()


def test_fix_fuses_programs_only_the_bod_bits_and_restore_puts_the_fuse_back(tmp_path, image):
    chip = original_chip(lfuse=0xFF)
    with Stk500Programmer(chip) as programmer:
        link = Programmer("stk500v1", programmer.port)
        fuses = avr_install.install(link, image, tmp_path / "b", True, print)
        assert chip.lfuse == 0x3F == fuses.low          # BODLEVEL and BODEN programmed, SUT/CKSEL kept
        assert chip.flash[:len(OURS)] == OURS
        avr_install.restore(link, tmp_path / "b", print)
    assert chip.lfuse == 0xFF and chip.flash == ORIGINAL_FLASH


class StuckBitChip(Atmega32):
    """A flash cell that does not take a 0 (a worn or damaged chip): the write 'succeeds', the verify must not."""

    def program_flash_page(self, address, data):
        super().program_flash_page(address, data)
        if address <= 0x100 < address + len(data):
            self.flash[0x100] |= 0x04


def test_a_flash_that_does_not_take_the_write_fails_the_verify(tmp_path, image):
    assert OURS[0x100] & 0x04 == 0
    chip = StuckBitChip(lfuse=B6_LFUSE, hfuse=B6_HFUSE)
    with Stk500Programmer(chip) as programmer:
        with pytest.raises(ProgrammerError, match="avrdude failed: .*(mismatch|verification).*; the chip was erased "
                                                  "and is half-written: put the backup back: zuml firmware restore "
                                                  f"{tmp_path / 'b'} --programmer stk500v1 --port {programmer.port}$"):
            avr_install.install(Programmer("stk500v1", programmer.port), image, tmp_path / "b", False, print)


def test_a_locked_charger_is_said_to_be_unrecoverable_before_anything_is_written(tmp_path, image):
    chip = original_chip(lock=0xFC)          # LB1 and LB2 programmed: nothing can be read out
    with Stk500Programmer(chip) as programmer:
        link = Programmer("stk500v1", programmer.port)
        with pytest.raises(OriginalUnreadable, match=r"cannot be read: its lock bits are set \(lock byte 0xFC\).*"
                                                     r"no way back.*Nothing was written.*--no-way-back"):
            avr_install.install(link, image, tmp_path / "b", False, print)
        assert chip.erases == 0 and chip.flash == ORIGINAL_FLASH
        said, say = lines()
        avr_install.install(link, image, tmp_path / "c", False, say, no_way_back=True)   # the user accepted it
        assert chip.flash[:len(OURS)] == OURS and chip.lock == 0xFF
        assert any("No way back, as accepted" in line for line in said)
    with pytest.raises(ProgrammerError, match="could not be read when this backup was made.*nothing to put back"):
        avr_install.restore(link, tmp_path / "c", print)


def test_a_flash_that_reads_as_a_repeating_pattern_is_an_unreadable_original(tmp_path, image):
    chip = original_chip(flash=bytearray(bytes(range(16)) * (FLASH_SIZE // 16)))    # unlocked, by its lock byte
    with Stk500Programmer(chip) as programmer:
        with pytest.raises(OriginalUnreadable, match="one short pattern repeated"):
            avr_install.install(Programmer("stk500v1", programmer.port), image, tmp_path / "b", False, print)
    assert chip.erases == 0


def test_a_backup_is_never_written_over_and_the_first_original_is_kept(tmp_path, image, monkeypatch):
    monkeypatch.setenv("ZUML_STUDIO_CONFIG_DIR", str(tmp_path / "config"))
    chip = original_chip()
    with Stk500Programmer(chip) as programmer:
        link = Programmer("stk500v1", programmer.port)
        said, say = lines()
        avr_install.install(link, image, tmp_path / "first", False, say)
        kept = avr_install.original_folder(hashlib.sha256(ORIGINAL_FLASH).hexdigest())
        assert (kept / "flash.hex").read_bytes() == (tmp_path / "first" / "flash.hex").read_bytes()
        assert any(f"kept also as {kept}" in line for line in said)
        with pytest.raises(ProgrammerError, match="first is not a new or empty folder: a backup is never written "
                                                  "over.*nothing was written"):
            avr_install.install(link, image, tmp_path / "first", False, print)      # an update, same folder
        said, say = lines()
        avr_install.install(link, image, tmp_path / "second", False, say)           # an update: ZUML over ZUML
        assert any("holds ZUML's own image, not the charger's original" in line for line in said)
        said, say = lines()
        avr_install.restore(link, tmp_path / "second", say)
        assert not any("original firmware is back" in line for line in said)
        assert f"ZUML's own image, not the charger's original; the charger's original is kept in {kept}" in said[-1]
        assert chip.flash[:len(OURS)] == OURS
        avr_install.restore(link, tmp_path / "first", say)
        assert said[-1] == "The original firmware is back (verified: flash, EEPROM and fuses)"
    assert chip.flash == ORIGINAL_FLASH and chip.eeprom == ORIGINAL_EEPROM


def test_the_default_backup_folder_is_a_new_one_each_time(tmp_path, monkeypatch):
    monkeypatch.setenv("ZUML_STUDIO_CONFIG_DIR", str(tmp_path))
    first = avr_install.default_backup_folder()
    first.mkdir(parents=True)
    assert avr_install.default_backup_folder() != first


def test_factory_fuses_are_refused_each_reason_said_and_fix_fuses_sets_what_the_b6_needs(tmp_path, image):
    chip = original_chip(lfuse=0xE1, hfuse=0x99)    # as an ATmega32 ships: 1 MHz RC, BOD off, JTAG on
    with Stk500Programmer(chip) as programmer:
        link = Programmer("stk500v1", programmer.port)
        with pytest.raises(ProgrammerError) as refused:
            avr_install.install(link, image, tmp_path / "a", False, print)
        assert str(refused.value) == (
            "brown-out detection is off (low fuse 0xE1): the firmware needs it at 4.0 V; the clock fuses do not "
            "select the B6's 16 MHz crystal (low fuse 0xE1, high fuse 0x99: CKSEL3..1 must be 101..111 and CKOPT "
            "programmed); JTAG is enabled (high fuse 0x99): the LCD is on the JTAG pins PC2..PC5 and would show "
            "squares; nothing was written (--fix-fuses sets them: low fuse 0x3F, high fuse 0xC9)")
        assert chip.erases == 0
        fuses = avr_install.install(link, image, tmp_path / "b", True, print)
        assert (chip.lfuse, chip.hfuse) == (0x3F, 0xC9) == (fuses.low, fuses.high)
        avr_install.restore(link, tmp_path / "b", print)
    assert (chip.lfuse, chip.hfuse) == (0xE1, 0x99) and chip.flash == ORIGINAL_FLASH


def test_the_fuse_checks_by_the_datasheet():
    b6 = avr_install.Fuses(0x3F, 0xC5, 0xFF)            # cheali's README values
    assert b6.problems() == [] and b6.fixed() == b6
    assert "2.7 V" in avr_install.Fuses(0xBF, 0xC5, 0xFF).problems()[0]        # BODEN on, BODLEVEL off
    assert avr_install.Fuses(0x3F, 0xD5, 0xFF).problems()[0].startswith("the clock fuses")   # CKOPT off
    assert avr_install.Fuses(0x24, 0xC5, 0xFF).problems()[0].startswith("the clock fuses")   # internal RC 8 MHz
    assert avr_install.Fuses(0x3F, 0x85, 0xFF).problems()[0].startswith("JTAG is enabled")
    assert avr_install.Fuses(0x3F, 0x85, 0xFF).fixed().high == 0xC5
    assert avr_install.Fuses(0xEF, 0xC5, 0xFF).fixed().low == 0x2F      # crystal kept with its own SUT; BOD on


def test_another_chip_is_refused_by_its_signature(tmp_path, image):
    chip = original_chip(signature=bytes((0x1E, 0x94, 0x03)))          # an ATmega16
    with Stk500Programmer(chip) as programmer:
        with pytest.raises(ProgrammerError, match="signature"):
            avr_install.install(Programmer("stk500v1", programmer.port), image, tmp_path / "b", False, print)
    assert chip.erases == 0 and chip.flash == ORIGINAL_FLASH


def test_restore_refuses_a_backup_changed_since_it_was_saved(tmp_path):
    folder = tmp_path / "backup"
    folder.mkdir()
    (folder / "flash.hex").write_text(":00000001FF\n")
    (folder / "eeprom.hex").write_text(":00000001FF\n")
    manifest = {"part": "m32", "lfuse": 0x3F, "hfuse": 0xC9, "lock": 0xFF,
                "files": {"flash.hex": avr_install.sha256(folder / "flash.hex"), "eeprom.hex": "0" * 64}}
    (folder / "backup.json").write_text(json.dumps(manifest))
    with pytest.raises(ProgrammerError, match=r"eeprom.hex: missing or changed since the backup was saved"):
        avr_install.restore(Programmer(), folder, print)
    with pytest.raises(ProgrammerError, match="not a firmware backup"):
        avr_install.restore(Programmer(), tmp_path, print)


def test_without_avrdude_it_names_the_package(tmp_path, image, monkeypatch):
    monkeypatch.setenv("PATH", str(tmp_path))
    with pytest.raises(ProgrammerError, match=r"avrdude not found: install it \(apt-get install avrdude\)"):
        avr_install.install(Programmer(), image, tmp_path / "b", False, print)
    assert not (tmp_path / "b").exists()


def test_an_avrdude_that_stops_answering_is_stopped_with_what_to_do(tmp_path, image, monkeypatch):
    # an avrdude whose programmer vanished: it says one thing, then waits on the port for ever
    fake = tmp_path / "bin" / "avrdude"
    fake.parent.mkdir()
    fake.write_text("#!/bin/sh\necho 'avrdude: opening port' >&2\nexec sleep 3600\n")
    fake.chmod(0o755)
    monkeypatch.setenv("PATH", f"{fake.parent}:/usr/bin:/bin")
    monkeypatch.setattr(avrdude, "SILENCE_S", 0.5)
    with pytest.raises(ProgrammerError, match=r"avrdude stopped answering: nothing from it for 0\.5 s"):
        avrdude.run_avrdude(Programmer(), ["flash:r:x.hex:i"])
