"""Device ▸ Serial Monitor: the raw bytes of a port (a pty this test owns), as text or hex, a
send line, and off while the Device panel's protocol has the port."""
import os
import tty

import pytest

from device_helpers import WAIT_MS, connect


@pytest.fixture
def pty_port():
    """A pty pair: the monitor opens the path, the test plays the device on the other end."""
    device, port = os.openpty()
    tty.setraw(port)
    yield device, os.ttyname(port)
    os.close(device)
    os.close(port)


def test_the_monitor_shows_what_comes_in_as_text_or_hex_and_sends_a_line(make_window, qtbot, pty_port):
    device, path = pty_port
    w = make_window()
    w.device_panel.ports.set_target(path)
    monitor = w.show_serial_monitor()
    assert path in monitor.where.text() and not monitor.send_button.isEnabled()
    assert monitor.open_port(), monitor.message.text()
    os.write(device, b"V=4.20\r\n\x01")
    qtbot.waitUntil(lambda: monitor.text() == "V=4.20\n\\x01", timeout=WAIT_MS)
    monitor.hex_mode.setChecked(True)
    assert monitor.text() == "56 3d 34 2e 32 30 0d 0a 01 "
    monitor.send_line.setText("55 aa")
    assert monitor.send()
    assert os.read(device, 16) == b"\x55\xaa"
    monitor.text_mode.setChecked(True)
    monitor.ending.setCurrentIndex(monitor.ending.findData("lf"))
    monitor.send_line.setText("PING")
    assert monitor.send() and os.read(device, 16) == b"PING\n"
    monitor.send_line.setText("zz")
    monitor.hex_mode.setChecked(True)
    assert not monitor.send() and "not hex bytes" in monitor.message.text()
    monitor.close()
    assert not monitor.is_open()


def test_the_monitor_is_off_while_the_device_panel_owns_the_port(make_window, qtbot):
    w = make_window()
    monitor = w.show_serial_monitor()
    assert not monitor.open_button.isEnabled()          # the virtual charger: no port to watch
    connect(qtbot, w.device_panel)
    assert not monitor.open_button.isEnabled() and not monitor.send_button.isEnabled()
    assert "Disconnect" in monitor.message.text()
    assert w.act_serial_monitor in w.menus["device"].actions()


def test_a_zuml_request_typed_by_hand_is_not_sent(make_window, qtbot, pty_port):
    """The one safety check guards every path to a charger: a hand-made START (or any request) from the
    monitor's send line would pass it by."""
    from zuml_studio.protocol.frames import encode_frame
    from zuml_studio.protocol.messages import START
    device, path = pty_port
    w = make_window()
    w.device_panel.ports.set_target(path)
    monitor = w.show_serial_monitor()
    assert monitor.open_port(), monitor.message.text()
    monitor.hex_mode.setChecked(True)
    monitor.ending.setCurrentIndex(monitor.ending.findData("none"))
    monitor.send_line.setText(encode_frame(START, 1, bytes(12)).hex(" "))
    assert not monitor.send() and "completes a ZUML request" in monitor.message.text()
    monitor.send_line.setText("55 aa")
    assert monitor.send() and os.read(device, 16) == b"\x55\xaa"
    monitor.close()


def test_a_request_split_over_sends_and_modes_is_refused_where_it_would_complete(make_window, qtbot, pty_port):
    """The charger's parser keeps a frame's first bytes until the rest comes: garbage, then a COMMIT's
    first bytes in hex, the rest typed as text escapes, is a COMMIT all the same. Nothing of the
    completing line reaches the port, while bytes that complete nothing still go."""
    from zuml_studio.protocol.frames import encode_frame
    from zuml_studio.protocol.messages import COMMIT, encode_request
    device, path = pty_port
    frame = encode_frame(COMMIT, 9, encode_request("COMMIT", token=1, crc=0xBEEF))
    w = make_window()
    w.device_panel.ports.set_target(path)
    monitor = w.show_serial_monitor()
    assert monitor.open_port(), monitor.message.text()
    monitor.ending.setCurrentIndex(monitor.ending.findData("none"))
    monitor.send_line.setText("hi\\xa5")
    assert monitor.send() and os.read(device, 16) == b"hi\xa5"
    monitor.hex_mode.setChecked(True)
    monitor.send_line.setText(frame[:3].hex(" "))
    assert monitor.send() and os.read(device, 16) == frame[:3]
    monitor.text_mode.setChecked(True)
    monitor.send_line.setText("".join(f"\\x{b:02x}" for b in frame[3:]))
    assert not monitor.send() and "COMMIT" in monitor.message.text()
    monitor.hex_mode.setChecked(True)
    monitor.send_line.setText(frame[3:].hex(" "))
    assert not monitor.send() and "COMMIT" in monitor.message.text()
    monitor.send_line.setText("00")
    assert monitor.send() and os.read(device, 16) == b"\x00"
    monitor.close()
