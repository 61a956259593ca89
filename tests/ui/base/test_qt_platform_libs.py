"""Missing X11 libraries are named, with the apt command that installs them, before Qt starts."""
import pytest

from zuml_studio.ui import app
from zuml_studio.ui.base import qt_platform_libs as q

# ldd on PySide6 6.11's libqxcb.so on a minimal Debian 12 (this machine when the test was written).
LDD = """\
\tlinux-vdso.so.1 (0x00007ffd5a1f2000)
\tlibQt6XcbQpa.so.6 => /venv/PySide6/Qt/plugins/platforms/../../lib/libQt6XcbQpa.so.6 (0x00007f0c)
\tlibxcb-icccm.so.4 => not found
\tlibxcb-keysyms.so.1 => not found
\tlibxcb-cursor.so.0 => /lib/x86_64-linux-gnu/libxcb-cursor.so.0 (0x00007f0c)
\tlibxcb-icccm.so.4 => not found
"""


def test_the_missing_libraries_are_read_from_ldd():
    assert q.missing_libraries(LDD) == ["libxcb-icccm.so.4", "libxcb-keysyms.so.1"]
    assert q.missing_libraries("\tlibc.so.6 => /lib/libc.so.6 (0x1)\n") == []


@pytest.mark.parametrize("soname, package", [
    ("libxcb-icccm.so.4", "libxcb-icccm4"), ("libxcb-keysyms.so.1", "libxcb-keysyms1"),
    ("libxcb-cursor.so.0", "libxcb-cursor0"), ("libxkbcommon-x11.so.0", "libxkbcommon-x11-0"),
    ("libX11-xcb.so.1", "libx11-xcb1"), ("libEGL.so.1", "libegl1"), ("libdbus-1.so.3", "libdbus-1-3"),
    ("libglib-2.0.so.0", "libglib2.0-0"), ("libfontconfig.so.1.12.0", "libfontconfig1"),
])
def test_debian_package_names(soname, package):
    assert q.debian_package(soname) == package


def test_one_apt_command_installs_everything_missing():
    text = q.advice(["libxcb-icccm.so.4", "libxcb-keysyms.so.1"], has_apt=True)
    assert "\n  sudo apt install libxcb-icccm4 libxcb-keysyms1\n" in text
    assert "apt" not in q.advice(["libxcb-icccm.so.4"], has_apt=False)


@pytest.mark.parametrize("env, platform, expected", [
    ({"DISPLAY": ":0"}, "linux", True),
    ({}, "linux", False),
    ({"DISPLAY": ":0", "QT_QPA_PLATFORM": "offscreen"}, "linux", False),
    ({"DISPLAY": ":0", "WAYLAND_DISPLAY": "wayland-0"}, "linux", False),
    ({"DISPLAY": ":0", "WAYLAND_DISPLAY": "wayland-0", "QT_QPA_PLATFORM": "xcb"}, "linux", True),
    ({"DISPLAY": ":0"}, "darwin", False),
])
def test_only_an_x11_start_is_checked(env, platform, expected):
    assert q.wants_xcb(env, platform) is expected


def test_offscreen_needs_no_check(monkeypatch):
    monkeypatch.setenv("QT_QPA_PLATFORM", "offscreen")
    assert q.check() == ""


def test_the_app_stops_with_the_advice_instead_of_letting_qt_abort(monkeypatch, capsys):
    monkeypatch.setattr(q, "check", lambda: q.advice(["libxcb-icccm.so.4"], has_apt=True))
    assert app.main([]) == 1
    assert "sudo apt install libxcb-icccm4" in capsys.readouterr().err


@pytest.mark.parametrize("env, platform, expected", [
    ({}, "linux", True),
    ({"QT_QPA_PLATFORM": "xcb"}, "linux", True),
    ({"DISPLAY": ":0"}, "linux", False),
    ({"WAYLAND_DISPLAY": "wayland-0"}, "linux", False),
    ({"QT_QPA_PLATFORM": "offscreen"}, "linux", False),
    ({}, "darwin", False),
])
def test_a_linux_start_without_a_desktop_is_told(env, platform, expected):
    assert q.lacks_display(env, platform) is expected


def test_without_a_desktop_the_app_says_so_instead_of_letting_qt_abort(monkeypatch, capsys):
    for name in ("DISPLAY", "WAYLAND_DISPLAY", "QT_QPA_PLATFORM"):
        monkeypatch.delenv(name, raising=False)
    assert app.main([]) == 1
    err = capsys.readouterr().err
    assert "neither DISPLAY nor WAYLAND_DISPLAY is set" in err and "--screenshot" in err and "xcb-cursor0" not in err
