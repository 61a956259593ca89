"""The log viewer's window: one tab per opened log, File actions to open, compare and export."""
from __future__ import annotations

from pathlib import Path

from PySide6.QtCore import QSettings, Qt, Signal
from PySide6.QtGui import QAction, QKeySequence
from PySide6.QtWidgets import QFileDialog, QLabel, QMainWindow, QMessageBox, QProgressBar, QTabWidget

from ...i18n import N_, _, ngettext
from ...logs import LogFormatError, read_log_file
from ...logs.export import write_csv
from ..background import BackgroundCall
from ..settings_values import text_value
from .log_document import LogDocument, Prepared, prepare

TITLE = N_("Logs — ZUML Studio")
# Reads not yet handed over, kept from being collected while their thread runs (a window
# deleted meanwhile leaves its read here: its results go nowhere, as Qt drops a signal to a
# receiver that is gone).
_READING: set[BackgroundCall] = set()


def _read_and_prepare(path: str, progress=None) -> Prepared:
    return prepare(read_log_file(path, progress=progress))


def file_filter() -> str:
    return (_("Charger logs and captures") + " (*.txt *.lov *.osd *.csv *.log *.cap *.bin);;"
            + _("All files") + " (*)")


class LogWindow(QMainWindow):
    """Logs are read and decoded off the GUI thread, one file at a time in the order asked
    for: ``open_path``/``add_path`` return at once, ``documentOpened``, ``overlayAdded`` or
    ``readFailed`` follow, and the status bar shows what is being read meanwhile."""

    documentOpened = Signal(object)     # the new LogDocument
    overlayAdded = Signal(object)       # the LogDocument a log was laid over
    readFailed = Signal(str)            # the message the window shows

    def __init__(self, settings: QSettings | None = None, parent=None):
        super().__init__(parent)
        self.setObjectName("logWindow")
        self.setWindowTitle(_(TITLE))
        # Owned by the main window: closing that ends the application, this one goes with it.
        self.setAttribute(Qt.WidgetAttribute.WA_QuitOnClose, parent is None)
        self.settings = settings
        self.tabs = QTabWidget()
        self.tabs.setTabsClosable(True)
        self.tabs.setDocumentMode(True)
        self.tabs.tabCloseRequested.connect(self._close_tab)
        self.setCentralWidget(self.tabs)
        menu = self.menuBar().addMenu(_("&File"))
        for text, slot, key in ((_("&Open Log…"), self.open_dialog, QKeySequence.StandardKey.Open),
                                (_("&Add a Log to Compare…"), self.add_dialog, "Ctrl+Shift+O"),
                                (_("Export as &CSV…"), self.export_csv_dialog, "Ctrl+E"),
                                (_("Export Plot as &PNG…"), self.export_png_dialog, None),
                                (_("&Close Log"), lambda: self._close_tab(self.tabs.currentIndex()),
                                 QKeySequence.StandardKey.Close)):
            action = QAction(text, self)
            if key is not None:
                action.setShortcut(QKeySequence(key))
            action.triggered.connect(slot)
            menu.addAction(action)
        self._queue: list[tuple[str, str]] = []        # ("open" or "add", path) not started yet
        self._job: BackgroundCall | None = None
        self._reading: tuple[str, str] | None = None
        self._outcome: Prepared | Exception | None = None
        self.busy_label = QLabel()
        self.busy_label.setObjectName("logReading")
        self.busy = QProgressBar()
        self.busy.setRange(0, 0)                # a busy bar until the reader tells how far it is
        self.busy.setMaximumWidth(120)
        self.busy.setTextVisible(False)
        self.statusBar().addPermanentWidget(self.busy_label)
        self.statusBar().addPermanentWidget(self.busy)
        self._show_reading()
        self.resize(1200, 760)

    # -- documents ---------------------------------------------------------------------------
    def current(self) -> LogDocument | None:
        widget = self.tabs.currentWidget()
        return widget if isinstance(widget, LogDocument) else None

    def open_path(self, path: str) -> None:
        """Read the log in the background into a new tab; ``documentOpened`` or ``readFailed`` follows."""
        self._queue.append(("open", path))
        self._next()

    def add_path(self, path: str) -> None:
        """Lay the log over the current one (open it if there is none), read in the background;
        ``overlayAdded`` (``documentOpened``) or ``readFailed`` follows."""
        self._queue.append(("add", path))
        self._next()

    def is_reading(self) -> bool:
        return self._job is not None or bool(self._queue)

    def _next(self) -> None:
        if self._job is None and self._queue:
            self._reading = kind, path = self._queue.pop(0)
            self._outcome = None
            self._job = job = BackgroundCall(lambda: _read_and_prepare(path, job.report))
            _READING.add(job)
            job.progress.connect(self._show_progress)
            # The outcome is kept and handled once the thread has finished (queued after it):
            # whoever hears the signals sees the window done with that file.
            job.done.connect(self._keep_outcome)
            job.failed.connect(self._keep_outcome)
            job.finished.connect(self._read_ended)
            self.busy.setRange(0, 0)            # busy until this read says how far it is
            job.start()
        self._show_reading()

    def _show_progress(self, done: int, total: int) -> None:
        """A long capture says how far its decoding is: the busy bar becomes a progress bar."""
        if self._job is not None and total > 0:
            self.busy.setRange(0, 1000)
            self.busy.setValue(int(done * 1000 // total))

    def _show_reading(self) -> None:
        reading = self._reading is not None
        if reading:
            text = _("Reading {name}…").format(name=Path(self._reading[1]).name)
            if self._queue:
                text += " " + ngettext("({count} more waiting)", "({count} more waiting)",
                                       len(self._queue)).format(count=len(self._queue))
            self.busy_label.setText(text)
        self.busy_label.setVisible(reading)
        self.busy.setVisible(reading)

    def _keep_outcome(self, outcome: Prepared | Exception) -> None:
        self._outcome = outcome

    def _read_ended(self) -> None:
        (kind, path), outcome = self._reading, self._outcome
        self._job.wait()                # finished comes from the thread's last moments: let it end
        _READING.discard(self._job)     # before the object can go (a QThread deleted running aborts)
        self._job = self._reading = self._outcome = None
        self._next()
        if isinstance(outcome, Prepared):
            self._read_done(kind, path, outcome)
        else:
            self._read_failed(path, outcome or RuntimeError("the reader ended without a result"))

    def _read_done(self, kind: str, path: str, prepared: Prepared) -> None:
        document = self.current()
        if kind == "add" and document is not None:
            document.add_overlay(Path(path).name, prepared.log)
            self._remember(path)
            self.overlayAdded.emit(document)
            return
        log = prepared.log
        document = LogDocument(prepared, path)
        document.addRequested.connect(self.add_dialog)
        index = self.tabs.addTab(document, document.name)
        self.tabs.setTabToolTip(index, f"{path}\n{log.device}")
        self.tabs.setCurrentIndex(index)
        self._remember(path)
        message = ngettext("{name}: {n} sample from {device}", "{name}: {n} samples from {device}",
                           len(log.samples)).format(name=document.name, n=len(log.samples), device=log.device)
        if log.bad_records:
            message += ", " + ngettext("{n} bad record skipped", "{n} bad records skipped",
                                       log.bad_records).format(n=log.bad_records)
        self.statusBar().showMessage(message, 8000)
        self.documentOpened.emit(document)

    def _read_failed(self, path: str, exc: Exception) -> None:
        # A reader's own failure is a LogFormatError that names the file; anything else is a bug
        # in a reader, said all the same instead of leaving the window waiting.
        message = str(exc) if isinstance(exc, LogFormatError) else _(
            "{path}: cannot read this log (internal error: {error})").format(path=path,
                                                                           error=f"{type(exc).__name__}: {exc}")
        self.show_error(message)
        self.readFailed.emit(message)

    def closeEvent(self, event) -> None:  # noqa: N802 - Qt's name
        self._queue.clear()             # what was not started yet is not wanted any more
        super().closeEvent(event)

    def _close_tab(self, index: int) -> None:
        widget = self.tabs.widget(index)
        if widget is not None:
            self.tabs.removeTab(index)
            widget.deleteLater()

    # -- dialogs -----------------------------------------------------------------------------
    def _folder(self) -> str:
        return text_value(self.settings, "lastLogDir", str(Path.home())) if self.settings else str(Path.home())

    def _remember(self, path: str) -> None:
        if self.settings is not None:
            self.settings.setValue("lastLogDir", str(Path(path).parent))

    def open_dialog(self) -> None:
        paths = QFileDialog.getOpenFileNames(self, _("Open charger logs"), self._folder(), file_filter())[0]
        for path in paths:
            self.open_path(path)

    def add_dialog(self) -> None:
        paths = QFileDialog.getOpenFileNames(self, _("Logs to compare"), self._folder(), file_filter())[0]
        for path in paths:
            self.add_path(path)

    def export_csv_dialog(self) -> None:
        document = self.current()
        if document is None:
            return
        suggested = str(Path(document.path).with_suffix("")) + "-export.csv"
        path = QFileDialog.getSaveFileName(self, _("Export log as CSV"), suggested, "CSV (*.csv)")[0]
        if path:
            self.export_csv(path)

    def export_csv(self, path: str) -> bool:
        document = self.current()
        if document is None:
            return False
        try:
            with open(path, "w", encoding="utf-8", newline="") as fh:
                rows = write_csv(document.log, fh)
        except OSError as exc:
            self.show_error(_("{path}: cannot write: {reason}").format(path=path, reason=exc.strerror or exc))
            return False
        self.statusBar().showMessage(ngettext("Wrote {n} row to {path}", "Wrote {n} rows to {path}", rows).format(
            n=rows, path=path), 6000)
        return True

    def export_png_dialog(self) -> None:
        document = self.current()
        if document is None:
            return
        path = QFileDialog.getSaveFileName(self, _("Export plot"), str(Path(document.path).with_suffix(".png")),
                                           "PNG (*.png)")[0]
        if path and not document.plot.export_png(path):
            self.show_error(_("{path}: cannot write the PNG").format(path=path))

    def show_error(self, message: str) -> None:
        """Non-modal, like the main window's: an error never blocks (nor a test)."""
        self.statusBar().showMessage(message, 8000)
        box = QMessageBox(QMessageBox.Icon.Warning, _(TITLE), message, QMessageBox.StandardButton.Ok, self)
        box.setObjectName("logErrorBox")
        box.setAttribute(Qt.WidgetAttribute.WA_DeleteOnClose)
        box.open()
