"""Device ▸ Install Firmware on an iMAX B6…: the warnings first, Install only once they are read, then the
real avrdude against the emulated STK500v1 programmer (tests/stk500_chip.py), off the GUI thread."""
from PySide6.QtWidgets import QLabel

from stk500_chip import FLASH_SIZE, Atmega32, Stk500Programmer
from tools import AVRDUDE, needs
from zuml_studio.ui.device.firmware_install_dialog import FirmwareInstallDialog

ORIGINAL = bytes((i * 3 + 7 + (i >> 8)) & 0xFF for i in range(FLASH_SIZE))


def test_the_device_menu_opens_the_dialog_with_its_warnings(make_window, qtbot):
    w = make_window()
    device = next(a.menu() for a in w.menuBar().actions() if a.text().replace("&", "") == "Device")
    assert w.act_install_firmware in device.actions()
    w.act_install_firmware.trigger()
    dialog = w.findChild(FirmwareInstallDialog)
    qtbot.waitUntil(dialog.isVisible)
    assert any("simulated board only" in label.text() for label in dialog.findChildren(QLabel))
    assert not dialog.install_button.isEnabled()
    dialog.read_it.setChecked(True)
    assert dialog.install_button.isEnabled()
    dialog.close()


def filled(qtbot, tmp_path, port):
    """The dialog with the emulated programmer, an image and tmp_path/original as the backup folder."""
    image = tmp_path / "zuml.bin"
    image.write_bytes(bytes(range(200)) * 50)
    dialog = FirmwareInstallDialog()
    qtbot.addWidget(dialog)
    dialog.programmer.setCurrentText("stk500v1")
    dialog.port.setText(port)
    dialog.image.setText(str(image))
    dialog.backup.setText(str(tmp_path / "original"))
    dialog.read_it.setChecked(True)
    return dialog


@needs(AVRDUDE)
def test_install_then_restore_from_the_dialog(qtbot, tmp_path):
    chip = Atmega32(flash=bytearray(ORIGINAL), lfuse=0x3F, hfuse=0xC9)
    with Stk500Programmer(chip) as programmer:
        dialog = filled(qtbot, tmp_path, programmer.port)
        dialog.install_button.click()
        assert not dialog.install_button.isEnabled() and not dialog.restore_button.isEnabled()
        qtbot.waitUntil(lambda: not dialog.busy(), timeout=120_000)
        log = dialog.log.toPlainText()
        assert "Installed and verified" in log and "Done." in log, log
        assert chip.flash[:10000] == bytes(range(200)) * 50
        assert dialog.backup.text() == str(tmp_path / "original-2")      # the next install: a new folder

        dialog.restore(tmp_path / "original")
        qtbot.waitUntil(lambda: not dialog.busy(), timeout=120_000)
        assert "The original firmware is back" in dialog.log.toPlainText()
    assert chip.flash == ORIGINAL


def test_a_failure_is_one_line_in_the_log(qtbot, tmp_path):
    dialog = FirmwareInstallDialog()
    qtbot.addWidget(dialog)
    dialog.image.setText(str(tmp_path / "zuml.txt"))
    dialog.read_it.setChecked(True)
    dialog.install_button.click()
    qtbot.waitUntil(lambda: not dialog.busy())
    assert dialog.log.toPlainText().splitlines()[-1].startswith("Stopped: ")
    assert dialog.install_button.isEnabled()


@needs(AVRDUDE)
def test_a_locked_original_is_said_before_anything_is_written_and_installed_only_after_yes(qtbot, tmp_path,
                                                                                          monkeypatch):
    from zuml_studio.ui.device import firmware_install_dialog
    asked = []
    answer = [False]
    monkeypatch.setattr(firmware_install_dialog, "ask_no_way_back",
                        lambda parent, reason: asked.append(reason) or answer[0])
    chip = Atmega32(flash=bytearray(ORIGINAL), lfuse=0x3F, hfuse=0xC9, lock=0xFC)
    with Stk500Programmer(chip) as programmer:
        dialog = filled(qtbot, tmp_path, programmer.port)
        dialog.install_button.click()
        qtbot.waitUntil(lambda: not dialog.busy() and bool(asked), timeout=120_000)
        assert "lock bits are set (lock byte 0xFC)" in asked[0] and "no way back" in asked[0]
        assert chip.erases == 0 and chip.flash == ORIGINAL          # No: nothing written
        answer[0] = True
        dialog.install_button.click()
        qtbot.waitUntil(lambda: not dialog.busy() and len(asked) == 2 and "Installed" in dialog.log.toPlainText(),
                        timeout=120_000)
    assert chip.flash[:10000] == bytes(range(200)) * 50
    assert "No way back, as accepted" in dialog.log.toPlainText()
