"""The run-time data shipped inside the package: chemistry and charger parameters, the wizard's
templates, the standard macros and the application's icon. This module is the one place that knows
where they live.

In the source tree they are the top-level folders ``resources/`` and ``macros/``; the build maps
them into the package as ``zuml_studio.resources`` and ``zuml_studio.macros`` (``setup.py``), and
an editable install maps them the same way, so no code path knows about the source tree.

They are read through ``importlib.resources`` so an installed wheel or a frozen bundle works
without the source tree. A file that is missing or unreadable raises `DataFileError` naming it:
the installation is broken, and no caller may carry on with a weaker answer (a safety lint
without the chemistry's limits would pass a dangerous macro).
"""
from __future__ import annotations

import tomllib
from importlib import resources
from pathlib import Path

from . import macros as MACROS, resources as RESOURCES  # noqa: N812 - `resources` is importlib's here
from .data_error import DataFileError
from .i18n import _
from .macro_file import EXTENSION

# MACROS and RESOURCES are the packages themselves, imported, not named: a frozen bundle (PyInstaller
# follows imports) then holds them as packages; named only, they came back as namespace packages.


def _missing(where: object, folder: bool = False) -> DataFileError:
    if folder:
        return DataFileError(_("data folder {where} is missing: the installation is incomplete, reinstall ZUML "
                               "Studio").format(where=where))
    return DataFileError(_("data file {where} is missing: the installation is incomplete, reinstall ZUML "
                           "Studio").format(where=where))


def location(relative: str) -> str:
    """Where a data file is (or should be), e.g. ``…/zuml_studio/resources/chemistries/LiPo.toml``."""
    return str(resources.files(RESOURCES).joinpath(*relative.split("/")))


def read_text(relative: str) -> str:
    """The text of a data file, ``relative`` to this package (``chemistries/LiPo.toml``)."""
    try:
        return resources.files(RESOURCES).joinpath(*relative.split("/")).read_text(encoding="utf-8")
    except FileNotFoundError:
        raise _missing(location(relative)) from None
    except (OSError, UnicodeDecodeError) as exc:
        raise DataFileError(_("data file {location} is unreadable ({exc}): reinstall ZUML Studio").format(
                location=location(relative), exc=exc)) from None


def read_toml(relative: str) -> dict:
    """A TOML data file, parsed."""
    try:
        return tomllib.loads(read_text(relative))
    except tomllib.TOMLDecodeError as exc:
        raise DataFileError(_("data file {location} is not valid TOML: {exc}").format(
                location=location(relative), exc=exc)) from None


def names(folder: str, suffix: str = ".toml") -> list[str]:
    """The stems of the data files in ``folder`` (``chargers`` -> ``['imax_b6']``), sorted."""
    entry = resources.files(RESOURCES).joinpath(folder)
    if not entry.is_dir():
        raise _missing(location(folder), folder=True)
    return sorted(f.name[: -len(suffix)] for f in entry.iterdir() if f.name.endswith(suffix))


def file_path(relative: str) -> Path:
    """A data file as a path on disk, for APIs that take a file name (Qt's QIcon)."""
    path = Path(location(relative))
    if not path.is_file():
        raise _missing(path)
    return path


def standard_macros_dir() -> Path:
    """The folder of the standard macros, a real directory (the editor opens them as files)."""
    folder = Path(str(resources.files(MACROS)))
    if not folder.is_dir():
        raise _missing(folder, folder=True)
    return folder


def standard_macros() -> list[Path]:
    """The standard macros, ordered by name regardless of case."""
    folder = standard_macros_dir()
    found = sorted(folder.glob(f"*{EXTENSION}"), key=lambda p: p.name.lower())
    if not found:
        raise DataFileError(_("data folder {folder} holds no macros: the installation is incomplete, reinstall "
                              "ZUML Studio").format(folder=folder))
    return found


def is_standard_macro(path: str | Path) -> bool:
    """True for a file inside the installation's standard macros (read-only by intent)."""
    return Path(path).resolve().parent == standard_macros_dir().resolve()
