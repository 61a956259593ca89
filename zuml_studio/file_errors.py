"""Reading a user's file with one precise sentence for each way it can fail, shared by the
command line and the editor's Open."""
from __future__ import annotations

from pathlib import Path


class FileReadError(Exception):
    pass


def read_file_bytes(path: str | Path) -> bytes:
    try:
        return Path(path).read_bytes()
    except FileNotFoundError:
        raise FileReadError(f"{path}: no such file") from None
    except IsADirectoryError:
        raise FileReadError(f"{path}: is a folder, not a file") from None
    except PermissionError:
        raise FileReadError(f"{path}: permission denied") from None
    except OSError as exc:
        raise FileReadError(f"{path}: {exc.strerror or exc}") from None
