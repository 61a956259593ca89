"""Reading a user's file with one precise sentence for each way it can fail, shared by the
command line and the editor's Open."""
from __future__ import annotations

from pathlib import Path
from .i18n import _


class FileReadError(Exception):
    pass


def read_file_bytes(path: str | Path) -> bytes:
    try:
        return Path(path).read_bytes()
    except FileNotFoundError:
        raise FileReadError(_("{path}: no such file").format(path=path)) from None
    except IsADirectoryError:
        raise FileReadError(_("{path}: is a folder, not a file").format(path=path)) from None
    except PermissionError:
        raise FileReadError(_("{path}: permission denied").format(path=path)) from None
    except OSError as exc:
        raise FileReadError(f"{path}: {exc.strerror or exc}") from None
