"""The Packs dock: the register (left), the chosen pack's health and sessions (middle) and its trend
(right); importing logs into it, its CSV and one-page report, and the simulator offered the pack's own
fitted model. All data work is ``zuml_studio.packs``; this is only its view."""
from __future__ import annotations

import sqlite3
from collections.abc import Callable
from pathlib import Path

from PySide6.QtCore import QObject, Qt, QTimer, Signal
from PySide6.QtGui import QAction
from PySide6.QtWidgets import (QFileDialog, QHBoxLayout, QHeaderView, QLabel, QListWidget, QListWidgetItem,
                               QMessageBox, QProgressBar, QPushButton, QSplitter, QTableWidget, QTableWidgetItem,
                               QVBoxLayout, QWidget)

from ...packs.db import Logbook, LogbookError
from ...packs.health import trend
from ...packs.model import fit_pack_model, fit_quality, has_model, model_name
from ...sim.fit_predict import trust_words
from ...packs.register import Pack, PackError, forget_attachments, get_pack, list_packs, remove_pack
from ...packs.sessions import ImportResult, import_files, pack_sessions, remove_session
from ...packs.summary import capacity_note, capacity_text, pack_summary, write_sessions_csv
from ..base import theme
from ..base.background import BackgroundCall
from ..device.confirm_dialogs import documents_folder
from .add_pack_dialog import AddPackDialog
from .report import ReportError, write_report
from ...packs.report_data import model_lines, session_curves
from .trend_plot import PackTrendPlot
from ...i18n import N_, _, ngettext

# How often the dock looks whether another writer changed the logbook (one PRAGMA: microseconds).
WATCH_MS = 1000
COLUMNS = (("recorded", N_("date")), ("charge_in_mah", N_("in mAh")), ("charge_out_mah", N_("out mAh")),
           ("capacity_mah", N_("capacity mAh")), ("resistance_mohm_per_cell", N_("mΩ/cell")),
           ("cell_deviation_mv", N_("ΔV cells mV")), ("t_max_c", N_("T max °C")), ("file", N_("file")))


class _Progress(QObject):
    """Carries the import's progress from its thread to the GUI thread (a queued signal)."""
    step = Signal(int, int, object)


class PacksPanel(QWidget):
    # battery name, cells, rated capacity: the simulator is to run the macro on this pack's model
    simulateOnPack = Signal(str, int, float)
    importFinished = Signal(list)             # the ImportResults
    statusMessage = Signal(str)

    def __init__(self, book: Logbook | None = None, parent: QWidget | None = None):
        super().__init__(parent)
        self.book = book
        self.error = ""
        if book is None:
            try:
                self.book = Logbook()
            except LogbookError as exc:       # shown in the dock; the logbook is never replaced
                self.error = str(exc)
        self._job: BackgroundCall | None = None
        self._save_dir = ""                        # where the user last saved an export or a report
        self._fits: dict = {}                      # pack name -> (fitted file, fit_quality): the report shows it
        self._session_ids: list[int] = []          # the table's rows' sessions
        self._bridge = _Progress(self)
        self._bridge.step.connect(self._progress_step)
        look = theme.colours(self.palette())
        self._look = look

        self.pack_list = QListWidget()
        self.add_button = QPushButton(_("Add…"))
        self.remove_button = QPushButton(_("Remove"))
        self.ask_again_button = QPushButton(_("Ask Again for Chargers"))
        self.ask_again_button.setToolTip(_("Forget which pack each charger port or passport serial was attached "
                                           "to: the next run there asks again"))
        left = QVBoxLayout()
        left.setContentsMargins(0, 0, 0, 0)
        left.addWidget(self.pack_list)
        row = QHBoxLayout()
        row.addWidget(self.add_button)
        row.addWidget(self.remove_button)
        left.addLayout(row)
        left.addWidget(self.ask_again_button)
        left_box = QWidget()
        left_box.setLayout(left)

        self.title = QLabel()
        self.title.setWordWrap(True)
        self.title.setTextInteractionFlags(Qt.TextInteractionFlag.TextSelectableByMouse)
        self.health = QLabel()
        self.health.setWordWrap(True)
        self.health.setTextFormat(Qt.TextFormat.RichText)
        self.import_files_button = QPushButton(_("Import Logs…"))
        self.import_folder_button = QPushButton(_("Import Folder…"))
        self.csv_button = QPushButton(_("Sessions CSV…"))
        self.report_button = QPushButton(_("Report…"))
        self.simulate_button = QPushButton()
        # The last fit's quality per pack: its RMSE and what it predicts for the pack's own log (issue 33 §2).
        self.model_label = QLabel()
        self.model_label.setWordWrap(True)
        self.model_label.setTextFormat(Qt.TextFormat.RichText)
        self.model_label.setTextInteractionFlags(Qt.TextInteractionFlag.TextSelectableByMouse)
        self.model_label.hide()
        self._model_notes: dict[int, str] = {}
        self.progress = QProgressBar()
        self.progress.hide()
        self.table = QTableWidget(0, len(COLUMNS))
        self.table.setHorizontalHeaderLabels([_(title) for _key, title in COLUMNS])
        self.table.verticalHeader().hide()
        self.table.verticalHeader().setDefaultSectionSize(self.fontMetrics().height() + 6)
        self.table.setEditTriggers(QTableWidget.EditTrigger.NoEditTriggers)
        self.table.setSelectionBehavior(QTableWidget.SelectionBehavior.SelectRows)
        self.table.horizontalHeader().setSectionResizeMode(QHeaderView.ResizeMode.ResizeToContents)
        self.table.horizontalHeader().setStretchLastSection(True)
        middle = QVBoxLayout()
        middle.setContentsMargins(4, 0, 4, 0)
        middle.addWidget(self.title)
        middle.addWidget(self.health)
        buttons = QHBoxLayout()
        for b in (self.import_files_button, self.import_folder_button, self.csv_button, self.report_button):
            buttons.addWidget(b)
        buttons.addStretch(1)
        middle.addLayout(buttons)
        middle.addWidget(self.simulate_button)
        middle.addWidget(self.model_label)
        middle.addWidget(self.progress)
        middle.addWidget(self.table, 1)
        middle_box = QWidget()
        middle_box.setLayout(middle)
        self.trend_plot = PackTrendPlot()

        split = QSplitter(Qt.Orientation.Horizontal)
        split.addWidget(left_box)
        split.addWidget(middle_box)
        split.addWidget(self.trend_plot)
        split.setSizes([150, 640, 560])
        split.setStretchFactor(1, 1)
        split.setStretchFactor(2, 1)
        layout = QVBoxLayout(self)
        layout.setContentsMargins(2, 2, 2, 2)
        self.error_label = QLabel(self.error)
        self.error_label.setWordWrap(True)
        self.error_label.setStyleSheet(f"color: {look.error}")
        self.error_label.setVisible(bool(self.error))
        layout.addWidget(self.error_label)
        layout.addWidget(split)
        split.setEnabled(not self.error)

        self.pack_list.currentItemChanged.connect(lambda *_a: self.show_pack())
        self.add_button.clicked.connect(self.add_pack)
        self.remove_button.clicked.connect(self.remove_pack)
        self.ask_again_button.clicked.connect(self.ask_again)
        self.table.setContextMenuPolicy(Qt.ContextMenuPolicy.ActionsContextMenu)
        self.remove_session_action = QAction(_("Remove the Session from the Pack"), self.table)
        self.remove_session_action.triggered.connect(self.remove_selected_session)
        self.table.addAction(self.remove_session_action)
        self.import_files_button.clicked.connect(self._choose_files)
        self.import_folder_button.clicked.connect(self._choose_folder)
        self.csv_button.clicked.connect(self._choose_csv)
        self.report_button.clicked.connect(self._choose_report)
        self.simulate_button.clicked.connect(self.simulate_on_pack)
        self.refresh()
        # Another writer (`zuml pack add` in a terminal, a second window) commits: SQLite's data_version
        # moves, and the shown register follows within a second, without a restart.
        self._data_version = self._logbook_version()
        self._watch = QTimer(self)
        self._watch.setInterval(WATCH_MS)
        self._watch.timeout.connect(self._follow_other_writers)
        self._watch.start()

    def _logbook_version(self) -> int | None:
        if self.error or self.book is None:
            return None
        try:
            return int(self.book.conn.execute("PRAGMA data_version").fetchone()[0])
        except sqlite3.Error:
            return None

    def _follow_other_writers(self) -> None:
        if self._job is not None:
            return
        version = self._logbook_version()
        if version is not None and version != self._data_version:
            self._data_version = version
            self.refresh()

    def showEvent(self, event) -> None:  # noqa: N802
        """Shown again: another instance (or `zuml pack import`) may have written the logbook meanwhile."""
        super().showEvent(event)
        if self._job is None:
            self.refresh()

    # -- the register ---------------------------------------------------------------------
    def refresh(self, select: str | None = None) -> None:
        if self.error:
            return
        chosen = self.current_pack()
        current = select or (chosen.name if chosen else None)
        self.pack_list.blockSignals(True)
        self.pack_list.clear()
        for pack in list_packs(self.book):
            item = QListWidgetItem(pack.name)
            item.setData(Qt.ItemDataRole.UserRole, pack.name)
            self.pack_list.addItem(item)
            if pack.name == current:
                self.pack_list.setCurrentItem(item)
        if self.pack_list.currentItem() is None and self.pack_list.count():
            self.pack_list.setCurrentRow(0)
        self.pack_list.blockSignals(False)
        self.show_pack()

    def current_pack(self) -> Pack | None:
        item = self.pack_list.currentItem()
        if item is None:
            return None
        try:
            return get_pack(self.book, item.data(Qt.ItemDataRole.UserRole))
        except PackError:
            return None

    def select_pack(self, name: str) -> None:
        self.refresh(select=name)

    def add_pack(self) -> Pack | None:
        dialog = AddPackDialog(self.book, self)
        if dialog.exec() and dialog.pack is not None:
            self.refresh(select=dialog.pack.name)
            return dialog.pack
        return None

    def remove_pack(self) -> None:
        pack = self.current_pack()
        if pack is None:
            return
        n = len(pack_sessions(self.book, pack))
        answer = QMessageBox.question(self, _("Remove Pack"), ngettext(
                "Remove pack '{name}' and its {n} session from the logbook? (The log files stay.)",
                "Remove pack '{name}' and its {n} sessions from the logbook? (The log files stay.)", n).format(
                name=pack.name, n=n))
        if answer == QMessageBox.StandardButton.Yes:
            self._writing(lambda: remove_pack(self.book, pack.name))
            self.refresh()

    def ask_again(self) -> None:
        n = self._writing(lambda: forget_attachments(self.book))
        if n is None:
            return
        self.statusMessage.emit(ngettext("{n} charger will be asked again which pack is on it",
                                         "{n} chargers will be asked again which pack is on them", n).format(n=n))

    # -- the chosen pack ------------------------------------------------------------------
    def show_pack(self) -> None:
        pack = self.current_pack()
        has = pack is not None
        for w in (self.remove_button, self.import_files_button, self.import_folder_button, self.csv_button,
                  self.report_button, self.simulate_button):
            w.setEnabled(has and self._job is None)
        if not has:
            self.title.setText(_("No pack chosen: Add… one, then import its logs.") if not self.pack_list.count()
                               else "")
            self.health.clear()
            self.table.setRowCount(0)
            self.trend_plot.show_trend([])
            self.simulate_button.setText(_("Simulate the macro on a pack"))
            return
        info = pack_summary(self.book, pack)
        extras = [f"{label}: {info[key]}" for key, label in (("bought", _("bought")), ("serial", _("serial")),
                                                               ("notes", _("notes"))) if info[key]]
        self.title.setText("<b>{}</b> — {}".format(_escape(pack.name), _escape(
                _("{chemistry}, {cells} cells, {capacity:g} mAh rated").format(
                        chemistry=pack.chemistry, cells=pack.cells, capacity=pack.capacity_mah)
                + ("; " + "; ".join(extras) if extras else ""))))
        verdict = info["health"]["verdict"]
        colour = {"good": self._look.ok, "poor": self._look.error}.get(verdict, self._look.muted)
        word = {"good": _("good"), "poor": _("poor"), "unknown": _("unknown")}[verdict]
        self.health.setText(f"<span style='color:{colour}'><b>" + _escape(_("Health: {verdict}").format(
                verdict=word)) + "</b></span><br>" + "<br>".join("• " + _escape(r) for r in info["health"]["reasons"]))
        note = self._model_notes.get(pack.id)
        self.model_label.setText(note or "")
        self.model_label.setVisible(bool(note))
        self.simulate_button.setText(
                _("Simulate the macro on pack '{name}'").format(name=pack.name) if has_model(pack)
                else _("Fit the model of pack '{name}' and simulate the macro on it").format(name=pack.name))
        sessions = info["sessions"]
        self._session_ids = [s.id for s in pack_sessions(self.book, pack)]
        self.table.setRowCount(len(sessions))
        for r, s in enumerate(sessions):
            for c, (key, _title) in enumerate(COLUMNS):
                value = s[key]
                text = (capacity_text(s, "g") if key == "capacity_mah" else "–" if value is None
                        else value[:10] if key == "recorded" else Path(value).name if key == "file" else f"{value:g}")
                item = QTableWidgetItem(text)
                if key == "file":
                    item.setToolTip(value)
                elif key == "capacity_mah" and text.startswith("("):
                    item.setToolTip(capacity_note([s]))
                elif key != "recorded":
                    item.setTextAlignment(Qt.AlignmentFlag.AlignRight | Qt.AlignmentFlag.AlignVCenter)
                self.table.setItem(r, c, item)
        self.trend_plot.show_trend(trend(pack, pack_sessions(self.book, pack)))

    def remove_selected_session(self) -> None:
        """A session attached to the wrong pack, or a log that was no charge of it: out of the logbook (the
        file stays; imported again later, it counts again)."""
        rows = sorted({i.row() for i in self.table.selectedIndexes()})
        for row in rows:
            self._writing(lambda session=self._session_ids[row]: remove_session(self.book, session))
        if rows:
            self.show_pack()

    # -- importing --------------------------------------------------------------------------
    def _choose_files(self) -> None:
        files, _f = QFileDialog.getOpenFileNames(self, _("Import Logs into the Pack"), "",
                                                 _("Charger logs (*.lov *.osd *.txt *.csv *.log);;All files (*)"))
        if files:
            self.import_paths(files)

    def _choose_folder(self) -> None:
        folder = QFileDialog.getExistingDirectory(self, _("Import a Folder of Logs into the Pack"))
        if folder:
            self.import_paths([folder])

    def import_paths(self, paths: list[str]) -> None:
        """Import off the GUI thread with a progress bar; ``importFinished`` follows."""
        pack = self.current_pack()
        if pack is None or self._job is not None:
            return
        bridge = self._bridge
        path = self.book.path

        def job() -> list[ImportResult]:
            book = Logbook(path)              # a connection of the import's own thread
            try:
                return import_files(book, pack, paths, lambda d, t, r: bridge.step.emit(d, t, r))
            finally:
                book.close()

        self.progress.setRange(0, 0)
        self.progress.show()
        self._start(job, self._import_done)

    def _progress_step(self, done: int, total: int, result: ImportResult) -> None:
        self.progress.setRange(0, total)
        self.progress.setValue(done)
        self.progress.setFormat(f"{done}/{total}  {Path(result.path).name}")

    def _import_done(self, results: list[ImportResult]) -> None:
        self.progress.hide()
        counts = {s: sum(r.status == s for r in results) for s in ("added", "known", "error")}
        self.statusMessage.emit(_("{added} added, {known} already known, {error} not read").format(**counts))
        errors = [f"{Path(r.path).name}: {r.message}" for r in results if r.status in ("error", "foreign")]
        self.show_pack()
        self.importFinished.emit(results)
        if errors and self.isVisible():
            QMessageBox.information(self, _("Import"), "\n".join(errors[:20]))

    def _start(self, fn, done) -> None:
        self._job = BackgroundCall(fn, self)
        self._job.done.connect(lambda result: (self._finish(), done(result)))
        self._job.failed.connect(lambda exc: (self._finish(), self._failed(exc)))
        self.show_pack()
        self._job.start()

    def _finish(self) -> None:
        self._job.wait()
        self._job = None

    def _failed(self, exc: Exception) -> None:
        self.progress.hide()
        self.show_pack()
        self.statusMessage.emit(str(exc))
        if self.isVisible():
            QMessageBox.warning(self, _("Packs"), str(exc))

    def _writing(self, change):
        """``change()``'s result; a logbook another instance holds (or that cannot be written) is said, None."""
        try:
            return change()
        except LogbookError as exc:
            self._failed(exc)
            return None

    def busy(self) -> bool:
        return self._job is not None

    # -- outputs ----------------------------------------------------------------------------
    def _choose_csv(self) -> None:
        pack = self.current_pack()
        if pack is None:
            return
        path, _f = QFileDialog.getSaveFileName(self, _("Export the Sessions"), self._save_start(f"{pack.name}.csv"),
                                               "CSV (*.csv)")
        if path:
            self._save_dir = str(Path(path).parent)
            self.export_csv(path)

    def export_csv(self, path: str) -> bool:
        pack = self.current_pack()
        try:
            write_sessions_csv(self.book, pack, path)
        except OSError as exc:
            self._failed(OSError(_("{path}: cannot write: {error}").format(path=path, error=exc.strerror or exc)))
            return False
        return True

    def _choose_report(self) -> None:
        pack = self.current_pack()
        if pack is None:
            return
        path, _f = QFileDialog.getSaveFileName(self, _("Pack Report"), self._save_start(f"{pack.name}.pdf"),
                                               _("PDF (*.pdf);;PNG image (*.png)"))
        if not path:
            return
        self._save_dir = str(Path(path).parent)
        if self._job is not None:
            self.write_report(path)
            return
        # the sessions' logs are read off the GUI thread too (a long log takes seconds)
        self._fit_then(pack, lambda _name, curves: self.write_report(path, curves), quiet=True,
                       fit=pack.name not in self._fits,
                       also=lambda book: session_curves(pack, pack_sessions(book, pack))[0])

    def _save_start(self, name: str) -> str:
        """A save dialog's suggestion: in the folder last saved to, else the user's documents (a bare
        name would start in the current directory: the source tree when run from a checkout)."""
        return str(Path(self._save_dir or documents_folder()) / name)

    def write_report(self, path: str, curves: list | None = None) -> bool:
        """The report, with the model this window last fitted to the pack (``_choose_report`` fits one first);
        ``curves``: the sessions' curves where already read (``session_curves``), else read here."""
        pack = self.current_pack()
        sessions = pack_sessions(self.book, pack)
        if curves is None:
            curves, _missing = session_curves(pack, sessions)
        fitted = self._fits.get(pack.name)
        try:
            write_report(path, pack_summary(self.book, pack), trend(pack, sessions), curves,
                         model_lines(fitted[1] if fitted else None, fitted[0] if fitted else ""))
        except ReportError as exc:
            self._failed(exc)
            return False
        return True

    # -- the simulator ----------------------------------------------------------------------
    def simulate_on_pack(self) -> None:
        """The pack's saved model, else fitted now (off the GUI thread), offered to the simulator."""
        pack = self.current_pack()
        if pack is None or self._job is not None:
            return
        if has_model(pack):
            self.simulateOnPack.emit(model_name(pack), pack.cells, pack.capacity_mah)
            return

        def simulate(name: str, _also) -> None:
            self.show_pack()
            self.simulateOnPack.emit(name, pack.cells, pack.capacity_mah)

        self._fit_then(pack, simulate)

    def _fit_then(self, pack: Pack, then: Callable[[str | None, object], None], quiet: bool = False,
                  fit: bool = True, also: Callable[[Logbook], object] | None = None) -> None:
        """Off the GUI thread: fits the pack's model (``fit``), keeping its quality for the report and the note,
        and runs ``also(book)``; then calls ``then(name, also's result)``. ``quiet``: a pack with no log to fit
        gives the name None instead of saying why."""
        path = self.book.path

        def job():
            book = Logbook(path)
            try:
                made = None
                if fit:
                    try:
                        name, result = fit_pack_model(book, pack)
                        made = name, result, fit_quality(result)
                    except PackError:
                        if not quiet:
                            raise
                return made, also(book) if also else None
            finally:
                book.close()

        def fitted(out) -> None:
            made, extra = out
            self.progress.hide()
            if made is not None:
                name, result, quality = made
                self._fits[pack.name] = (result.curve.name, quality)
                self._model_notes[pack.id] = self._model_note(quality, result.curve.name)
            then(made[0] if made is not None else None, extra)

        self.progress.setRange(0, 0)
        self.progress.setFormat(_("fitting the model of pack '{name}'…").format(name=pack.name) if fit
                                else _("reading the logs of pack '{name}'…").format(name=pack.name))
        self.progress.show()
        self._start(job, fitted)

    def _model_note(self, quality: dict, logged_file: str = "") -> str:
        """The fit's quality and its prediction of the pack's own log (the report's lines), the warning in the
        error colour where the model is not to be trusted (rich text)."""
        warning = trust_words(quality["own_program"])
        return "<br>".join(f"<span style='color:{self._look.error}'><b>{_escape(line)}</b></span>"
                           if line == warning else _escape(line) for line in model_lines(quality, logged_file))


def _escape(text: str) -> str:
    return text.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;")
