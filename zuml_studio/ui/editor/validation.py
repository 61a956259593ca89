"""Checks the editor's text a moment after the user stops typing (debounce), on the
GUI thread: a check and compile of the largest macro takes about a millisecond
(benchmarks/bench_compile.py), so a worker thread would cost more than it saves."""
from __future__ import annotations

import logging

from PySide6.QtCore import QObject, QTimer, Signal

from ...i18n import _
from ...lang.compiler import CompileResult, compile_source
from ...lang.diagnostics import Diagnostic, Severity

log = logging.getLogger(__name__)

DEBOUNCE_MS = 250


class Validator(QObject):
    validated = Signal(object)          # CompileResult

    def __init__(self, parent: QObject | None = None, delay_ms: int = DEBOUNCE_MS):
        super().__init__(parent)
        self._timer = QTimer(self, singleShot=True, interval=delay_ms)
        self._timer.timeout.connect(self._run)
        self._text = ""
        self.last: CompileResult | None = None
        self.last_valid: CompileResult | None = None
        self.runs = 0

    def forget(self) -> None:
        """Another document: the last results, and its last valid version, are none of its own."""
        self._timer.stop()
        self.last = self.last_valid = None

    def schedule(self, text: str) -> None:
        """Restart the wait: only the text present when typing pauses is checked."""
        self._text = text
        self._timer.start()

    def run_now(self, text: str) -> CompileResult:
        self._timer.stop()
        self._text = text
        return self._run()

    def _run(self) -> CompileResult:
        self.runs += 1
        try:
            result = compile_source(self._text)
        except Exception as exc:   # noqa: BLE001 - a checker bug must not leave the last result standing
            log.exception("checking the macro failed")
            result = CompileResult(None, [Diagnostic(
                Severity.ERROR, 1, 1, (1, 1), "E000", _("The check itself failed ({error}); nothing can be compiled or flashed until it "
                                   "passes").format(error=f"{type(exc).__name__}: {exc}"),
                _("please report this with the macro"))])
        self.last = result
        if result.ok:
            self.last_valid = result
        self.validated.emit(result)
        return result
