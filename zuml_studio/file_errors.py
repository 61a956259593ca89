"""Reading a user's file with one precise sentence for each way it can fail, shared by the
command line and the editor's Open."""
from __future__ import annotations

import stat
from pathlib import Path
from .errors import ZumlError, error_text
from .i18n import _


class FileReadError(ZumlError):
    def words(self, action: str = "") -> str:
        if action in ("flash", "restore"):
            return _("Nothing was written: {error}").format(error=error_text(self))
        return super().words(action)


def read_file_bytes(path: str | Path, pipes: bool = True) -> bytes:
    """The whole file. A device (/dev/zero, a serial port, a disk) is refused before it is opened:
    reading one never ends, or blocks, or eats the memory. A named pipe is read (a shell's
    ``<(...)`` and /dev/stdin are pipes), like any program reads one: until its writer closes it;
    with ``pipes=False`` it is refused as a device is (a charger's log is a file: a pipe found in a
    folder of logs would hang the import)."""
    try:
        mode = Path(path).stat().st_mode
        if stat.S_ISCHR(mode) or stat.S_ISBLK(mode) or stat.S_ISSOCK(mode):
            raise FileReadError(_("{path}: a device, not a file").format(path=path))
        if not pipes and stat.S_ISFIFO(mode):
            raise FileReadError(_("{path}: a named pipe, not a log file").format(path=path))
        return Path(path).read_bytes()
    except FileNotFoundError:
        raise FileReadError(_("{path}: no such file").format(path=path)) from None
    except IsADirectoryError:
        raise FileReadError(_("{path}: is a folder, not a file").format(path=path)) from None
    except PermissionError:
        raise FileReadError(_("{path}: permission denied").format(path=path)) from None
    except OSError as exc:
        raise FileReadError(f"{path}: {exc.strerror or exc}") from None
