"""USB-HID chargers through a stand-in for the hidapi module: listing by exact ids, reading
pushed reports, polling, and a clear message without hidapi."""
import sys
import threading
import types

import pytest

from realdata_samples import ICHARGER_HID_REPORT, isdt_frames
from zuml_studio.streams import isdt_hid
from zuml_studio.device.errors import DeviceLinkError
from zuml_studio.device.links.hid_link import list_hid_chargers, parse_port
from zuml_studio.device.links.monitor_link import MonitorLink

DEVICES = [
    {"vendor_id": 0x0483, "product_id": 0x5751, "path": b"a", "product_string": "Junsi iCharger 4010Duo USB HID"},
    {"vendor_id": 0x0000, "product_id": 0x0001, "path": b"b", "product_string": ""},
    {"vendor_id": 0x28E9, "product_id": 0x028A, "path": b"c", "product_string": "ISDT"},
    {"vendor_id": 0x046D, "product_id": 0xC52B, "path": b"d", "product_string": "a mouse"},
    {"vendor_id": 0x0000, "product_id": 0x0002, "path": b"e", "product_string": "not SkyRC"},
]


def fake_hid(reports: dict, written: list):
    mod = types.ModuleType("hid")
    mod.enumerate = lambda vid=0, pid=0: list(DEVICES)

    class Device:
        def open_path(self, path):
            self.queue = list(reports.get(path, []))

        def read(self, n, timeout_ms):
            if self.queue:
                return list(self.queue.pop(0))
            threading.Event().wait(timeout_ms / 1000)
            return []

        def write(self, data):
            written.append(bytes(data))
            return len(data)

        def close(self):
            pass

    mod.device = Device
    return mod


def test_listing_matches_exact_ids(monkeypatch):
    monkeypatch.setitem(sys.modules, "hid", fake_hid({}, []))
    ports = list_hid_chargers()
    assert [p.device for p in ports] == ["hid:0483:5751", "hid:0000:0001", "hid:28e9:028a"]
    assert ports[0].label() == "hid:0483:5751 - Junsi iCharger 4010Duo USB HID (USB HID) [0483:5751]"
    assert ports[1].description == "SkyRC USB (B6 mini, B6AC v2, Q200) (USB HID)"


def test_without_hidapi_everything_else_runs(monkeypatch):
    monkeypatch.setitem(sys.modules, "hid", None)             # import hid -> ImportError
    assert list_hid_chargers() == []
    with pytest.raises(DeviceLinkError, match="need the hidapi package"):
        MonitorLink("hid:0483:5751")


def test_port_syntax():
    assert parse_port("hid:0483:5751:1") == (0x0483, 0x5751, 1)
    with pytest.raises(DeviceLinkError, match="hid:VVVV:PPPP"):
        parse_port("hid:zz")


def _collect(link, count):
    got, done = [], threading.Event()
    link._on_sample = lambda t: (got.append(t), len(got) >= count and done.set())
    link.start()
    assert done.wait(10)
    link.close()
    return got


def test_icharger_pushes_reports(monkeypatch):
    written = []
    monkeypatch.setitem(sys.modules, "hid", fake_hid({b"a": [ICHARGER_HID_REPORT[:44]] * 3}, written))
    link = MonitorLink("hid:0483:5751")                        # auto: the driver from the USB ids
    assert link.driver.name == "icharger-hid"
    got = _collect(link, 3)
    assert len(got) == 3 and got[0].voltage_v == 15.403 and written == []   # nothing to request


def test_isdt_is_polled(monkeypatch):
    written = []
    monkeypatch.setitem(sys.modules, "hid", fake_hid({b"c": [isdt_frames()[3]]}, written))
    link = MonitorLink("hid:28e9:028a", "isdt")
    (t,) = _collect(link, 1)
    assert t.time_s == 448.0
    assert written[0] == b"\x00" + isdt_hid.poll_request(0).ljust(64, b"\x00")


def test_a_serial_driver_on_a_hid_port_is_refused(monkeypatch):
    monkeypatch.setitem(sys.modules, "hid", fake_hid({}, []))
    with pytest.raises(DeviceLinkError, match="cheali is a serial charger"):
        MonitorLink("hid:0483:5751", "cheali")


def test_a_pulled_usb_cable_says_the_links_one_sentence(monkeypatch):
    """Issue 27: hidapi's "read error" became "the device went away: read error"; a USB charger
    that goes away is said as every other link says it."""
    from zuml_studio.device.links.hid_link import HidPort
    module = fake_hid({}, [])

    def unplugged(self, n, timeout_ms):
        raise OSError("read error")
    module.device.read = unplugged
    monkeypatch.setitem(sys.modules, "hid", module)
    link = HidPort("hid:0483:5751")
    with pytest.raises(DeviceLinkError) as lost:
        link.read(0.1)
    assert str(lost.value) == "hid:0483:5751: the charger closed the line: it stopped, or its cable was pulled"
