"""Before Qt starts on X11: find the system libraries Qt's xcb platform plugin needs and this system
lacks, and say which packages to install.

Without them Qt aborts with a misleading "xcb-cursor0 is needed" whatever is missing (a minimal
Debian or Ubuntu lacks libxcb-icccm4 and libxcb-keysyms1, say). The plugin's dependencies are
what ``ldd`` reports "not found"; Debian's package names follow the library's soname. Qt-free:
it runs before any Qt import.
"""
from __future__ import annotations

import os
import re
import shutil
import subprocess
import sys
from importlib.util import find_spec
from pathlib import Path

from ...i18n import _

# Where the soname rule (libFOO.so.N -> libfooN, libfoo-x.so.N -> libfoo-x-N) gives the wrong name.
DEBIAN_PACKAGE = {"libglib-2.0.so.0": "libglib2.0-0", "libgthread-2.0.so.0": "libglib2.0-0",
                  "libgobject-2.0.so.0": "libglib2.0-0"}


def wants_xcb(environ: dict[str, str] = os.environ, platform: str = sys.platform) -> bool:
    """Whether Qt is about to use its xcb plugin: Linux, an X display, no other platform asked for."""
    if not platform.startswith("linux") or not environ.get("DISPLAY"):
        return False
    asked = environ.get("QT_QPA_PLATFORM", "")
    if asked:
        return asked.split(";")[0].startswith("xcb")
    return not environ.get("WAYLAND_DISPLAY")     # Qt prefers its Wayland plugin in a Wayland session


def lacks_display(environ: dict[str, str] = os.environ, platform: str = sys.platform) -> bool:
    """Whether Qt is about to look for a desktop on Linux and there is none (ssh, a console): it
    would abort saying "xcb-cursor0 is needed" and that reinstalling may help, both wrong."""
    if not platform.startswith("linux") or environ.get("DISPLAY") or environ.get("WAYLAND_DISPLAY"):
        return False
    return environ.get("QT_QPA_PLATFORM", "").split(";")[0] in ("", "xcb", "wayland")


def no_display_advice() -> str:
    return _("no desktop to open the window on (neither DISPLAY nor WAYLAND_DISPLAY is set): start it in a "
             "desktop session, or over ssh with `ssh -X`. Without one, `zuml-studio FILE --screenshot OUT.png` "
             "renders the window to a file and the `zuml` command line does the rest.") + "\n"


def missing_libraries(ldd_output: str) -> list[str]:
    """The sonames ``ldd`` reports "not found", in its order, without repeats."""
    found = re.findall(r"^\s*(\S+) => not found", ldd_output, flags=re.M)
    return list(dict.fromkeys(found))


def debian_package(soname: str) -> str:
    """The Debian/Ubuntu package that ships a library, by Debian's library-package naming rule."""
    if soname in DEBIAN_PACKAGE:
        return DEBIAN_PACKAGE[soname]
    m = re.fullmatch(r"(lib.+)\.so\.(\d+)(?:\..*)?", soname)
    if not m:
        return soname
    name, version = m.group(1).lower(), m.group(2)
    return f"{name}-{version}" if name[-1].isdigit() else f"{name}{version}"


def xcb_plugin() -> Path | None:
    """PySide6's libqxcb.so, found without importing PySide6 (importing it is fine, but not needed)."""
    spec = find_spec("PySide6")
    if spec is None or not spec.submodule_search_locations:
        return None
    plugin = Path(next(iter(spec.submodule_search_locations))) / "Qt" / "plugins" / "platforms" / "libqxcb.so"
    return plugin if plugin.is_file() else None


def advice(missing: list[str], has_apt: bool) -> str:
    """What to print for the missing libraries."""
    text = _("Qt's X11 platform plugin needs libraries this system lacks: {libraries}.").format(
        libraries=", ".join(missing)) + "\n"
    if has_apt:
        packages = " ".join(dict.fromkeys(debian_package(s) for s in missing))
        text += _("Install them with:") + f"\n  sudo apt install {packages}\n"
    else:
        text += _("Install the packages that provide them with your distribution's package manager.") + "\n"
    return text + _("(Without them Qt stops with \"xcb-cursor0 is needed\", whichever library is missing.)") + "\n"


def lacking() -> str:
    """The advice for the xcb plugin on this system, or '' when nothing is missing or it cannot be told."""
    plugin, ldd = xcb_plugin(), shutil.which("ldd")
    if plugin is None or ldd is None:
        return ""
    try:
        out = subprocess.run([ldd, str(plugin)], capture_output=True, text=True, timeout=10).stdout
    except (OSError, subprocess.SubprocessError):
        return ""
    missing = missing_libraries(out)
    return advice(missing, shutil.which("apt-get") is not None) if missing else ""


def check() -> str:
    """What stops Qt from starting here, said plainly: no display, or `lacking()` when Qt is about
    to start on X11; '' when nothing does."""
    if lacks_display():
        return no_display_advice()
    return lacking() if wants_xcb() else ""


if __name__ == "__main__":
    # packaging/pyinstaller/build.sh: a bundle frozen here would lack these libraries too.
    text = lacking()
    sys.stdout.write(text)
    sys.exit(1 if text else 0)
