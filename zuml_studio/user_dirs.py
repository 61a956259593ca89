"""The user's own folders, never the package's (an installed package may be read-only): the
configuration (settings, crash recovery, named batteries) and the cache (what can be rebuilt
at any time: the analysed grammar; nowhere if it cannot be written, a cache is an
optimisation, never a reason to fail). One rule for both: an override variable, else the
XDG variable, else its home default, else on Windows the per-user application folder."""
from __future__ import annotations

import os
from pathlib import Path


def _user_dir(override: str, xdg: str, home_default: str, windows: str) -> Path:
    if os.environ.get(override):
        return Path(os.environ[override])
    base = os.environ.get(xdg) or (Path.home() / home_default)
    if os.name == "nt":
        base = os.environ.get(windows) or base
    return Path(base) / "zuml-studio"


def config_dir() -> Path:
    """Where settings, recovery files and named batteries live (ZUML_STUDIO_CONFIG_DIR overrides it)."""
    return _user_dir("ZUML_STUDIO_CONFIG_DIR", "XDG_CONFIG_HOME", ".config", "APPDATA")


def data_dir() -> Path:
    """Where the user's own records live (the pack logbook): ZUML_STUDIO_DATA_DIR, else the platform's
    per-user data directory; unlike the cache it cannot be rebuilt."""
    return _user_dir("ZUML_STUDIO_DATA_DIR", "XDG_DATA_HOME", ".local/share", "APPDATA")


def cache_dir() -> Path:
    """ZUML_STUDIO_CACHE_DIR, else the platform's per-user cache directory."""
    return _user_dir("ZUML_STUDIO_CACHE_DIR", "XDG_CACHE_HOME", ".cache", "LOCALAPPDATA")


def cache_file(name: str) -> str | None:
    """A path for ``name`` in the cache directory, None if the directory cannot be written."""
    try:
        folder = cache_dir()
        folder.mkdir(parents=True, exist_ok=True)
    except (OSError, RuntimeError):         # RuntimeError: no home directory to be found
        return None
    return str(folder / name) if os.access(folder, os.W_OK) else None
