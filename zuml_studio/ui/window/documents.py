"""The document the window shows and its files: New (empty, a template, the wizard), Open,
Save / Save As (a standard macro is read-only), the recent files, the exports (bytes, samples,
plot), unsaved work (asked about, written to crash recovery and offered back at start).

A mixin of the main window: it uses the window's editor, validator, simulator panel, library,
settings and status bar."""
from __future__ import annotations

import os
from pathlib import Path

from PySide6.QtCore import QSize, QStandardPaths
from PySide6.QtWidgets import QFileDialog, QMessageBox

from ... import data
from ...i18n import _, ngettext
from ...macro_file import EXTENSION, MacroFile, MacroFileError, read_macro_file, write_macro_file
from ...recovery import Recovered, RecoveryStore, atomic_write
from ..plots.plot_export import PlotExportDialog
from ..base.settings_values import text_value
from ..visual import NewMacroWizard

APP_NAME = "ZUML Studio"
MAX_RECENT = 10
# File > New: a 1-cell LiPo charged CC-CV (constant current, then the voltage held until the current falls),
# which fills the cell; every value in it is one the user is expected to change.
EMPTY_MACRO = """MACRO NewMacro
  AKK_TYPE=LiPo
  SERIES=1
  CAPACITY=2000
  CHARGE_SECTION
    FAZE
      CONSTANT_I=INPUT
      CONSTANT_V=4.2S
      IF(I<0.1C) STOP_FAZE
      IF(T>45) STOP_FAZE
    END_FAZE
  END_SECTION
END_MACRO
"""


def is_standard(path: str | Path | None) -> bool:
    """Whether a file is one of the standard macros (opened read-only: Save goes to Save As)."""
    return path is not None and data.is_standard_macro(path)


def documents_dir() -> Path:
    """The user's documents folder (exports go there by default), the home folder without one."""
    found = QStandardPaths.writableLocation(QStandardPaths.StandardLocation.DocumentsLocation)
    return Path(found) if found and Path(found).is_dir() else Path.home()


class DocumentFiles:
    """The main window's file commands (mixed into MainWindow)."""

    def _set_document(self, text: str, path: str | None, file: MacroFile | None, dirty: bool = False) -> None:
        """Show a text; ``dirty`` for one that is not on disk as shown (generated, recovered),
        which is then unsaved work: asked about before it is dropped, and written to recovery."""
        if self._recovery_key:
            self._saver.discard(self._recovery_key)
        self.path, self.file = path, file
        if path is None:
            self._untitled += 1
        self._recovery_key = RecoveryStore.key_for(path, f"{os.getpid()}-{self._untitled}")
        self.editor.setPlainText(text)
        self.editor.document().setModified(dirty)
        self.setWindowModified(dirty)
        self._update_title()
        self.sim_panel.new_macro()
        self.visual.say("")             # the last macro's refusal is not this one's
        self.validator.forget()
        self.validate_now()
        self.editor.goto(1, 1)
        self.autosave()

    def _update_title(self) -> None:
        name = Path(self.path).name if self.path else _("untitled")
        if self.is_read_only():
            name += " " + _("(standard macro, read-only: Save makes a copy in My macros)")
        self.setWindowTitle(f"{name}[*] — {APP_NAME}")

    def is_read_only(self) -> bool:
        return is_standard(self.path)

    def new_file(self, text: str = EMPTY_MACRO, ask: bool = True) -> bool:
        if ask and not self.maybe_save():
            return False
        self._set_document(text, None, None)
        return True

    def new_generated(self, text: str) -> bool:
        """A macro made for the user (template, wizard): untitled and unsaved work."""
        if not self.maybe_save():
            return False
        self._set_document(text, None, None, dirty=True)
        return True

    def new_from_template(self, path: Path) -> bool:
        try:
            text = read_macro_file(path).text
        except MacroFileError as exc:
            self.show_error(str(exc))
            return False
        return self.new_generated(text)

    def new_from_wizard(self) -> bool:
        dialog = NewMacroWizard(self)
        if not dialog.exec():
            return False
        return self.new_generated(dialog.text())

    def open_dialog(self) -> None:
        if not self.maybe_save():
            return
        start = text_value(self.settings, "lastDir", str(documents_dir()))
        path = self.ask_open_path(_("Open macro"), start,
                                  _("ZUML macros") + f" (*{EXTENSION});;" + _("All files") + " (*)")
        if path:
            self.open_file(path, ask=False)

    def open_file(self, path: str, ask: bool = True) -> bool:
        if ask and not self.maybe_save():
            return False
        try:
            opened = read_macro_file(path)
        except MacroFileError as exc:
            self.show_error(str(exc))
            return False
        self._set_document(opened.text, str(Path(path).resolve()), opened)
        self._remember(self.path)
        return True

    def open_log(self, path: str | None = None):
        """The log viewer's window (made on first use), with ``path`` opened or a file chosen."""
        from ..logs import LogWindow      # the viewer's modules load only when a log is wanted
        if getattr(self, "log_window", None) is None:
            self.log_window = LogWindow(self.settings, self)
        self.log_window.show()
        self.log_window.raise_()
        if path:
            self.log_window.open_path(path)
        else:
            self.log_window.open_dialog()
        return self.log_window

    def save(self) -> bool:
        if self.path is None or self.is_read_only():
            return self.save_as()
        return self._write(self.path)

    def save_as(self) -> bool:
        suggested = str(self._save_folder() / f"{self.suggested_name()}{EXTENSION}")
        path = self.ask_save_path(_("Save macro as"), suggested, _("ZUML macros") + f" (*{EXTENSION})")
        if not path:
            return False
        if not path.endswith(EXTENSION):
            path += EXTENSION
        if is_standard(path):
            self.show_error(_("The standard macros are read-only: save the macro into My macros or another folder."))
            return False
        return self._write(path)

    def _save_folder(self) -> Path:
        """Where Save As and Export start: beside the open file, else My macros; never the
        standard macros' folder."""
        if self.path and not self.is_read_only():
            return Path(self.path).parent
        return self.user_macros

    # Tests replace these two (no modal dialog in a test).
    def ask_save_path(self, title: str, suggested: str, filters: str) -> str:
        return QFileDialog.getSaveFileName(self, title, suggested, filters)[0]

    def ask_open_path(self, title: str, start: str, filters: str) -> str:
        return QFileDialog.getOpenFileName(self, title, start, filters)[0]

    def suggested_name(self) -> str:
        """The MACRO name, as the spec says the name names the file."""
        result = self.validator.last
        name = result.macro.name if result and result.macro and result.macro.name else "macro"
        return "".join(c if c.isalnum() or c in "-_." else "_" for c in name)

    def _write(self, path: str) -> bool:
        try:
            self.file = write_macro_file(path, self.text(), self.file)
        except MacroFileError as exc:
            self.show_error(str(exc))
            return False
        self._saver.discard(self._recovery_key)
        self.path = str(Path(path).resolve())
        self._recovery_key = RecoveryStore.key_for(self.path, "")
        self.editor.document().setModified(False)
        self._update_title()
        self._remember(self.path)
        self.statusBar().showMessage(_("Saved {path}").format(path=self.path), 4000)
        if Path(self.path).parent == self.user_macros.resolve():
            self.library.refresh()
        return True

    def export_record(self) -> bool:
        result = self.validate_now()
        if not result.ok:
            self.show_error(_("The macro has errors; fix them before exporting its bytes."))
            return False
        path = self.ask_save_path(_("Export byte record"), str(self._save_folder() / f"{self.suggested_name()}.bin"),
                                  _("Byte records") + " (*.bin)")
        if not path:
            return False
        try:
            atomic_write(Path(path), result.record)
        except OSError as exc:
            self.show_error(f"{path}: {exc.strerror or exc}")
            return False
        self.statusBar().showMessage(ngettext("Wrote {n} byte to {path}", "Wrote {n} bytes to {path}",
                                               len(result.record)).format(n=len(result.record), path=path), 4000)
        return True

    def export_csv(self) -> None:
        if self.sim_panel.result() is None:
            self.show_error(_("Simulate first: there are no samples yet."))
            return
        path = self.ask_save_path(_("Export samples"), str(documents_dir() / f"{self.suggested_name()}.csv"),
                                  "CSV (*.csv)")
        if path and self.sim_panel.export_csv(path):
            count = len(self.sim_panel.result().log)
            self.statusBar().showMessage(ngettext("Wrote {n} sample to {path}", "Wrote {n} samples to {path}",
                                                  count).format(n=count, path=path), 6000)

    def export_png(self) -> None:
        if self.sim_panel.result() is None:
            self.show_error(_("Simulate first: there is no plot yet."))
            return
        options = self.ask_png_options(self.suggested_name())
        if options is None:
            return
        title, size = options
        path = self.ask_save_path(_("Export plot"), str(documents_dir() / f"{self.suggested_name()}.png"),
                                  "PNG (*.png)")
        if path and self.sim_panel.export_png(path, size, title):
            self.statusBar().showMessage(_("Wrote the plot ({width}×{height}) to {path}").format(
                width=size.width(), height=size.height(), path=path), 6000)

    def ask_png_options(self, title: str) -> tuple[str, QSize] | None:
        """The title and size of an exported plot, None when cancelled (tests replace this)."""
        dialog = PlotExportDialog(title, self)
        return dialog.chosen() if dialog.exec() else None

    def _remember(self, path: str | None) -> None:
        if not path:
            return
        recent = [p for p in self.recent_files() if p != path]
        self.settings.setValue("recentFiles", [path] + recent[:MAX_RECENT - 1])
        if not is_standard(path):       # Open starts where the user keeps macros, never in the package
            self.settings.setValue("lastDir", str(Path(path).parent))
        self._fill_recent()

    def recent_files(self) -> list[str]:
        value = self.settings.value("recentFiles", [])
        if isinstance(value, str):
            value = [value]
        return [str(v) for v in value or []]

    def _fill_recent(self) -> None:
        self.recent_menu.clear()
        files = self.recent_files()
        for path in files:
            self.recent_menu.addAction(path, lambda p=path: self.open_file(p))
        self.recent_menu.setEnabled(bool(files))

    # -- unsaved work -----------------------------------------------------------------
    def ask_unsaved(self) -> str:
        """'save', 'discard' or 'cancel' (tests replace this)."""
        name = Path(self.path).name if self.path else _("untitled")
        box = QMessageBox(QMessageBox.Icon.Warning, APP_NAME, _("{name} has unsaved changes.").format(name=name),
                          QMessageBox.StandardButton.Save | QMessageBox.StandardButton.Discard |
                          QMessageBox.StandardButton.Cancel, self)
        box.setInformativeText(_("Save them before closing it?"))
        answer = box.exec()
        return {QMessageBox.StandardButton.Save: "save",
                QMessageBox.StandardButton.Discard: "discard"}.get(QMessageBox.StandardButton(answer), "cancel")

    def maybe_save(self) -> bool:
        if not self.is_dirty():
            return True
        answer = self.ask_unsaved()
        if answer == "save":
            return self.save()
        return answer == "discard"

    def autosave(self, wait: bool = True) -> None:
        """Write the unsaved text to the recovery file (atomically, on the saver's thread; with
        ``wait``, written when this returns); a failure is said, not raised."""
        if not self.is_dirty():
            return
        self._saver.save(self._recovery_key, self.text(), self.path)
        if wait:
            self._saver.wait()

    def _recovery_failed(self, exc: OSError) -> None:
        self.statusBar().showMessage(_("Crash recovery cannot write {folder}: {reason}").format(
            folder=self.recovery.root, reason=exc.strerror or exc), 10000)

    def ask_recover(self, found: Recovered) -> bool:
        """Whether to restore text a crash left behind (tests replace this)."""
        where = found.original or _("an untitled macro")
        box = QMessageBox(QMessageBox.Icon.Question, APP_NAME,
                          _("ZUML Studio did not close cleanly.\n\nRecover the unsaved text of {macro}?").format(
                              macro=where), QMessageBox.StandardButton.Yes | QMessageBox.StandardButton.No, self)
        return box.exec() == QMessageBox.StandardButton.Yes

    def offer_recovery(self) -> bool:
        """At start: offer back what a crash left; returns whether a text was restored."""
        for found in self.recovery.pending(own_key=self._recovery_key):
            if self.ask_recover(found):
                file = None
                if found.original and Path(found.original).is_file():
                    try:
                        file = read_macro_file(found.original)
                    except MacroFileError:
                        file = None
                self._set_document(found.text, found.original, file, dirty=True)
                self._saver.discard(found.key)
                self.autosave()
                return True
            self._saver.discard(found.key)
        return False

    def reopen_last(self) -> bool:
        """At start without a file: the file open when the window last closed, if it is still there."""
        last = text_value(self.settings, "lastOpen", "")
        if not last or not Path(last).is_file():
            return False
        return self.open_file(last, ask=False)
