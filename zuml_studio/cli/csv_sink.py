"""The CSV file ``zuml monitor --csv`` writes beside the screen.

A write failure (disk full, a file system gone read-only) is said once, on one line, and ends
the file, never the stream: the monitor goes on on screen and exits non-zero at the end."""
from __future__ import annotations

import csv
import sys
import time

from .common import CliError
from ..i18n import _

FLUSH_S = 0.5


class CsvSink:
    def __init__(self, path: str, columns: tuple[str, ...]):
        self.path = path
        self.failed: str | None = None      # the first failure, as printed
        try:
            self._fh = open(path, "w", encoding="utf-8", newline="")
        except OSError as exc:
            raise CliError(_("{path}: cannot write: {error}").format(path=path, error=exc.strerror or exc)) from None
        self._writer = csv.writer(self._fh, lineterminator="\n")
        self._flushed = time.monotonic()
        self.row(columns)

    def row(self, values) -> None:
        if self.failed is None:
            self._guard(lambda: self._writer.writerow(values))

    def flush_if_due(self) -> None:
        if self.failed is None and time.monotonic() - self._flushed >= FLUSH_S:
            self._guard(self._fh.flush)
            self._flushed = time.monotonic()

    def close(self) -> None:
        if self.failed is None:
            self._guard(self._fh.flush)
        try:
            self._fh.close()
        except OSError:
            pass            # the failure was said already; closing retries the same lost bytes

    def _guard(self, action) -> None:
        try:
            action()
        except OSError as exc:
            self.failed = _("{path}: cannot write: {error}").format(path=self.path, error=exc.strerror or exc)
            sys.stderr.write(_("zuml: error: {failed}; the CSV ends here, the monitor goes on on screen\n").format(
                    failed=self.failed))
            sys.stderr.flush()
