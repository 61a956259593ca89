"""zuml firmware install / restore: the real avrdude against the emulated STK500v1 programmer."""
from stk500_chip import FLASH_SIZE, Atmega32, Stk500Programmer
from tools import AVRDUDE, needs

needs_avrdude = needs(AVRDUDE)
ORIGINAL = bytes((i * 5 + (i >> 8)) & 0xFF for i in range(FLASH_SIZE))


@needs_avrdude
def test_install_then_restore_from_the_printed_backup(zuml, tmp_path):
    image = tmp_path / "zuml.bin"
    image.write_bytes(bytes(range(256)) * 40)
    chip = Atmega32(flash=bytearray(ORIGINAL), lfuse=0xFF)
    with Stk500Programmer(chip) as programmer:
        link = ("--programmer", "stk500v1", "--port", programmer.port)
        code, out, err = zuml("firmware", "install", *link, "--image", str(image), "--backup-dir",
                              str(tmp_path / "orig"), "--yes")
        assert code == 1 and "brown-out detection is off (low fuse 0xFF)" in err and chip.erases == 0
        assert "simulated board only" in err                  # the warnings come first
        code, out, err = zuml("firmware", "install", *link, "--image", str(image), "--backup-dir",
                              str(tmp_path / "orig"), "--fix-fuses", "--yes")
        assert code == 1 and "orig is not a new or empty folder: a backup is never written over" in err
        code, out, err = zuml("firmware", "install", *link, "--image", str(image), "--backup-dir",
                              str(tmp_path / "orig2"), "--fix-fuses", "--yes")
        assert code == 0, err
        assert chip.flash[:10240] == bytes(range(256)) * 40 and chip.lfuse == 0x3F
        restore = f"zuml firmware restore {tmp_path / 'orig2'} --programmer stk500v1 --port {programmer.port}"
        assert out.splitlines()[-1] == f"To put the backup back: {restore}"
        code, out, err = zuml(*restore.split()[1:])
        assert code == 0, err
        assert out.splitlines()[-1] == "The original firmware is back (verified: flash, EEPROM and fuses)"
    assert chip.flash == ORIGINAL and chip.lfuse == 0xFF


@needs_avrdude
def test_install_without_yes_on_a_pipe_asks_for_it(zuml, tmp_path, monkeypatch):
    monkeypatch.setattr("sys.stdin.isatty", lambda: False)
    code, out, err = zuml("firmware", "install", "--image", str(tmp_path / "x.hex"))
    assert code == 2 and err.splitlines()[-1] == ("zuml: error: the warnings above need an answer: add --yes to "
                                                  "install without a question")


@needs_avrdude
def test_bad_image_and_bad_backup_are_one_line_errors(zuml, tmp_path):
    code, out, err = zuml("firmware", "install", "--image", str(tmp_path / "x.txt"), "--yes")
    assert code == 1 and err.splitlines()[-1].endswith("x.txt: the firmware image must be .hex, .elf or .bin")
    code, out, err = zuml("firmware", "restore", str(tmp_path))
    assert code == 1 and err.startswith(f"zuml: error: {tmp_path}: not a firmware backup")


def test_without_avrdude_it_says_which_package_to_install(zuml, tmp_path, monkeypatch):
    monkeypatch.setenv("PATH", str(tmp_path))
    code, out, err = zuml("firmware", "install", "--yes")
    assert code == 2 and err == "zuml: error: avrdude not found: install it (apt-get install avrdude)\n"
