"""packaging/windows and packaging/macos are prepared (untested on those systems): the files they
name exist and their ids agree with the application's (issue 10)."""
import plistlib
import re

from helpers import ROOT
from zuml_studio import APP_ID

PACKAGING = ROOT / "packaging"


def test_the_inno_setup_script_installs_both_programs_in_english_and_russian():
    iss = (PACKAGING / "windows" / "zuml-studio.iss").read_text(encoding="utf-8")
    assert 'MessagesFile: "compiler:Languages\\Russian.isl"' in iss
    assert "{app}\\zuml-studio.exe" in iss
    for relative in re.findall(r"^(?:LicenseFile|SetupIconFile)=(.+)$", iss, flags=re.M):
        assert (PACKAGING / "windows" / relative.replace("\\", "/")).is_file(), relative
    # Every English custom message has its Russian one.
    english = set(re.findall(r"^english\.(\w+)=", iss, flags=re.M))
    assert english and english == set(re.findall(r"^russian\.(\w+)=", iss, flags=re.M))


def test_the_info_plist_carries_the_app_id_and_an_icon_that_exists():
    plist = plistlib.loads((PACKAGING / "macos" / "Info.plist").read_bytes())
    assert plist["CFBundleIdentifier"] == APP_ID
    assert (PACKAGING / "macos" / plist["CFBundleIconFile"]).read_bytes()[:4] == b"icns"
    assert "ru" in plist["CFBundleLocalizations"]


def test_the_windows_icon_is_an_ico():
    assert (PACKAGING / "windows" / "zuml-studio.ico").read_bytes()[:4] == b"\x00\x00\x01\x00"
