"""ZUML Studio's main window: the editor in the centre, the library on the left,
the bytes on the right, problems and the simulator below. It wires the parts
together; each part lives in its own module."""
from __future__ import annotations

import os
from pathlib import Path

from PySide6.QtCore import QSettings, Qt, QTimer
from PySide6.QtGui import QAction, QKeySequence
from PySide6.QtWidgets import (QDialog, QDockWidget, QFileDialog, QLabel, QMainWindow, QMessageBox, QTextBrowser,
                               QVBoxLayout, QWidget)

from ..lang import opcodes as ops
from ..lang.compiler import CompileResult
from ..lang.docgen import commands_markdown
from ..macro_file import EXTENSION, MacroFile, MacroFileError, read_macro_file, write_macro_file
from ..recovery import Recovered, RecoveryStore, atomic_write, config_dir
from .editor.code_editor import EditorWithFind
from .hex_view import HexView
from .library import STANDARD_MACROS, LibraryBrowser
from .problems import ProblemsView
from .sim.sim_panel import SimulatorPanel
from .validation import Validator
from .visual import NewMacroWizard, VisualEditor

APP_NAME = "ZUML Studio"
AUTOSAVE_MS = 5000
DEVICE_PANEL_DELAY_MS = 300      # built after the first paint: its tab is not the one in front
MAX_RECENT = 10
LAYOUT_VERSION = 3      # raise when docks are added or removed: an older saved layout is then ignored
EMPTY_MACRO = """MACRO NewMacro
  AKK_TYPE=LiPo
  CHARGE_SECTION
    FAZE
      CONSTANT_I=INPUT
      IF(V>4.2S) STOP_FAZE
    END_FAZE
  END_SECTION
END_MACRO
"""


class MainWindow(QMainWindow):
    def __init__(self, config: Path | None = None):
        super().__init__()
        self.setObjectName("mainWindow")
        self.config = config or config_dir()
        self.settings = QSettings(str(self.config / "settings.ini"), QSettings.Format.IniFormat)
        self.recovery = RecoveryStore(self.config)
        self.user_macros = self.config / "macros"
        self.user_macros.mkdir(parents=True, exist_ok=True)

        self.path: str | None = None
        self.file: MacroFile | None = None
        self._untitled = 0
        self._recovery_key = ""

        self._build_widgets()
        self._build_actions()
        self._build_menus()
        self._connect()
        self._autosave = QTimer(self, interval=AUTOSAVE_MS, timeout=self.autosave)
        self._autosave.start()
        self.resize(1500, 950)
        self._restore_layout()
        self.new_file(EMPTY_MACRO, ask=False)

    # -- construction -------------------------------------------------------------------
    def _build_widgets(self) -> None:
        self.editor_box = EditorWithFind()
        self.editor = self.editor_box.editor
        self.setCentralWidget(self.editor_box)
        self.validator = Validator(self)
        self.problems = ProblemsView()
        self.hex_view = HexView()
        self.library = LibraryBrowser(self.user_macros)
        self.sim_panel = SimulatorPanel()
        self.visual = VisualEditor(self.editor)
        self._device_panel = None

        self.library_dock = self._dock("Library", "libraryDock", self.library, Qt.DockWidgetArea.LeftDockWidgetArea)
        self.hex_dock = self._dock("Bytes", "hexDock", self.hex_view, Qt.DockWidgetArea.RightDockWidgetArea)
        self.visual_dock = self._dock("Visual", "visualDock", self.visual, Qt.DockWidgetArea.RightDockWidgetArea)
        self.tabifyDockWidget(self.hex_dock, self.visual_dock)
        self.hex_dock.raise_()
        self.problems_dock = self._dock("Problems", "problemsDock", self.problems,
                                        Qt.DockWidgetArea.BottomDockWidgetArea)
        self.sim_dock = self._dock("Simulator", "simulatorDock", self.sim_panel, Qt.DockWidgetArea.BottomDockWidgetArea)
        self.device_dock = self._dock("Device", "deviceDock", QWidget(), Qt.DockWidgetArea.BottomDockWidgetArea)
        self.device_dock.visibilityChanged.connect(lambda visible: visible and self.device_panel)
        QTimer.singleShot(DEVICE_PANEL_DELAY_MS, self, lambda: self.isVisible() and self.device_panel)
        self.splitDockWidget(self.problems_dock, self.sim_dock, Qt.Orientation.Horizontal)
        self.tabifyDockWidget(self.sim_dock, self.device_dock)
        self.sim_dock.raise_()
        self.resizeDocks([self.library_dock, self.hex_dock], [230, 420], Qt.Orientation.Horizontal)
        self.resizeDocks([self.problems_dock, self.sim_dock], [330, 1170], Qt.Orientation.Horizontal)
        self.resizeDocks([self.sim_dock], [400], Qt.Orientation.Vertical)

        self.pos_label = QLabel()
        self.size_label = QLabel()
        self.state_label = QLabel()
        for label in (self.pos_label, self.size_label, self.state_label):
            label.setContentsMargins(8, 0, 8, 0)
        self.statusBar().addPermanentWidget(self.pos_label)
        self.statusBar().addPermanentWidget(self.size_label)
        self.statusBar().addPermanentWidget(self.state_label)

    @property
    def device_panel(self):
        """The Device panel, built on first use (or shortly after the window's first paint)."""
        if self._device_panel is None:
            from .device.device_panel import DevicePanel

            panel = DevicePanel(self._current_record, self.config / "sessions")
            panel.statusMessage.connect(lambda message: self.statusBar().showMessage(message, 6000))
            self._device_panel = panel
            self.device_dock.setWidget(panel)
        return self._device_panel

    def _dock(self, title: str, name: str, widget, area) -> QDockWidget:
        dock = QDockWidget(title, self)
        dock.setObjectName(name)
        dock.setWidget(widget)
        dock.setFeatures(QDockWidget.DockWidgetFeature.DockWidgetMovable |
                         QDockWidget.DockWidgetFeature.DockWidgetFloatable |
                         QDockWidget.DockWidgetFeature.DockWidgetClosable)
        self.addDockWidget(area, dock)
        return dock

    def _action(self, text: str, slot, shortcut=None, tip: str = "") -> QAction:
        action = QAction(text, self)
        if shortcut is not None:
            action.setShortcut(QKeySequence(shortcut))
        if tip:
            action.setStatusTip(tip)
        action.triggered.connect(slot)
        return action

    def _build_actions(self) -> None:
        K = QKeySequence.StandardKey
        self.act_new = self._action("&New", lambda: self.new_file(EMPTY_MACRO), K.New, "A new macro")
        self.act_wizard = self._action("New from &Wizard…", self.new_from_wizard, "Ctrl+Shift+N",
                                       "Answer a few questions about the battery")
        self.act_visual = self._action("&Visual Editor", self.show_visual, "Ctrl+Shift+V")
        self.act_open = self._action("&Open…", self.open_dialog, K.Open)
        self.act_save = self._action("&Save", self.save, K.Save)
        self.act_save_as = self._action("Save &As…", self.save_as, K.SaveAs)
        self.act_export = self._action("Export &Byte Record…", self.export_record, "Ctrl+Shift+E",
                                       "Write the compiled record (.bin)")
        self.act_quit = self._action("&Quit", self.close, K.Quit)
        self.act_toggle_comment = self._action("Toggle &Comment", lambda: self.editor.toggle_comment(), "Ctrl+/")
        self.act_find = self._action("&Find…", lambda: self.editor.show_find(False), K.Find)
        self.act_replace = self._action("&Replace…", lambda: self.editor.show_find(True), K.Replace)
        self.act_simulate = self._action("&Simulate", lambda: self.sim_panel.simulate(), "F5")
        self.act_cancel_sim = self._action("&Cancel Simulation", lambda: self.sim_panel.cancel(), "Shift+F5")
        self.act_export_csv = self._action("Export Samples as &CSV…", self.export_csv)
        self.act_export_png = self._action("Export Plot as &PNG…", self.export_png)
        self.act_reference = self._action("&Command Reference", self.show_reference, K.HelpContents)
        self.act_about = self._action("&About ZUML Studio", self.show_about)

    def _build_menus(self) -> None:
        bar = self.menuBar()
        file_menu = bar.addMenu("&File")
        file_menu.addAction(self.act_new)
        file_menu.addAction(self.act_wizard)
        templates = file_menu.addMenu("New from &Template")
        for path in sorted(STANDARD_MACROS.glob(f"*{EXTENSION}"), key=lambda p: p.name.lower()):
            templates.addAction(path.stem, lambda p=path: self.new_from_template(p))
        file_menu.addAction(self.act_open)
        self.recent_menu = file_menu.addMenu("Open &Recent")
        file_menu.addSeparator()
        file_menu.addAction(self.act_save)
        file_menu.addAction(self.act_save_as)
        file_menu.addAction(self.act_export)
        file_menu.addSeparator()
        file_menu.addAction(self.act_quit)
        self._fill_recent()

        edit = bar.addMenu("&Edit")
        undo = self._action("&Undo", lambda: self.editor.undo(), QKeySequence.StandardKey.Undo)
        redo = self._action("&Redo", lambda: self.editor.redo(), QKeySequence.StandardKey.Redo)
        self.editor.undoAvailable.connect(undo.setEnabled)
        self.editor.redoAvailable.connect(redo.setEnabled)
        for action in (undo, redo):
            action.setShortcutContext(Qt.ShortcutContext.WidgetShortcut)
            edit.addAction(action)
        edit.addSeparator()
        for action in (self.act_find, self.act_replace, self.act_toggle_comment):
            edit.addAction(action)

        view = bar.addMenu("&View")
        view.addAction(self.act_visual)
        view.addSeparator()
        for dock in (self.library_dock, self.hex_dock, self.visual_dock, self.problems_dock, self.sim_dock,
                     self.device_dock):
            view.addAction(dock.toggleViewAction())

        sim = bar.addMenu("&Simulate")
        for action in (self.act_simulate, self.act_cancel_sim):
            sim.addAction(action)
        sim.addSeparator()
        sim.addAction(self.act_export_csv)
        sim.addAction(self.act_export_png)

        help_menu = bar.addMenu("&Help")
        help_menu.addAction(self.act_reference)
        help_menu.addAction(self.act_about)

    def _connect(self) -> None:
        self.editor.textChanged.connect(self._text_changed)
        self.editor.document().modificationChanged.connect(self.setWindowModified)
        self.editor.cursorPositionChanged.connect(self._cursor_moved)
        self.editor.cursorLineChanged.connect(self._cursor_line_changed)
        self.validator.validated.connect(self._validated)
        self.validator.validated.connect(self.visual.show_result)
        self.visual.statusMessage.connect(lambda message: self.statusBar().showMessage(message, 6000))
        self.hex_view.lineActivated.connect(lambda line: self.editor.goto(line))
        self.hex_view.rowsSelected.connect(self.editor.set_linked_lines)
        self.problems.problemActivated.connect(self.editor.goto)
        self.library.fileActivated.connect(self.open_file)
        self.sim_panel.phaseActivated.connect(self._goto_offset)

    # -- text and checking --------------------------------------------------------------
    def text(self) -> str:
        return self.editor.toPlainText()

    def is_dirty(self) -> bool:
        return self.editor.document().isModified()

    def _text_changed(self) -> None:
        self.validator.schedule(self.text())

    def validate_now(self) -> CompileResult:
        return self.validator.run_now(self.text())

    def _validated(self, result: CompileResult) -> None:
        self.editor.set_diagnostics(result.diagnostics)
        self.problems.set_diagnostics(result.diagnostics)
        self.hex_view.show_result(result, self.validator.last_valid)
        self.hex_view.select_line(self.editor.current_line())
        errors = len(result.errors)
        warnings = len(result.diagnostics) - errors
        if result.ok:
            self.size_label.setText(f"{len(result.record)} / 255 bytes")
            self.state_label.setText("✔ valid" + (f", {warnings} warning(s)" if warnings else ""))
            self.state_label.setStyleSheet("color:#1b7f3b;")
            self.sim_panel.set_record(result.record, result.macro.name, self._declared(result))
        else:
            self.size_label.setText("– / 255 bytes")
            self.state_label.setText(f"✖ {errors} error(s)")
            self.state_label.setStyleSheet("color:#b00020;")
            self.sim_panel.set_record(None)
        self.problems_dock.setWindowTitle(f"Problems ({errors} errors, {warnings} warnings)"
                                          if result.diagnostics else "Problems")

    @staticmethod
    def _declared(result: CompileResult) -> dict:
        hints: dict = {}
        macro = result.macro
        akk, series, capacity = (macro.declared(op) for op in (ops.AKK_TYPE, ops.SERIES, ops.CAPACITY))
        if akk:
            hints["chemistry"] = ops.AKK_TYPE.operands[0].kind.format(akk.args[0].raw)
        if series:
            hints["series"] = series.args[0].raw
        if capacity and capacity.args[0].raw not in (0, 0xFFFF):
            hints["capacity_mah"] = capacity.args[0].raw
        return hints

    def _current_record(self) -> tuple[bytes, str] | None:
        """What Compile & Flash writes: the editor's macro, checked now (never stale bytes)."""
        result = self.validate_now()
        return (result.record, result.macro.name) if result.ok else None

    def _cursor_moved(self) -> None:
        cursor = self.editor.textCursor()
        self.pos_label.setText(f"Ln {cursor.blockNumber() + 1}, Col {cursor.positionInBlock() + 1}")

    def _cursor_line_changed(self, line: int) -> None:
        # The cursor leads again: the bytes follow it and a highlight from an earlier row click goes.
        self.editor.set_linked_lines(set())
        self.hex_view.select_line(line)

    def _goto_offset(self, offset: int) -> None:
        """A phase chosen in the simulator: its FAZE byte -> the source line it came from."""
        valid = self.validator.last_valid
        if not valid:
            return
        for ins, node in zip(valid.encoded.instructions, valid.encoded.nodes):
            span = getattr(node, "span", None)
            if ins.offset == offset and span:
                self.editor.goto(span.line, span.column)
                return

    # -- files ------------------------------------------------------------------------
    def _set_document(self, text: str, path: str | None, file: MacroFile | None, dirty: bool = False) -> None:
        if self._recovery_key:
            self.recovery.discard(self._recovery_key)
        self.path, self.file = path, file
        if path is None:
            self._untitled += 1
        self._recovery_key = RecoveryStore.key_for(path, f"{os.getpid()}-{self._untitled}")
        self.editor.setPlainText(text)
        self.editor.document().setModified(dirty)
        self.setWindowModified(dirty)
        self._update_title()
        self.validate_now()
        self.editor.goto(1, 1)

    def _update_title(self) -> None:
        name = Path(self.path).name if self.path else "untitled"
        self.setWindowTitle(f"{name}[*] — {APP_NAME}")

    def new_file(self, text: str = EMPTY_MACRO, ask: bool = True) -> bool:
        if ask and not self.maybe_save():
            return False
        self._set_document(text, None, None)
        return True

    def new_from_template(self, path: Path) -> bool:
        try:
            text = read_macro_file(path).text
        except MacroFileError as exc:
            self.show_error(str(exc))
            return False
        return self.new_file(text)

    def new_from_wizard(self) -> bool:
        dialog = NewMacroWizard(self)
        if not dialog.exec():
            return False
        return self.new_file(dialog.text())

    def show_visual(self) -> None:
        self.visual_dock.show()
        self.visual_dock.raise_()

    def open_dialog(self) -> None:
        if not self.maybe_save():
            return
        start = self.settings.value("lastDir", str(self.user_macros))
        path, _ = QFileDialog.getOpenFileName(self, "Open macro", start, f"ZUML macros (*{EXTENSION});;All files (*)")
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

    def save(self) -> bool:
        if self.path is None:
            return self.save_as()
        return self._write(self.path)

    def save_as(self) -> bool:
        folder = Path(self.path).parent if self.path else Path(self.settings.value("lastDir", str(self.user_macros)))
        suggested = str(folder / f"{self.suggested_name()}{EXTENSION}")
        path, _ = QFileDialog.getSaveFileName(self, "Save macro as", suggested, f"ZUML macros (*{EXTENSION})")
        if not path:
            return False
        if not path.endswith(EXTENSION):
            path += EXTENSION
        return self._write(path)

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
        self.recovery.discard(self._recovery_key)
        self.path = str(Path(path).resolve())
        self._recovery_key = RecoveryStore.key_for(self.path, "")
        self.editor.document().setModified(False)
        self._update_title()
        self._remember(self.path)
        self.statusBar().showMessage(f"Saved {self.path}", 4000)
        if Path(self.path).parent == self.user_macros.resolve():
            self.library.refresh()
        return True

    def export_record(self) -> bool:
        result = self.validate_now()
        if not result.ok:
            self.show_error("The macro has errors; fix them before exporting its bytes.")
            return False
        folder = Path(self.path).parent if self.path else self.user_macros
        path, _ = QFileDialog.getSaveFileName(self, "Export byte record", str(folder / f"{self.suggested_name()}.bin"),
                                              "Byte records (*.bin)")
        if not path:
            return False
        try:
            atomic_write(Path(path), result.record)
        except OSError as exc:
            self.show_error(f"{path}: {exc.strerror or exc}")
            return False
        self.statusBar().showMessage(f"Wrote {len(result.record)} bytes to {path}", 4000)
        return True

    def export_csv(self) -> None:
        if self.sim_panel.result() is None:
            self.show_error("Simulate first: there are no samples yet.")
            return
        path, _ = QFileDialog.getSaveFileName(self, "Export samples", f"{self.suggested_name()}.csv", "CSV (*.csv)")
        if path:
            self.sim_panel.export_csv(path)

    def export_png(self) -> None:
        path, _ = QFileDialog.getSaveFileName(self, "Export plot", f"{self.suggested_name()}.png", "PNG (*.png)")
        if path:
            self.sim_panel.export_png(path)

    def _remember(self, path: str | None) -> None:
        if not path:
            return
        recent = [p for p in self.recent_files() if p != path]
        self.settings.setValue("recentFiles", [path] + recent[:MAX_RECENT - 1])
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
        name = Path(self.path).name if self.path else "untitled"
        box = QMessageBox(QMessageBox.Icon.Warning, APP_NAME, f"{name} has unsaved changes.",
                          QMessageBox.StandardButton.Save | QMessageBox.StandardButton.Discard |
                          QMessageBox.StandardButton.Cancel, self)
        box.setInformativeText("Save them before closing it?")
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

    def autosave(self) -> None:
        if self.is_dirty():
            self.recovery.save(self._recovery_key, self.text(), self.path)

    def ask_recover(self, found: Recovered) -> bool:
        """Whether to restore text a crash left behind (tests replace this)."""
        where = found.original or "an untitled macro"
        answer = QMessageBox.question(self, APP_NAME, f"ZUML Studio did not close cleanly.\n\nRecover the unsaved "
                                      f"text of {where}?")
        return answer == QMessageBox.StandardButton.Yes

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
                self.recovery.discard(found.key)
                self.autosave()
                return True
            self.recovery.discard(found.key)
        return False

    def closeEvent(self, event) -> None:
        if not self.maybe_save():
            event.ignore()
            return
        self.sim_panel.cancel()
        if self._device_panel is not None:
            self._device_panel.shutdown()
        self.recovery.discard(self._recovery_key)
        self.settings.setValue("geometry", self.saveGeometry())
        self.settings.setValue("windowState", self.saveState(LAYOUT_VERSION))
        self.settings.sync()
        event.accept()

    def _restore_layout(self) -> None:
        geometry = self.settings.value("geometry")
        state = self.settings.value("windowState")
        if geometry is not None:
            self.restoreGeometry(geometry)
        if state is not None:
            self.restoreState(state, LAYOUT_VERSION)

    # -- messages and help ----------------------------------------------------------------
    def show_error(self, message: str) -> None:
        """Non-modal: an error never blocks the window (nor a test)."""
        self.statusBar().showMessage(message, 8000)
        box = QMessageBox(QMessageBox.Icon.Warning, APP_NAME, message, QMessageBox.StandardButton.Ok, self)
        box.setObjectName("errorBox")
        box.setAttribute(Qt.WidgetAttribute.WA_DeleteOnClose)
        box.open()

    def show_reference(self) -> None:
        dialog = QDialog(self)
        dialog.setWindowTitle("ZUML 2.0 commands")
        browser = QTextBrowser()
        browser.setMarkdown(commands_markdown())
        layout = QVBoxLayout(dialog)
        layout.addWidget(browser)
        dialog.resize(1000, 700)
        dialog.show()

    def show_about(self) -> None:
        QMessageBox.about(self, APP_NAME, "ZUML Studio: write, check, simulate and flash ZUML 2.0 charger macros.")
