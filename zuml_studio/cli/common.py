"""What every subcommand shares: reading files with precise errors, one-line failures."""
from __future__ import annotations

import json
import math
import os
import sys
from pathlib import Path

from ..file_errors import FileReadError, read_file_bytes
from ..recovery import atomic_write
from ..errors import ZumlError
from ..i18n import _, ngettext


class CliError(ZumlError):
    """A failure shown as one line on stderr, with a non-zero exit."""

    def __init__(self, message: str, code: int = 2):
        super().__init__(message)
        self.code = code


class OutputError(CliError):
    """Standard output cannot be written (a full disk, a closed pipe's reader gone)."""


class GuardedOutput:
    """``sys.stdout`` while a command runs: a write that fails is one line (``OutputError``), never
    a traceback, wherever the command writes from."""

    def __init__(self, stream) -> None:
        self.stream = stream

    def write(self, text: str) -> int:
        try:
            return self.stream.write(text)
        except BrokenPipeError:
            raise
        except OSError as exc:
            raise _output_error(exc) from None

    def flush(self) -> None:
        try:
            self.stream.flush()
        except BrokenPipeError:
            raise
        except OSError as exc:
            raise _output_error(exc) from None

    def __getattr__(self, name: str):
        return getattr(self.stream, name)


def _output_error(exc: OSError) -> OutputError:
    return OutputError(_("standard output: cannot write: {error}").format(error=exc.strerror or exc), 1)


def silence(stream) -> None:
    """Point a failed output at /dev/null: what it still buffers is dropped at exit, not reported
    a second time by Python as an ignored exception."""
    try:
        fd = stream.fileno()
    except (AttributeError, OSError, ValueError):
        return                  # not a file (captured by a test): nothing is flushed at exit
    null = os.open(os.devnull, os.O_WRONLY)
    os.dup2(null, fd)
    os.close(null)


def read_bytes(path: str) -> bytes:
    try:
        return read_file_bytes(path)
    except FileReadError as exc:
        raise CliError(str(exc)) from None


def read_text(path: str) -> str:
    """A macro's text."""
    data = read_bytes(path)
    try:
        return data.decode("utf-8-sig")
    except UnicodeDecodeError as exc:
        if path.lower().endswith(".bin"):
            what = _("a compiled record? `zuml decompile {path}` prints its text").format(path=path)
        else:
            what = _("a macro is UTF-8 text; a compiled record is read from a file named .bin")
        raise CliError(_("{path}: not UTF-8 text (byte 0x{data:02x} at offset {start}): {what}").format(
                path=path, data=data[exc.start], start=exc.start, what=what)) from None


def is_macro_text(data: bytes) -> bool:
    """Whether ``data`` is a macro's text (its first statement MACRO) rather than compiled bytes."""
    try:
        text = data.decode("utf-8-sig")
    except UnicodeDecodeError:
        return False
    for line in text.splitlines():
        line = line.strip()
        if line and not line.startswith("//"):
            return line.upper().startswith("MACRO")
    return False


def write_bytes(path: str, data: bytes) -> None:
    try:
        atomic_write(Path(path), data, parents=False)
    except OSError as exc:
        raise CliError(_("{path}: cannot write: {error}").format(path=path, error=exc.strerror or exc)) from None


def refuse_unsafe(problems: list[str], force: bool, what: str) -> None:
    """Print the safety check's problems; refuse (exit 1) unless the user forced it."""
    if not problems:
        return
    for line in problems:
        sys.stderr.write(f"  {line}\n")
    if not force:
        raise CliError(ngettext("{what}: refused, {n_problems} safety problem above (--force-unsafe overrides)",
                                "{what}: refused, {n_problems} safety problems above (--force-unsafe overrides)",
                                len(problems)).format(what=what, n_problems=len(problems)), 1)
    sys.stderr.write(ngettext("zuml: warning: {what}: --force-unsafe: going ahead despite the problem above\n",
                              "zuml: warning: {what}: --force-unsafe: going ahead despite the problems above\n",
                              len(problems)).format(what=what))


def add_force_unsafe(p) -> None:
    p.add_argument("--force-unsafe", action="store_true",
                   help=_("write (or start) even what the safety check refuses (chemistry limits, passport)"))


def out(text: str = "") -> None:
    sys.stdout.write(text + "\n")


def out_json(value, **options) -> None:
    """One strict JSON document (RFC 8259: no NaN or Infinity): a figure that is not a finite number
    is missing, ``null``."""
    sys.stdout.write(json.dumps(_finite_or_null(value), indent=2, allow_nan=False, **options) + "\n")


def _finite_or_null(value):
    if isinstance(value, float):
        return value if math.isfinite(value) else None
    if isinstance(value, dict):
        return {k: _finite_or_null(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_finite_or_null(v) for v in value]
    return value


def check_start_options(args, capacity_max: float = 65534.0, amps_max: float = 327.0) -> None:
    """The start values every run command takes (--cycles, --series, --capacity, --current, --voltage)."""
    for name in ("cycles", "series"):
        value = getattr(args, name, None)
        if value is not None and not 1 <= value <= 255:
            raise CliError(_("--{name} must be 1 to 255").format(name=name))
    limits = {"capacity": capacity_max, "current": amps_max, "voltage": amps_max}
    for name, top in limits.items():
        value = getattr(args, name, None)
        if value is not None and not 0 < value <= top:
            raise CliError(_("--{name} must be above 0 and at most {top:g}").format(name=name, top=top))
