"""What every subcommand shares: reading files with precise errors, one-line failures."""
from __future__ import annotations

import sys
from pathlib import Path

from ..file_errors import FileReadError, read_file_bytes


class CliError(Exception):
    """A failure shown as one line on stderr, with a non-zero exit."""

    def __init__(self, message: str, code: int = 2):
        super().__init__(message)
        self.code = code


def read_bytes(path: str) -> bytes:
    try:
        return read_file_bytes(path)
    except FileReadError as exc:
        raise CliError(str(exc)) from None


def read_text(path: str) -> str:
    data = read_bytes(path)
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        raise CliError(f"{path}: not UTF-8 text (byte 0x{data[exc.start]:02x} at offset {exc.start})") from None


def write_bytes(path: str, data: bytes) -> None:
    try:
        Path(path).write_bytes(data)
    except OSError as exc:
        raise CliError(f"{path}: cannot write: {exc.strerror or exc}") from None


def refuse_unsafe(problems: list[str], force: bool, what: str) -> None:
    """Print the safety check's problems; refuse (exit 1) unless the user forced it."""
    if not problems:
        return
    for line in problems:
        sys.stderr.write(f"  {line}\n")
    if not force:
        raise CliError(f"{what}: refused, {len(problems)} safety problem(s) above "
                       "(--force-unsafe overrides)", 1)
    sys.stderr.write(f"zuml: warning: {what}: --force-unsafe: going ahead despite the problem(s) above\n")


def add_force_unsafe(p) -> None:
    p.add_argument("--force-unsafe", action="store_true",
                   help="write (or start) even what the safety check refuses (chemistry limits, passport)")


def out(text: str = "") -> None:
    sys.stdout.write(text + "\n")


def check_start_options(args, capacity_max: float = 65534.0, amps_max: float = 327.0) -> None:
    """The start values every run command takes (--cycles, --series, --capacity, --current, --voltage)."""
    for name in ("cycles", "series"):
        value = getattr(args, name, None)
        if value is not None and not 1 <= value <= 255:
            raise CliError(f"--{name} must be 1 to 255")
    limits = {"capacity": capacity_max, "current": amps_max, "voltage": amps_max}
    for name, top in limits.items():
        value = getattr(args, name, None)
        if value is not None and not 0 < value <= top:
            raise CliError(f"--{name} must be above 0 and at most {top:g}")
