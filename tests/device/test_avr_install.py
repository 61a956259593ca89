"""Installing and restoring the firmware with the real avrdude, against an emulated STK500v1 programmer
holding an ATmega32 (tests/stk500_chip.py): every outcome is asserted on the chip's memories."""
import json

import pytest

from tools import AVRDUDE, needs

from stk500_chip import EEPROM_SIZE, FLASH_SIZE, Atmega32, Stk500Programmer
from zuml_studio.device import avr_install
from zuml_studio.device.avr_install import InstallError, Programmer

pytestmark = needs(AVRDUDE)

ORIGINAL_FLASH = bytes((i * 7 + (i >> 8)) & 0xFF for i in range(FLASH_SIZE))
ORIGINAL_EEPROM = bytes((i * 13 + 1) & 0xFF for i in range(EEPROM_SIZE))
OURS = bytes((i * 31 + 3) & 0xFF for i in range(20_000))
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
        with pytest.raises(InstallError, match=r"brown-out detection is off \(low fuse 0xFF\).*nothing was written"):
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
    chip = StuckBitChip(lfuse=B6_LFUSE)
    with Stk500Programmer(chip) as programmer:
        with pytest.raises(InstallError, match="avrdude failed: .*(mismatch|verification)"):
            avr_install.install(Programmer("stk500v1", programmer.port), image, tmp_path / "b", False, print)


def test_a_read_protected_charger_is_refused_and_left_alone(tmp_path, image):
    chip = original_chip(lock=0xFC)          # LB1 and LB2 programmed: nothing can be read out
    with Stk500Programmer(chip) as programmer:
        with pytest.raises(InstallError, match=r"read-protected \(lock byte 0xFC\).*nothing was written"):
            avr_install.install(Programmer("stk500v1", programmer.port), image, tmp_path / "b", False, print)
    assert chip.erases == 0 and chip.flash == ORIGINAL_FLASH


def test_another_chip_is_refused_by_its_signature(tmp_path, image):
    chip = original_chip(signature=bytes((0x1E, 0x94, 0x03)))          # an ATmega16
    with Stk500Programmer(chip) as programmer:
        with pytest.raises(InstallError, match="signature"):
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
    with pytest.raises(InstallError, match=r"eeprom.hex: missing or changed since the backup was saved"):
        avr_install.restore(Programmer(), folder, print)
    with pytest.raises(InstallError, match="not a firmware backup"):
        avr_install.restore(Programmer(), tmp_path, print)


def test_without_avrdude_it_names_the_package(tmp_path, image, monkeypatch):
    monkeypatch.setenv("PATH", str(tmp_path))
    with pytest.raises(InstallError, match=r"avrdude not found: install it \(apt-get install avrdude\)"):
        avr_install.install(Programmer(), image, tmp_path / "b", False, print)
    assert not (tmp_path / "b").exists()


def test_an_avrdude_that_stops_answering_is_stopped_with_what_to_do(tmp_path, image, monkeypatch):
    # an avrdude whose programmer vanished: it says one thing, then waits on the port for ever
    fake = tmp_path / "bin" / "avrdude"
    fake.parent.mkdir()
    fake.write_text("#!/bin/sh\necho 'avrdude: opening port' >&2\nexec sleep 3600\n")
    fake.chmod(0o755)
    monkeypatch.setenv("PATH", f"{fake.parent}:/usr/bin:/bin")
    monkeypatch.setattr(avr_install, "SILENCE_S", 0.5)
    with pytest.raises(InstallError, match=r"avrdude stopped answering: nothing from it for 0\.5 s.*half-written"):
        avr_install.run_avrdude(Programmer(), ["flash:r:x.hex:i"])
