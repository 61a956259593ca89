"""The log viewer's window: one tab per opened log, File actions to open, compare and export."""
from __future__ import annotations

from pathlib import Path

from PySide6.QtCore import QSettings, Qt, Signal
from PySide6.QtGui import QAction, QKeySequence
from PySide6.QtWidgets import QFileDialog, QLabel, QMainWindow, QMessageBox, QProgressBar, QTabWidget

from ...i18n import N_, _, ngettext
from ...file_errors import FileReadError, read_file_bytes
from ...logs import Log, LogFormatError, csv_import, read_log_file
from ...logs.export import write_csv
from ..base.background import BackgroundCall
from ..base.settings_values import text_value
from ..base.window_geometry import place_on_screen
from .csv_dialog import CsvChoices, CsvDialog, key_hash
from .log_document import HiddenCurves, LogDocument, Prepared, prepare

TITLE = N_("Logs — ZUML Studio")
# Reads not yet handed over, kept from being collected while their thread runs (a window
# deleted meanwhile leaves its read here: its results go nowhere, as Qt drops a signal to a
# receiver that is gone).
_READING: set[BackgroundCall] = set()


class CsvColumnsNeeded(LogFormatError):
    """A CSV whose guessed columns cannot be read (no time or voltage column found), and no
    choice remembered for its header: the user says which column is what."""


def _read_and_prepare(path: str, choices: dict[str, str], progress=None) -> Prepared:
    """Read a log; a CSV with the columns remembered for its header (``choices``: key_hash -> spec);
    ``progress(done, total)`` where the reader can tell (raw captures, CSV files)."""
    try:
        log = read_log_file(path, progress=progress)
    except LogFormatError as exc:
        try:
            g = csv_import.guess(read_file_bytes(path, pipes=False))
        except (LogFormatError, FileReadError):
            raise exc from None
        if key_hash(g.key) not in choices:
            raise CsvColumnsNeeded(str(exc)) from None
        return prepare(_read_csv(path, choices[key_hash(g.key)]))
    spec = choices.get(key_hash(log.meta.get("csv_key", ""))) if log.format == csv_import.FORMAT else None
    if spec and spec != log.meta["csv_columns"]:
        log = _read_csv(path, spec)
    return prepare(log)


def _read_csv(path: str, spec: str) -> Log:
    try:
        return csv_import.read_as(read_file_bytes(path, pipes=False), spec)
    except (LogFormatError, FileReadError) as exc:
        raise LogFormatError(f"{path}: {exc}") from None


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
        self.csv_choices = CsvChoices(settings)
        self.hidden_curves = HiddenCurves(settings)
        self.csv_dialog: CsvDialog | None = None
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
                                (_("CSV Co&lumns…"), self.csv_columns_dialog, None),
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
        place_on_screen(self, 1200, 760)

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
            choices = self.csv_choices.snapshot()
            self._job = job = BackgroundCall(lambda: _read_and_prepare(path, choices, job.report))
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
        document = LogDocument(prepared, path, hidden=self.hidden_curves)
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
        if log.format == csv_import.FORMAT and key_hash(log.meta["csv_key"]) not in self.csv_choices.snapshot():
            self._ask_columns(path, log.meta["csv_columns"], document)      # the guess, shown once per header

    def _read_failed(self, path: str, exc: Exception) -> None:
        if isinstance(exc, CsvColumnsNeeded):
            self.statusBar().showMessage(str(exc), 8000)
            self._ask_columns(path, None, None)
            return
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

    # -- CSV columns -------------------------------------------------------------------------
    def csv_columns_dialog(self) -> None:
        """The current CSV's columns, to correct (File ▸ CSV Columns…)."""
        document = self.current()
        if document is not None and document.log.format == csv_import.FORMAT:
            self._ask_columns(document.path, document.log.meta["csv_columns"], document)
        elif document is not None:
            self.statusBar().showMessage(_("{name} is not read as a CSV").format(name=document.name), 6000)

    def _ask_columns(self, path: str, spec: str | None, document: LogDocument | None) -> None:
        """The CSV dialog, non-modal; accepted, its columns are kept for the header and the file
        is read again with them (in place of ``document``)."""
        try:
            dialog = CsvDialog(Path(path).name, read_file_bytes(path, pipes=False), spec, self)
        except (LogFormatError, FileReadError) as exc:
            self.show_error(f"{path}: {exc}")
            return
        if self.csv_dialog is not None:
            self.csv_dialog.close()
        self.csv_dialog = dialog
        dialog.setAttribute(Qt.WidgetAttribute.WA_DeleteOnClose)

        def accepted() -> None:
            self.csv_choices.put(dialog.guess.key, dialog.spec())
            if document is not None and self.tabs.indexOf(document) >= 0:
                self._close_tab(self.tabs.indexOf(document))
            self.open_path(path)
        dialog.accepted.connect(accepted)
        dialog.open()

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
