"""packaging/linux: the desktop file and AppStream data validate and agree with the application's id,
programs and file type, the icons have their sizes, the udev rule covers the chargers' chips, and install.sh
installs a bundle under a prefix and removes it again (issue 10)."""
import os
import re
import shutil
import struct
import subprocess
import tomllib
import xml.etree.ElementTree as ET

import pytest

from helpers import ROOT
from zuml_studio import APP_ID

LINUX = ROOT / "packaging" / "linux"
DESKTOP = LINUX / f"{APP_ID}.desktop"
METAINFO = LINUX / f"{APP_ID}.metainfo.xml"
RULES = LINUX / "60-zuml-studio-serial.rules"
CHIPS = {("1a86", "7523"), ("1a86", "55d4"), ("10c4", "ea60"), ("0403", "6001"), ("0403", "6015"),
         ("067b", "2303")}


def _tool(name: str) -> str:
    path = shutil.which(name)
    if path is None:
        pytest.skip(f"{name} is not installed (Debian/Ubuntu: apt-get install desktop-file-utils appstream)")
    return path


def _desktop_entry(path) -> dict:
    entry = {}
    for line in path.read_text(encoding="utf-8").splitlines():
        if "=" in line and not line.startswith("#"):
            key, value = line.split("=", 1)
            entry[key] = value
    return entry


def test_desktop_file_validates():
    proc = subprocess.run([_tool("desktop-file-validate"), str(DESKTOP)], capture_output=True, text=True)
    assert proc.returncode == 0 and not proc.stdout.strip(), proc.stdout + proc.stderr


def test_metainfo_validates():
    proc = subprocess.run([_tool("appstreamcli"), "validate", "--no-net", str(METAINFO)], capture_output=True,
                          text=True)
    assert proc.returncode == 0, proc.stdout + proc.stderr


def test_ids_and_programs_agree():
    entry = _desktop_entry(DESKTOP)
    meta = ET.parse(METAINFO).getroot()
    scripts = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]["scripts"]
    spec = (ROOT / "packaging" / "pyinstaller" / "zuml-studio.spec").read_text()
    assert meta.findtext("id") == APP_ID and entry["Icon"] == APP_ID
    assert meta.find("launchable[@type='desktop-id']").text == DESKTOP.name
    program = entry["Exec"].split()[0]
    assert program == entry["TryExec"] == "zuml-studio"
    assert {b.text for b in meta.iter("binary")} == set(scripts) == {"zuml-studio", "zuml"}
    assert set(re.findall(r'name="(zuml[-\w]*)"', spec)) >= set(scripts)
    assert APP_ID in (ROOT / "packaging" / "linux" / "install.sh").read_text()


def test_the_zuml_file_type_is_one_type_everywhere():
    mime = ET.parse(LINUX / f"{APP_ID}.mime.xml").getroot()
    ns = {"m": "http://www.freedesktop.org/standards/shared-mime-info"}
    [kind] = mime.findall("m:mime-type", ns)
    assert kind.find("m:glob", ns).get("pattern") == "*.zuml"
    assert _desktop_entry(DESKTOP)["MimeType"] == kind.get("type") + ";"
    assert [m.text for m in ET.parse(METAINFO).getroot().iter("mediatype")] == [kind.get("type")]


def test_every_udev_line_tags_one_of_the_chargers_chips_for_the_seat_user():
    lines = [line for line in RULES.read_text().splitlines() if line.strip() and not line.startswith("#")]
    found = set()
    for line in lines:
        m = re.fullmatch(r'SUBSYSTEM=="tty", ATTRS\{idVendor\}=="([0-9a-f]{4})", '
                         r'ATTRS\{idProduct\}=="([0-9a-f]{4})", TAG\+="uaccess"', line)
        assert m, line
        found.add(m.groups())
    assert found == CHIPS and len(lines) == len(CHIPS)


@pytest.mark.parametrize("size", [48, 128, 256])
def test_icon_png_has_its_size(size):
    head = (LINUX / "icons" / f"{size}.png").read_bytes()[:24]
    assert head[:8] == b"\x89PNG\r\n\x1a\n" and struct.unpack(">II", head[16:24]) == (size, size)


def _fake_bundle(tmp_path):
    bundle = tmp_path / "zuml-studio-0.1.0-linux-x86_64"
    for program in ("zuml-studio", "zuml"):
        (bundle / program).parent.mkdir(parents=True, exist_ok=True)
        (bundle / program).write_text(f"#!/bin/sh\necho {program} \"$@\"\n")
        (bundle / program).chmod(0o755)
    data = bundle / "_internal" / "zuml_studio" / "resources"
    data.mkdir(parents=True)
    shutil.copy2(ROOT / "resources" / "icon.svg", data / "icon.svg")
    shutil.copytree(LINUX, bundle / "linux")
    return bundle


def test_install_sh_installs_a_bundle_under_the_prefix_and_uninstalls_it(tmp_path):
    bundle = _fake_bundle(tmp_path)
    prefix = tmp_path / "home" / ".local"
    env = dict(os.environ, PREFIX=str(prefix), PATH="/usr/bin:/bin")
    proc = subprocess.run(["bash", str(bundle / "linux" / "install.sh")], env=env, capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    assert "sudo install -m 644" in proc.stdout and "/etc/udev/rules.d/" in proc.stdout
    lib = prefix / "lib" / "zuml-studio"
    linked = subprocess.run([str(prefix / "bin" / "zuml"), "check"], capture_output=True, text=True)
    assert linked.stdout == "zuml check\n"
    desktop = prefix / "share" / "applications" / f"{APP_ID}.desktop"
    entry = _desktop_entry(desktop)
    assert entry["Exec"] == f"{lib}/zuml-studio %f" and entry["TryExec"] == f"{lib}/zuml-studio"
    assert (prefix / "share" / "metainfo" / METAINFO.name).is_file()
    assert (prefix / "share" / "mime" / "packages" / f"{APP_ID}.xml").is_file()
    assert (prefix / "share" / "icons" / "hicolor" / "scalable" / "apps" / f"{APP_ID}.svg").is_file()
    for size in (48, 128, 256):
        assert (prefix / "share" / "icons" / "hicolor" / f"{size}x{size}" / "apps" / f"{APP_ID}.png").is_file()
    if shutil.which("desktop-file-validate"):
        assert subprocess.run(["desktop-file-validate", str(desktop)]).returncode == 0

    proc = subprocess.run(["bash", str(bundle / "linux" / "install.sh"), "--uninstall"], env=env,
                          capture_output=True, text=True)
    assert proc.returncode == 0, proc.stderr
    assert not lib.exists() and not desktop.exists() and not (prefix / "bin" / "zuml").exists()
    assert not (prefix / "share" / "mime" / "packages" / f"{APP_ID}.xml").exists()


def test_install_sh_refuses_a_folder_that_is_not_a_bundle(tmp_path):
    env = dict(os.environ, PREFIX=str(tmp_path / "prefix"))
    proc = subprocess.run(["bash", str(LINUX / "install.sh"), str(tmp_path)], env=env, capture_output=True, text=True)
    assert proc.returncode == 2 and "is not a ZUML Studio bundle" in proc.stderr
    assert not (tmp_path / "prefix").exists()
