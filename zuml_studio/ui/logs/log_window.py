"""The log viewer's window: one tab per opened log, File actions to open, compare and export."""
from __future__ import annotations

from pathlib import Path

from PySide6.QtCore import QSettings, Qt
from PySide6.QtGui import QAction, QKeySequence
from PySide6.QtWidgets import QFileDialog, QMainWindow, QMessageBox, QTabWidget

from ...i18n import N_, _, ngettext
from ...logs import Log, LogFormatError, read_log_file
from ...logs.export import write_csv
from .log_document import LogDocument

TITLE = N_("Logs — ZUML Studio")


def file_filter() -> str:
    return (_("Charger logs and captures") + " (*.txt *.lov *.osd *.csv *.log *.cap *.bin);;"
            + _("All files") + " (*)")


class LogWindow(QMainWindow):
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
        self.resize(1200, 760)

    # -- documents ---------------------------------------------------------------------------
    def current(self) -> LogDocument | None:
        widget = self.tabs.currentWidget()
        return widget if isinstance(widget, LogDocument) else None

    def _read(self, path: str) -> Log | None:
        try:
            return read_log_file(path)
        except LogFormatError as exc:
            self.show_error(str(exc))
            return None

    def open_path(self, path: str) -> LogDocument | None:
        log = self._read(path)
        if log is None:
            return None
        document = LogDocument(log, path)
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
        return document

    def add_path(self, path: str) -> bool:
        document = self.current()
        if document is None:
            return self.open_path(path) is not None
        log = self._read(path)
        if log is None:
            return False
        document.add_overlay(Path(path).name, log)
        self._remember(path)
        return True

    def _close_tab(self, index: int) -> None:
        widget = self.tabs.widget(index)
        if widget is not None:
            self.tabs.removeTab(index)
            widget.deleteLater()

    # -- dialogs -----------------------------------------------------------------------------
    def _folder(self) -> str:
        return str(self.settings.value("lastLogDir", str(Path.home()))) if self.settings else str(Path.home())

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
