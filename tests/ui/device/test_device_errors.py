"""What users will meet, each a clear message in the panel (never a traceback, never a freeze):
a port that does not exist, something that is not a charger, a passport that forbids the
macro, a cable pulled mid-flash, an image larger than the EEPROM, a link that goes away;
and Backup/Restore, the port chooser's background scans."""
import os
import socket
import sys
import threading

import pytest

from device_helpers import WAIT_MS, connect, flash_and_start
from helpers import until
from zuml_studio.device.zuml.client import ChargerClient
from zuml_studio.device.links.ports import PortInfo

pytestmark = pytest.mark.skipif(os.name != "posix", reason="the virtual chargers use ptys here")


def test_a_port_that_does_not_exist_says_so_and_stays_disconnected(qtbot, make_panel):
    panel = make_panel()
    with qtbot.waitSignal(panel.connectedChanged, timeout=WAIT_MS) as blocker:
        panel.connect_to("/dev/ttyZUML-not-there")
    assert blocker.args == [False]
    text = panel.message_text()
    assert text.startswith("Cannot connect: /dev/ttyZUML-not-there: no such port")
    assert "Traceback" not in text
    assert not panel.is_connected() and panel.connect_button.text() == "Connect"
    assert panel.ports.url.text() == "/dev/ttyZUML-not-there"
    # the empty session CSV of a failed connect is not left behind
    assert not list(panel.session_dir.glob("session-*.csv"))


def test_something_that_is_not_a_charger(qtbot, make_panel):
    server = socket.socket()
    server.bind(("127.0.0.1", 0))
    server.listen(1)
    held = []
    stop = threading.Event()

    def accept():
        server.settimeout(0.2)
        while not stop.is_set():
            try:
                conn, _ = server.accept()
                held.append(conn)            # accepts, reads nothing, answers nothing
            except OSError:
                pass

    thread = threading.Thread(target=accept, daemon=True)
    thread.start()
    try:
        panel = make_panel()
        url = f"socket://127.0.0.1:{server.getsockname()[1]}"
        with qtbot.waitSignal(panel.connectedChanged, timeout=WAIT_MS) as blocker:
            panel.connect_to(url, "zuml")
        assert blocker.args == [False]
        assert "no ZUML charger answered" in panel.message_text()
        assert not panel.is_connected()
        # "Auto" (the default) then listens for a monitor-only charger on the same port
        with qtbot.waitSignal(panel.connectedChanged, timeout=WAIT_MS) as blocker:
            panel.connect_to(url, "auto")
        assert blocker.args == [True] and panel.is_monitoring() and not panel.is_connected()
        assert panel.message_text().startswith(f"No ZUML charger answered on {url}: listening for a monitor-only")
        assert not panel.flash_button.isEnabled() and not panel.start_button.isEnabled()
        with qtbot.waitSignal(panel.connectedChanged, timeout=WAIT_MS) as blocker:
            panel.disconnect()
        assert blocker.args == [False] and not panel.is_monitoring()
    finally:
        stop.set()
        thread.join(2)
        for conn in held:
            conn.close()
        server.close()


def test_a_passport_of_another_chemistry_refuses_start(qtbot, make_panel):
    panel = make_panel()
    panel.v_passport.setCurrentIndex(panel.v_passport.findData("LiPo"))
    connect(qtbot, panel)
    assert panel.pp_labels["type"].text().startswith("LiPo")
    ok, text = flash_and_start(qtbot, panel)
    assert not ok
    assert text.startswith("Not started: NiMh-dV: the safety check refused it:")
    assert "• the macro is for NiMh; the battery is LiPo" in text and "--force-unsafe" in text
    assert panel.message_text() == text and "b00020" in panel.message.styleSheet()
    assert panel.connection.virtual_device.state == "idle"


def test_unplugged_mid_flash_keeps_the_previous_image(qtbot, make_panel, monkeypatch):
    panel = make_panel()
    connect(qtbot, panel)
    device = panel.connection.virtual_device
    before = device.eeprom_image
    original = ChargerClient._call
    pulled = []

    def call(self, name, *args, **kw):
        if name == "WRITE_STAGE" and not pulled:
            pulled.append(True)
            panel.connection.hang_up_virtual()          # the cable goes, mid-transfer
        return original(self, name, *args, **kw)

    monkeypatch.setattr(ChargerClient, "_call", call)
    with qtbot.waitSignal(panel.flashFinished, timeout=WAIT_MS) as flashed:
        panel.flash()
    ok, text = flashed.args
    assert pulled and not ok
    assert "while flashing" in text and "the charger keeps its previous image" in text
    assert device.eeprom_image == before
    qtbot.waitUntil(lambda: not panel.is_connected(), timeout=WAIT_MS)
    assert panel.connect_button.text() == "Connect"
    assert panel.result_label.text() == text


def test_an_image_larger_than_the_eeprom(qtbot, make_panel, make_charger):
    device, port = make_charger(eeprom_size=32)
    panel = make_panel()
    connect(qtbot, panel, port)
    assert "EEPROM 32 bytes" in panel.info_label.full_text()
    with qtbot.waitSignal(panel.flashFinished, timeout=WAIT_MS) as flashed:
        panel.flash()
    ok, text = flashed.args
    assert not ok
    assert text == "The image needs 38 bytes; the charger has 32. Nothing was written."
    assert device.eeprom_image == b"\xff" * 32


def test_the_link_going_away_resets_the_panel_and_keeps_plot_and_csv(qtbot, make_panel):
    panel = make_panel()
    panel.v_speed.setValue(1000)
    panel.rate.setValue(50)
    connect(qtbot, panel)
    flash_and_start(qtbot, panel)
    qtbot.waitUntil(lambda: panel.plot.points > 5, timeout=WAIT_MS)
    path = panel.session_file
    with qtbot.waitSignal(panel.connectedChanged, timeout=WAIT_MS) as gone:
        panel.connection.hang_up_virtual()
    assert gone.args == [False]
    text = panel.message_text()
    assert text.startswith("Disconnected: ") and "The plot and the session CSV are kept." in text
    assert panel.plot.points > 5 and path.exists()
    assert path.read_text().count("\n") > 5
    assert not panel.start_button.isEnabled() and panel.connect_button.isEnabled()
    # and it connects again: a new session CSV; the built-in charger kept its EEPROM, as a real one does
    connect(qtbot, panel)
    assert panel.session_file != path
    assert panel.slot_names() == ["NiMh-dV"]


def test_flash_needs_a_link_and_a_valid_macro(qtbot, make_panel, editor):
    panel = make_panel()
    with qtbot.waitSignal(panel.flashFinished, timeout=WAIT_MS) as blocker:
        panel.flash()
    assert blocker.args == [False, "Connect to a charger first, then Compile & Flash."]
    connect(qtbot, panel)
    editor.set(None)
    with qtbot.waitSignal(panel.flashFinished, timeout=WAIT_MS) as blocker:
        panel.flash()
    assert not blocker.args[0] and "The macro has errors" in blocker.args[1]
    with qtbot.waitSignal(panel.startFinished, timeout=WAIT_MS) as blocker:
        panel.start()
    assert not blocker.args[0] and "Compile & Flash one first" in blocker.args[1]


def test_flash_into_a_chosen_slot_and_backup_restore(qtbot, make_panel, editor, tmp_path):
    panel = make_panel()
    connect(qtbot, panel)
    for name in ("NiMh-dV", "LiPo"):
        editor.set(name)
        with qtbot.waitSignal(panel.flashFinished, timeout=WAIT_MS) as flashed:
            panel.flash()
        assert flashed.args[0], flashed.args[1]
    assert panel.slot_names() == ["NiMh-dV", "LiPo"]
    assert panel.run_slot.currentData() == 1          # Start defaults to the macro just flashed
    backup = tmp_path / "backup.bin"
    with qtbot.waitSignal(panel.operationFinished, timeout=WAIT_MS) as saved:
        panel.backup(backup)
    assert saved.args[:2] == ["backup", True] and "2 macros" in saved.args[2]
    assert backup.read_bytes() == panel.connection.virtual_device.eeprom_image

    editor.set("NiCd")
    panel.flash_slot.setCurrentIndex(panel.flash_slot.findData(0))      # replace slot 0
    with qtbot.waitSignal(panel.flashFinished, timeout=WAIT_MS) as flashed:
        panel.flash()
    assert flashed.args[0] and "into slot 0" in flashed.args[1] and "(it replaced NiMh-dV)" in flashed.args[1]
    assert panel.slot_names() == ["NiCd", "LiPo"]

    with qtbot.waitSignal(panel.operationFinished, timeout=WAIT_MS) as restored:
        panel.restore(backup)
    assert restored.args[:2] == ["restore", True] and "verified" in restored.args[2]
    assert panel.slot_names() == ["NiMh-dV", "LiPo"]

    broken = tmp_path / "broken.bin"
    broken.write_bytes(b"\x05\x01\x02\x03\x04")
    with qtbot.waitSignal(panel.operationFinished, timeout=WAIT_MS) as refused:
        panel.restore(broken)
    assert refused.args[:2] == ["restore", False] and "Nothing was written" in refused.args[2]
    assert panel.slot_names() == ["NiMh-dV", "LiPo"]

    # a folder and a device: the read said why (a device was read until the memory ran out)
    (tmp_path / "folder.bin").mkdir()
    for path, said in ((tmp_path / "folder.bin", "is a folder, not a file"), ("/dev/zero", "a device, not a file")):
        with qtbot.waitSignal(panel.operationFinished, timeout=WAIT_MS) as refused:
            panel.restore(path)
        assert refused.args[:2] == ["restore", False]
        assert refused.args[2].startswith("Nothing was written: ") and said in refused.args[2]
        assert panel.slot_names() == ["NiMh-dV", "LiPo"]


def test_port_scans_run_off_the_gui_thread(qtbot, tmp_path, editor):
    from zuml_studio.ui.device import DevicePanel

    gui = threading.current_thread()
    seen = []
    release = threading.Event()                # the scan lasts until the test lets it end

    def slow_lister():
        seen.append(threading.current_thread() is gui)
        release.wait(WAIT_MS / 1000)
        return [PortInfo("/dev/ttyUSB7", "CP2102 USB to UART", "", 0x10C4, 0xEA60)]

    panel = DevicePanel(editor, tmp_path, port_lister=slow_lister)
    qtbot.addWidget(panel)
    try:
        panel.show()                               # the first scan starts when the panel shows
        assert until(lambda: seen) and not release.is_set()    # show() returned with the scan still going
        with qtbot.waitSignal(panel.ports.portsScanned, timeout=WAIT_MS):
            release.set()
        assert seen and not any(seen)
        combo = panel.ports.combo
        assert combo.itemText(0) == "Virtual charger (built-in)" and combo.currentIndex() == 0
        assert combo.itemText(1) == "Simulated iMAX B6 (ZUML firmware)"
        assert combo.itemText(2) == "iMAX B6 (ZUML) through a USBasp" and combo.itemData(2) == "isp:usbasp"
        assert combo.itemData(3) == "/dev/ttyUSB7" and "CP2102" in combo.itemText(3)
        combo.setCurrentIndex(3)
        assert panel.ports.target() == "/dev/ttyUSB7"
        assert not panel.virtual_box.isVisible()
        panel.ports.url.setText("socket://127.0.0.1:7777")
        assert panel.ports.target() == "socket://127.0.0.1:7777"
    finally:
        panel.shutdown()


def test_a_port_another_program_holds_is_busy(qtbot, make_panel, make_charger):
    device, port = make_charger()
    holder = ChargerClient(port)                 # another program has the port (exclusive lock)
    try:
        panel = make_panel()
        with qtbot.waitSignal(panel.connectedChanged, timeout=WAIT_MS) as blocker:
            panel.connect_to(port)
        assert blocker.args == [False]
        assert panel.message_text() == (f"Cannot connect: {port}: the port is busy: another program (a serial "
                                        "monitor, another ZUML Studio?) has it open; close it and try again")
    finally:
        holder.close()
    connect(qtbot, panel, port)                  # free again: it connects


def test_permission_denied_says_how_to_get_the_port(qtbot, make_panel, monkeypatch):
    import serial

    def refuse(url, *args, **kw):                # what pyserial raises for a port without rw rights
        raise serial.SerialException(13, f"could not open port {url}: [Errno 13] Permission denied: '{url}'")

    monkeypatch.setattr(serial, "serial_for_url", refuse)
    panel = make_panel()
    with qtbot.waitSignal(panel.connectedChanged, timeout=WAIT_MS) as blocker:
        panel.connect_to("/dev/ttyUSB0")
    assert blocker.args == [False]
    text = panel.message_text()
    assert text.startswith("Cannot connect: /dev/ttyUSB0: permission denied; ")
    if sys.platform.startswith("linux"):
        for advice in ("sudo usermod -aG dialout $USER", "uucp on Arch", "60-zuml-studio-serial.rules", "brltty"):
            assert advice in text


def test_every_error_reads_as_a_sentence():
    from zuml_studio.device.errors import (CommitUncertain, DeviceError, DeviceTimeout, Disconnected,
                                           ImageTooLarge, InvalidImage, VerifyFailed)
    from zuml_studio.lang.eeprom import ImageError
    from zuml_studio.ui.device.connection import describe_error

    timeout = DeviceTimeout("/dev/ttyUSB0: no answer to WRITE_STAGE after 4 tries (0.11 s each)")
    assert describe_error(timeout, "flash") == (
        "The charger stopped answering while flashing: nothing was written, the charger keeps its previous "
        "image. (/dev/ttyUSB0: no answer to WRITE_STAGE after 4 tries (0.11 s each))")
    assert describe_error(timeout, "stop").startswith("The charger does not answer: /dev/ttyUSB0")
    assert describe_error(Disconnected("x: closed"), "restore").startswith("The connection was lost while restoring")
    assert describe_error(CommitUncertain("x: lost"), "flash").startswith(
        "The connection was lost just as the charger committed the new image: it holds either the new image or "
        "its previous one")
    assert describe_error(ImageTooLarge(1090, 1024), "restore") == (
        "The image needs 1090 bytes; the charger has 1024. Nothing was written.")
    assert describe_error(VerifyFailed("verify failed: byte 3 reads 0x00, wrote 0x01"), "flash").startswith(
        "The write did not verify: verify failed: byte 3")
    assert describe_error(InvalidImage("slot 0 at offset 0 does not decode"), "restore") == (
        "Nothing was written: slot 0 at offset 0 does not decode")
    assert "restore a backup" in describe_error(ImageError(0, "record 0 says it is 3 bytes long"), "flash")
    refused = DeviceError(10, "the battery's capacity is needed: the macro takes it at start")
    assert describe_error(refused, "start") == ("The charger refused to start:\n"
                                                "• the battery's capacity is needed: the macro takes it at start")
    assert describe_error(RuntimeError("boom"), "stop") == "Internal error: RuntimeError: boom"


def _set_passport(device, **fields):
    from zuml_studio.protocol import passport as pp
    old = device.chip.image
    new = pp.Passport.from_bytes(old)
    for key, value in fields.items():
        new = new.with_field(key, value)
    for req in pp.page_writes(old, new.to_bytes()):
        assert pp.answer_error(device.chip.answer(req)) is None


def test_start_warns_about_battery_errors_and_an_unreliable_minus_dv_and_refuses_critical_errors(qtbot, make_panel):
    """Issue 11.4/11.5: ERR and an entered current too low for -dV warn; CRIT refuses, naming it."""
    panel = make_panel()
    connect(qtbot, panel)
    device = panel.connection.virtual_device
    _set_passport(device, err=2)
    with qtbot.waitSignal(panel.flashFinished, timeout=WAIT_MS):
        panel.flash()
    panel.set_start_params(current_a=0.4, capacity_mah=2000, series=4, sensor=False)
    with qtbot.waitSignal(panel.startFinished, timeout=WAIT_MS) as started:
        panel.start()
    ok, text = started.args
    assert ok, text
    assert "\n⚠ the battery reports 2 error(s) (ERR=2)" in text
    assert "\n⚠ charge phase 1: 0.40 A is 0.20C of 2000 mAh; NiMh shows no reliable -dV below 0.3C" in text
    panel.stop()
    qtbot.waitUntil(lambda: device.state != "running", timeout=WAIT_MS)
    _set_passport(device, crit=1)
    with qtbot.waitSignal(panel.startFinished, timeout=WAIT_MS) as refused:
        panel.start()
    ok, text = refused.args
    assert not ok and "• the battery reports 1 critical error(s) (CRIT=1): it is not fit for use" in text
