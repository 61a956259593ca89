"""What to tell a user whose serial port is refused, or vanished, on this system.

On Linux a USB-serial port belongs to a group (dialout on Debian, Ubuntu and Fedora, uucp on Arch);
ZUML Studio's udev rule (packaging/linux/60-zuml-studio-serial.rules) hands the chargers' chips to
the logged-in user instead. On Ubuntu 22.04 and some later releases brltty, a braille display
driver, claims CH340 and CP210x chips, and the port disappears or is refused.
"""
from __future__ import annotations

import os
import shutil
import sys
from pathlib import Path

from ...i18n import N_, _

RULE_NAME = "60-zuml-studio-serial.rules"
BRLTTY_RULES = ("/usr/lib/udev/rules.d/85-brltty.rules", "/lib/udev/rules.d/85-brltty.rules")
BRLTTY = N_("On Ubuntu 22.04 and some later releases brltty (a braille display driver) takes CH340 and "
            "CP210x ports; without a braille display: sudo apt remove brltty, then replug the charger.")


def refused_advice(port: str) -> str:
    """The lines after "PORT: permission denied": how to get the right to open the port."""
    if not sys.platform.startswith("linux"):
        return _("check who may open it: ls -l {port}").format(port=port)
    group = _owning_group(port)
    rule = _bundled_rule()
    where = "" if rule else _(" (linux/{rule} in the release bundle, packaging/linux/ in the sources)").format(
        rule=RULE_NAME)
    return (_("to use the port, either\n"
              "  - join the group that owns it (dialout on Debian, Ubuntu and Fedora, uucp on Arch): "
              "sudo usermod -aG {group} $USER, then log out and in again, or\n"
              "  - install ZUML Studio's udev rule{where}, which gives chargers' USB-serial ports to the "
              "logged-in user: sudo install -m 644 {rule} /etc/udev/rules.d/ && "
              "sudo udevadm control --reload-rules && sudo udevadm trigger, then replug the charger.").format(
                  group=group, where=where, rule=rule or RULE_NAME) + "\n" + _(BRLTTY))


def vanished_hint(port: str) -> str:
    """A sentence to add when a USB-serial port does not exist and brltty may have taken it; else ''."""
    if sys.platform.startswith("linux") and port.startswith("/dev/ttyUSB") and _brltty_installed():
        return " " + _(BRLTTY)
    return ""


def _owning_group(port: str) -> str:
    try:
        import grp
        gid = os.stat(port).st_gid
        name = grp.getgrgid(gid).gr_name if gid != 0 else ""
    except (ImportError, OSError, KeyError):
        name = ""
    return name or "dialout"


def _bundled_rule() -> str | None:
    """The rule file in a frozen bundle's linux/ folder, when this is one."""
    if getattr(sys, "frozen", False):
        beside = Path(sys.executable).resolve().parent / "linux" / RULE_NAME
        if beside.is_file():
            return str(beside)
    return None


def _brltty_installed() -> bool:
    return shutil.which("brltty") is not None or any(os.path.exists(p) for p in BRLTTY_RULES)
