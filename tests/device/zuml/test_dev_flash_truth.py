"""The flash result is the truth (issue 12, point 4): a link lost after a confirmed COMMIT is
said as such and settled by a read-back; a read that keeps failing shrinks and backs off; a
charger that dies is not said to be "another program". The 200-flash BER figure is measured
by benchmarks/bench_flash_faults.py."""
import socket
import threading

import pytest

from helpers import compiled, needs_pty
from zuml_studio.device.zuml import client as client_module
from zuml_studio.device.zuml.client import ChargerClient
from zuml_studio.device.errors import CommitUnverified, DeviceTimeout, Disconnected
from zuml_studio.virtual.virtual_charger import Faults
from zuml_studio.lang.eeprom import pack

pytestmark = needs_pty


def lose_link_during_verify(client, monkeypatch):
    """The first READ_EEPROM after a confirmed COMMIT finds the link gone."""
    real = client.request
    state = {"committed": False}

    def request(name, payload, **kw):
        if name == "READ_EEPROM" and state["committed"]:
            raise Disconnected("the connection was lost")
        answer = real(name, payload, **kw)
        state["committed"] = state["committed"] or name == "COMMIT"
        return answer
    monkeypatch.setattr(client, "request", request)


def test_link_lost_after_a_confirmed_commit_says_the_new_image_is_there(any_client, monkeypatch):
    charger, client = any_client
    size = client.info.eeprom_size
    new = pack([compiled("LiPo")], size)
    before = client.read_image()
    lose_link_during_verify(client, monkeypatch)
    with pytest.raises(CommitUnverified, match="confirmed the new image") as lost:
        client.write_image(new)
    assert lost.value.holds == "new"
    monkeypatch.undo()
    assert lost.value.settle(client.read_image()) == "new"
    assert lost.value.settle(before) == "previous" and lost.value.settle(b"\0" * size) == "other"


def test_a_read_that_keeps_failing_shrinks_and_backs_off(any_client, monkeypatch):
    charger, client = any_client
    client.write_image(pack([compiled("LiPo"), compiled("NiMh-dV")], client.info.eeprom_size))
    image = client.read_image()
    real = client.read_eeprom
    asked, pauses = [], []

    def read_eeprom(offset, length):
        asked.append(length)
        if length > 40:                          # long answers never get through this "line"
            raise DeviceTimeout("no answer to READ_EEPROM")
        return real(offset, length)
    monkeypatch.setattr(client, "read_eeprom", read_eeprom)
    monkeypatch.setattr(client_module, "_pause", pauses.append)
    assert client.read_image() == image
    assert asked[:4] == [240, 120, 60, 30]                    # halved on each failure
    assert pauses[:2] == [0.02, 0.04]                         # waiting longer each time


def test_a_piece_that_fails_every_time_ends_in_a_timeout(charger, monkeypatch):
    device, _, client = charger

    def read_eeprom(offset, length):
        raise DeviceTimeout("no answer to READ_EEPROM")
    monkeypatch.setattr(client, "read_eeprom", read_eeprom)
    monkeypatch.setattr(client_module, "_pause", lambda s: None)
    with pytest.raises(DeviceTimeout):
        client.read_image()


def test_a_charger_that_closes_the_line_is_not_called_another_program(make_charger):
    device, port = make_charger(faults=Faults(disconnect_after=3))
    with pytest.raises(Disconnected) as lost:
        ChargerClient(port)
    assert "another program" not in str(lost.value) and "stopped" in str(lost.value)


def test_a_tcp_charger_that_closes_at_once_may_serve_another_program():
    server = socket.socket()
    server.bind(("127.0.0.1", 0))
    server.listen(1)

    def close_at_once():
        conn, _ = server.accept()
        conn.close()
    thread = threading.Thread(target=close_at_once, daemon=True)
    thread.start()
    try:
        with pytest.raises(Disconnected, match="serves another program already"):
            ChargerClient(f"socket://127.0.0.1:{server.getsockname()[1]}")
    finally:
        thread.join(5)
        server.close()
