"""A refused or vanished serial port says what to do on this system (issue 10)."""
import sys

import pytest

from zuml_studio.device.links import port_access
from zuml_studio.device.errors import PermissionDenied

linux_only = pytest.mark.skipif(not sys.platform.startswith("linux"), reason="the advice is for Linux")


@linux_only
def test_a_refused_port_names_the_group_the_udev_rule_and_brltty():
    text = str(PermissionDenied("/dev/ttyUSB0"))
    assert text.startswith("/dev/ttyUSB0: permission denied; ")
    assert "sudo usermod -aG dialout $USER" in text and "uucp on Arch" in text
    assert "/etc/udev/rules.d/" in text and port_access.RULE_NAME in text
    assert "sudo apt remove brltty" in text


@linux_only
def test_the_group_is_the_one_that_owns_the_port(monkeypatch, tmp_path):
    import grp
    import os

    class Stat:
        st_gid = 987
    monkeypatch.setattr(os, "stat", lambda path: Stat())
    monkeypatch.setattr(grp, "getgrgid", lambda gid: type("G", (), {"gr_name": "uucp"})())
    assert "sudo usermod -aG uucp $USER" in port_access.refused_advice("/dev/ttyUSB0")


@linux_only
def test_a_frozen_bundle_points_at_its_own_copy_of_the_rule(monkeypatch, tmp_path):
    rule = tmp_path / "linux" / port_access.RULE_NAME
    rule.parent.mkdir()
    rule.write_text("# rule\n")
    monkeypatch.setattr(sys, "frozen", True, raising=False)
    monkeypatch.setattr(sys, "executable", str(tmp_path / "zuml"))
    assert f"sudo install -m 644 {rule} /etc/udev/rules.d/" in port_access.refused_advice("/dev/ttyUSB0")


@linux_only
def test_a_vanished_usb_port_mentions_brltty_only_where_brltty_is_installed(monkeypatch):
    monkeypatch.setattr(port_access, "_brltty_installed", lambda: True)
    assert "brltty" in port_access.vanished_hint("/dev/ttyUSB0")
    assert port_access.vanished_hint("/dev/ttyS0") == ""
    monkeypatch.setattr(port_access, "_brltty_installed", lambda: False)
    assert port_access.vanished_hint("/dev/ttyUSB0") == ""
