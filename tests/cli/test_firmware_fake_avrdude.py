"""zuml firmware install / restore against a misbehaving avrdude (tests/fake_avrdude.py, first in PATH): every
case ends in one line that says what was left and what to do next, never a traceback or a hang, and never
claims an original is back when it is not."""
import json
import shutil
from pathlib import Path

import pytest

from zuml_studio.device.install import avr_install, avrdude

FAKE = Path(__file__).resolve().parents[1] / "fake_avrdude.py"
ORIGINAL = b"ORIGINAL-IMAX-B6-FIRMWARE" * 1000 + b"\xff" * (32768 - 25000)
ORIGINAL_EEPROM = b"ORIG-EEPROM" * 90 + b"\xff" * (1024 - 990)


@pytest.fixture
def chip(tmp_path, monkeypatch):
    """The fake's chip, holding an original; ``chip.mode(m)`` sets how avrdude misbehaves."""
    state = tmp_path / "chip"
    state.mkdir()
    (state / "flash.bin").write_bytes(ORIGINAL)
    (state / "eeprom.bin").write_bytes(ORIGINAL_EEPROM)
    bin_dir = tmp_path / "bin"
    bin_dir.mkdir()
    shutil.copy(FAKE, bin_dir / "avrdude")
    monkeypatch.setenv("PATH", f"{bin_dir}:/usr/bin:/bin")
    monkeypatch.setenv("FAKE_AVR_STATE", str(state))

    class Chip:
        path = state

        @staticmethod
        def mode(name):
            monkeypatch.setenv("FAKE_AVR_MODE", name)

        @staticmethod
        def flash():
            return (state / "flash.bin").read_bytes()

        @staticmethod
        def fuses():
            return json.loads((state / "fuses.json").read_text())
    return Chip


@pytest.fixture
def image(tmp_path):
    path = tmp_path / "zuml.bin"
    path.write_bytes(bytes(range(256)) * 80 + b"zuml-fw 0.2 imaxb6\0")
    return path


def install(zuml, image, folder, *more):
    return zuml("firmware", "install", "--yes", "--image", str(image), "--backup-dir", str(folder), *more)


def last_line(err):
    lines = [line for line in err.splitlines() if not line.startswith("warning:")]
    assert len(lines) == 1 and "Traceback" not in err, err
    return lines[0]


@pytest.mark.parametrize("mode, said", [
    ("fail", "avrdude failed: error: could not find USB device with vid=0x16c0 pid=0x5dc; nothing was written to "
             "the charger: check the programmer's cable and the charger's power, then try again"),
    ("garbage_exit0", "avrdude said it read the lfuse but wrote no lfuse.hex (is it really avrdude, and the "
                      "programmer connected?); nothing was written to the charger"),
    ("lfuse_garbage", "avrdude's lfuse file holds no fuse value ('zz'): the fuses are not known; nothing was written "
                      "to the charger"),
    ("read_truncates", "avrdude failed: verification error, first mismatch at byte 0x0000; nothing was written to "
                       "the charger"),
])
def test_a_failure_before_writing_is_one_line_and_leaves_the_original(zuml, chip, image, tmp_path, mode, said):
    chip.mode(mode)
    code, out, err = install(zuml, image, tmp_path / "bk")
    assert code == 1 and last_line(err).startswith(f"zuml: error: {said}")
    assert chip.flash() == ORIGINAL


@pytest.mark.parametrize("mode", ["fail_on_write", "fail_mid_flash_write"])
def test_a_write_failing_after_the_erase_says_half_written_and_the_exact_restore(zuml, chip, image, tmp_path, mode,
                                                                                 monkeypatch):
    chip.mode("ok")
    # the backup is read by a working avrdude, then the write fails: the mode changes at the erasing run
    real = avrdude.run_avrdude

    def failing_writes(programmer, operations, erase=False):
        if erase:
            chip.mode(mode)
        return real(programmer, operations, erase)
    monkeypatch.setattr(avr_install, "run_avrdude", failing_writes)
    code, out, err = install(zuml, image, tmp_path / "bk")
    monkeypatch.setattr(avr_install, "run_avrdude", real)
    assert code == 1 and last_line(err) == (
        "zuml: error: avrdude failed: error: programmer is not responding; the chip was erased and is half-written: "
        f"put the backup back: zuml firmware restore {tmp_path / 'bk'}")
    chip.mode("ok")
    code, out, err = zuml("firmware", "restore", str(tmp_path / "bk"))
    assert code == 0, err
    assert out.splitlines()[-1] == "The original firmware is back (verified: flash, EEPROM and fuses)"
    assert chip.flash() == ORIGINAL


def test_restore_with_a_failing_avrdude_says_so_and_how_to_retry(zuml, chip, image, tmp_path):
    chip.mode("ok")
    assert install(zuml, image, tmp_path / "bk")[0] == 0
    chip.mode("fail")
    code, out, err = zuml("firmware", "restore", str(tmp_path / "bk"))
    assert code == 1 and last_line(err).endswith(f"restore again: zuml firmware restore {tmp_path / 'bk'}")
    assert "is back" not in out


def test_restore_whose_fuse_writes_are_ignored_is_not_verified(zuml, chip, image, tmp_path):
    (chip.path / "fuses.json").write_text(json.dumps({"lfuse": 0xFF, "hfuse": 0xC9, "lock": 0xFF}))
    chip.mode("ok")
    code, out, err = install(zuml, image, tmp_path / "bk", "--fix-fuses")
    assert code == 0 and chip.fuses()["lfuse"] == 0x3F, err
    chip.mode("fuse_write_ignored")
    code, out, err = zuml("firmware", "restore", str(tmp_path / "bk"))
    assert code == 1 and "is back" not in out
    assert last_line(err) == (
        "zuml: error: the flash and EEPROM are back, but the fuses read back (low 0x3F, high 0xC9) are not the saved "
        f"ones (low 0xFF, high 0xC9): not verified; restore again: zuml firmware restore {tmp_path / 'bk'}")


def test_a_second_install_into_the_first_backup_s_folder_is_refused(zuml, chip, image, tmp_path):
    chip.mode("ok")
    assert install(zuml, image, tmp_path / "bk")[0] == 0
    saved = (tmp_path / "bk" / "flash.hex").read_bytes()
    code, out, err = install(zuml, image, tmp_path / "bk")
    assert code == 1 and "a backup is never written over" in last_line(err)
    assert (tmp_path / "bk" / "flash.hex").read_bytes() == saved
    code, out, err = zuml("firmware", "restore", str(tmp_path / "bk"))
    assert code == 0 and chip.flash() == ORIGINAL


def test_an_update_s_backup_is_never_called_the_original(zuml, chip, image, tmp_path):
    chip.mode("ok")
    assert install(zuml, image, tmp_path / "first")[0] == 0
    assert install(zuml, image, tmp_path / "update")[0] == 0
    code, out, err = zuml("firmware", "restore", str(tmp_path / "update"))
    assert code == 0 and "original firmware is back" not in out
    assert "is back (verified), but it is ZUML's own image, not the charger's original; the charger's original is " \
           "kept in " in out


@pytest.mark.parametrize("mode, total, silence, said", [
    ("hang_chatty", 2.0, 60.0, "avrdude was still running after 2 s (its last words: usbasp_transmit(): retrying "
                               "...), so it was stopped (is the programmer plugged in and the chip powered?); "
                               "nothing was written"),
    ("hang_silent", 300.0, 1.0, "avrdude stopped answering: nothing from it for 1 s, so it was stopped (is the "
                                "programmer still plugged in?); nothing was written"),
])
def test_an_avrdude_that_never_ends_is_stopped_after_the_stated_limits(zuml, chip, image, tmp_path, monkeypatch,
                                                                      mode, total, silence, said):
    monkeypatch.setattr(avrdude, "TOTAL_S", total)
    monkeypatch.setattr(avrdude, "SILENCE_S", silence)
    chip.mode(mode)
    code, out, err = install(zuml, image, tmp_path / "bk")
    assert code == 1 and last_line(err).startswith(f"zuml: error: {said}")
