"""Where ZUML Studio keeps what it can rebuild at any time (the analysed grammar): the user's
cache directory, never the package's (an installed package may be read-only), and nowhere if
that cannot be written: a cache is an optimisation, never a reason to fail."""
from __future__ import annotations

import os
from pathlib import Path


def cache_dir() -> Path:
    """ZUML_STUDIO_CACHE_DIR, else the platform's per-user cache directory."""
    override = os.environ.get("ZUML_STUDIO_CACHE_DIR")
    if override:
        return Path(override)
    base = os.environ.get("XDG_CACHE_HOME") or (Path.home() / ".cache")
    if os.name == "nt":
        base = os.environ.get("LOCALAPPDATA") or base
    return Path(base) / "zuml-studio"


def cache_file(name: str) -> str | None:
    """A path for ``name`` in the cache directory, None if the directory cannot be written."""
    try:
        folder = cache_dir()
        folder.mkdir(parents=True, exist_ok=True)
    except (OSError, RuntimeError):         # RuntimeError: no home directory to be found
        return None
    return str(folder / name) if os.access(folder, os.W_OK) else None
