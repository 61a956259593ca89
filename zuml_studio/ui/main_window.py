"""ZUML Studio's main window: the editor in the centre, the library on the left,
the bytes on the right, problems and the simulator below. It wires the parts
together; each part lives in its own module."""
from __future__ import annotations

import os
from pathlib import Path

from PySide6.QtCore import QEvent, QSettings, QSize, QStandardPaths, Qt, QTimer, Signal
from PySide6.QtGui import QAction, QKeySequence
from PySide6.QtWidgets import QDockWidget, QFileDialog, QLabel, QMainWindow, QMessageBox, QStyle, QToolBar, QWidget

from .. import data
from ..i18n import _, ngettext
from ..lang import opcodes as ops
from ..lang.compiler import CompileResult, compile_source
from ..macro_file import EXTENSION, MacroFile, MacroFileError, read_macro_file, write_macro_file
from ..recovery import BackgroundSaver, Recovered, RecoveryStore, atomic_write
from ..user_dirs import config_dir
from . import theme
from .editor.code_editor import EditorWithFind
from .editor.highlighter import ops_at
from .help_browser import HelpBrowser
from .hex_view import HexView
from .language import restart
from .library import LibraryBrowser
from .plot_export import PlotExportDialog
from .preferences import Preferences, PreferencesDialog
from .problems import ProblemsView
from .settings_values import bytes_value, text_value
from .sim.sim_panel import SimulatorPanel
from .validation import Validator
from .visual import NewMacroWizard, VisualEditor
from .window_geometry import first_geometry, fits

APP_NAME = "ZUML Studio"
DEVICE_PANEL_DELAY_MS = 300      # built after the first paint: its tab is not the one in front
VISUAL_MIN_HEIGHT = 440          # the Visual tab, when shown, takes this much height from the docks below
MAX_RECENT = 10
LAYOUT_VERSION = 4      # raise when docks or toolbars are added or removed: an older saved layout is then ignored
EMPTY_MACRO = """MACRO NewMacro
  AKK_TYPE=LiPo
  SERIES=1
  CHARGE_SECTION
    FAZE
      CONSTANT_I=INPUT
      IF(V>4.2S) STOP_FAZE
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
    return Path(found) if found else Path.home()


class MainWindow(QMainWindow):
    _recoveryFailed = Signal(object)     # an OSError of the recovery saver's thread

    def __init__(self, config: Path | None = None):
        super().__init__()
        self.setObjectName("mainWindow")
        self.config = config or config_dir()
        self.settings = QSettings(str(self.config / "settings.ini"), QSettings.Format.IniFormat)
        self.recovery = RecoveryStore(self.config)
        self._saver = BackgroundSaver(self.recovery, self._recoveryFailed.emit)
        self._recoveryFailed.connect(self._recovery_failed)
        self.user_macros = self.config / "macros"
        self.user_macros.mkdir(parents=True, exist_ok=True)

        self.path: str | None = None
        self.file: MacroFile | None = None
        self._untitled = 0
        self._recovery_key = ""
        self._help: HelpBrowser | None = None
        self._upload_pending = False
        self._borrowed = None        # (dock, height) the Visual tab borrowed height from
        self.prefs = Preferences.load(self.settings)

        self._build_widgets()
        self._build_actions()
        self._build_menus()
        self._build_toolbar()
        self._connect()
        self._restore_layout()
        self.apply_preferences(self.prefs)
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

        self.library_dock = self._dock(_("Library"), "libraryDock", self.library, Qt.DockWidgetArea.LeftDockWidgetArea)
        self.hex_dock = self._dock(_("Bytes"), "hexDock", self.hex_view, Qt.DockWidgetArea.RightDockWidgetArea)
        self.visual_dock = self._dock(_("Visual"), "visualDock", self.visual, Qt.DockWidgetArea.RightDockWidgetArea)
        self.tabifyDockWidget(self.hex_dock, self.visual_dock)
        self.visual_dock.visibilityChanged.connect(self._visual_shown)
        self.hex_dock.raise_()
        self.problems_dock = self._dock(_("Problems"), "problemsDock", self.problems,
                                        Qt.DockWidgetArea.BottomDockWidgetArea)
        self.sim_dock = self._dock(_("Simulator"), "simulatorDock", self.sim_panel, Qt.DockWidgetArea.BottomDockWidgetArea)
        self.device_dock = self._dock(_("Device"), "deviceDock", QWidget(), Qt.DockWidgetArea.BottomDockWidgetArea)
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
            panel.connectedChanged.connect(self._device_connected)
            self._device_panel = panel
            self.device_dock.setWidget(panel)
            if self.validator.last_valid is not None:
                panel.macro_changed(self.validator.last_valid.record)
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
        self.act_new = self._action(_("&New"), lambda: self.new_file(EMPTY_MACRO), K.New, _("A new macro"))
        self.act_wizard = self._action(_("New from &Wizard…"), self.new_from_wizard, "Ctrl+Shift+N",
                                       _("Answer a few questions about the battery"))
        self.act_visual = self._action(_("&Visual Editor"), self.show_visual, "Ctrl+Shift+V")
        self.act_open = self._action(_("&Open…"), self.open_dialog, K.Open)
        self.act_open_log = self._action(_("Open &Log…"), lambda: self.open_log(), "Ctrl+L",
                                         _("View a charger's log file: iCharger, LogView, DataExplorer, session CSV"))
        self.act_save = self._action(_("&Save"), self.save, K.Save, _("Save the macro (a standard macro: as a copy)"))
        self.act_save_as = self._action(_("Save &As…"), self.save_as, K.SaveAs)
        self.act_export = self._action(_("Export &Byte Record…"), self.export_record, "Ctrl+Shift+E",
                                       _("Write the compiled record (.bin)"))
        self.act_quit = self._action(_("&Quit"), self.close, K.Quit)
        self.act_toggle_comment = self._action(_("Toggle &Comment"), lambda: self.editor.toggle_comment(), "Ctrl+/")
        self.act_find = self._action(_("&Find…"), lambda: self.editor.show_find(False), K.Find)
        # Ctrl+H, which the editor also handles: the platform's Replace key is empty on some desktops.
        self.act_replace = self._action(_("&Replace…"), lambda: self.editor.show_find(True), "Ctrl+H")
        self.act_prefs = self._action(_("&Preferences…"), self.show_preferences, K.Preferences)
        if self.act_prefs.shortcut().isEmpty():
            self.act_prefs.setShortcut(QKeySequence("Ctrl+,"))
        self.act_zoom_in = self._action(_("Zoom &In"), lambda: self.editor.zoom(1), "Ctrl+=")
        self.act_zoom_in.setShortcuts([QKeySequence("Ctrl+="), QKeySequence("Ctrl++")])
        self.act_zoom_out = self._action(_("Zoom &Out"), lambda: self.editor.zoom(-1), "Ctrl+-")
        self.act_zoom_reset = self._action(_("&Reset Zoom"), self.reset_zoom, "Ctrl+0")
        self.act_verify = self._action(_("&Verify"), self.verify, "Ctrl+R", _("Check and compile the macro"))
        self.act_upload = self._action(_("&Upload"), self.upload, "Ctrl+U",
                                       _("Compile & Flash the macro to the charger (connecting first if needed)"))
        self.act_connect = self._action(_("&Connect"), lambda: self._device_call(self.device_panel.connect_to))
        self.act_disconnect = self._action(_("&Disconnect"), lambda: self._device_call(self.device_panel.disconnect))
        self.act_start = self._action(_("&Start the Macro"), lambda: self._device_call(self.device_panel.start))
        self.act_stop = self._action(_("S&top the Charger"), lambda: self._device_call(self.device_panel.stop))
        self.act_install_firmware = self._action(_("&Install Firmware on an iMAX B6…"), self.install_firmware, None,
                                                 _("Save the charger's original, then write the ZUML firmware"))
        self.act_simulate = self._action(_("&Simulate"), lambda: self.sim_panel.simulate(), "F5")
        self.act_cancel_sim = self._action(_("&Cancel Simulation"), lambda: self.sim_panel.cancel(), "Shift+F5")
        self.act_export_csv = self._action(_("Export Samples as &CSV…"), self.export_csv)
        self.act_export_png = self._action(_("Export Plot as &PNG…"), self.export_png)
        self.act_compare_log = self._action(_("Compare with &Log…"), self.compare_with_log, None,
                                            _("A real charge log against the simulation; fit the model to it"))
        self.act_reference = self._action(_("&Command Reference"), self.show_help, K.HelpContents,
                                          _("Help on the command under the cursor"))
        self.act_about = self._action(_("&About ZUML Studio"), self.show_about)

    def install_firmware(self) -> None:
        from .device.firmware_install_dialog import FirmwareInstallDialog
        FirmwareInstallDialog(self).open()

    def _build_menus(self) -> None:
        bar = self.menuBar()
        file_menu = bar.addMenu(_("&File"))
        file_menu.addAction(self.act_new)
        file_menu.addAction(self.act_wizard)
        templates = file_menu.addMenu(_("New from &Template"))
        for path in data.standard_macros():
            templates.addAction(path.stem, lambda p=path: self.new_from_template(p))
        file_menu.addAction(self.act_open)
        self.recent_menu = file_menu.addMenu(_("Open &Recent"))
        file_menu.addAction(self.act_open_log)
        file_menu.addSeparator()
        file_menu.addAction(self.act_save)
        file_menu.addAction(self.act_save_as)
        file_menu.addAction(self.act_export)
        file_menu.addSeparator()
        file_menu.addAction(self.act_quit)
        self._fill_recent()

        edit = bar.addMenu(_("&Edit"))
        undo = self._action(_("&Undo"), lambda: self.editor.undo(), QKeySequence.StandardKey.Undo)
        redo = self._action(_("&Redo"), lambda: self.editor.redo(), "Ctrl+Y")
        redo.setShortcuts([QKeySequence("Ctrl+Y")] + QKeySequence.keyBindings(QKeySequence.StandardKey.Redo))
        self.editor.undoAvailable.connect(undo.setEnabled)
        self.editor.redoAvailable.connect(redo.setEnabled)
        for action in (undo, redo):
            action.setShortcutContext(Qt.ShortcutContext.WidgetShortcut)
            edit.addAction(action)
        edit.addSeparator()
        for action in (self.act_find, self.act_replace, self.act_toggle_comment):
            edit.addAction(action)
        edit.addSeparator()
        edit.addAction(self.act_prefs)

        view = bar.addMenu(_("&View"))
        view.addAction(self.act_visual)
        view.addSeparator()
        for action in (self.act_zoom_in, self.act_zoom_out, self.act_zoom_reset):
            view.addAction(action)
        view.addSeparator()
        for dock in (self.library_dock, self.hex_dock, self.visual_dock, self.problems_dock, self.sim_dock,
                     self.device_dock):
            view.addAction(dock.toggleViewAction())

        sketch = bar.addMenu(_("&Macro"))
        sketch.addAction(self.act_verify)
        sketch.addAction(self.act_upload)

        device = bar.addMenu(_("&Device"))
        for action in (self.act_connect, self.act_disconnect, None, self.act_upload, self.act_start, self.act_stop,
                       None, self.device_dock.toggleViewAction(), None, self.act_install_firmware):
            device.addSeparator() if action is None else device.addAction(action)

        sim = bar.addMenu(_("&Simulate"))
        for action in (self.act_simulate, self.act_cancel_sim):
            sim.addAction(action)
        sim.addSeparator()
        sim.addAction(self.act_export_csv)
        sim.addAction(self.act_export_png)
        sim.addSeparator()
        sim.addAction(self.act_compare_log)

        help_menu = bar.addMenu(_("&Help"))
        help_menu.addAction(self.act_reference)
        help_menu.addAction(self.act_about)

    def _build_toolbar(self) -> None:
        """The Arduino-style row: files, then Verify and Upload, then Simulate."""
        bar = QToolBar(_("Main"), self)
        bar.setObjectName("mainToolBar")
        bar.setMovable(False)
        bar.setToolButtonStyle(Qt.ToolButtonStyle.ToolButtonTextBesideIcon)
        icon = self.style().standardIcon
        P = QStyle.StandardPixmap
        for action, pixmap in ((self.act_new, P.SP_FileIcon), (self.act_open, P.SP_DialogOpenButton),
                               (self.act_save, P.SP_DialogSaveButton), (None, None),
                               (self.act_verify, P.SP_DialogApplyButton), (self.act_upload, P.SP_ArrowUp),
                               (None, None), (self.act_simulate, P.SP_MediaPlay)):
            if action is None:
                bar.addSeparator()
                continue
            action.setIcon(icon(pixmap))
            bar.addAction(action)
            tip = action.statusTip() or action.text().replace("&", "")
            action.setToolTip(f"{tip} ({action.shortcut().toString(QKeySequence.SequenceFormat.NativeText)})"
                              if not action.shortcut().isEmpty() else tip)
        self.addToolBar(Qt.ToolBarArea.TopToolBarArea, bar)
        self.toolbar = bar

    def compare_with_log(self):
        from .sim.compare_dialog import CompareDialog
        def saved() -> None:
            self.sim_panel.form.add_named_batteries()
            self.device_panel.add_named_batteries()

        last = self.sim_panel.result()
        dialog = CompareDialog(self.sim_panel.current_record, self, saved, last.chemistry if last else None)
        dialog.show()
        return dialog

    def _connect(self) -> None:
        self.editor.textChanged.connect(self._text_changed)
        self.editor.fontSizeChanged.connect(self._font_size_changed)
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
        self.autosave(wait=False)   # every debounced change reaches the recovery file, off the GUI thread
        self.editor.set_diagnostics(result.diagnostics)
        self.problems.set_diagnostics(result.diagnostics)
        self.hex_view.show_result(result, self.validator.last_valid)
        self.hex_view.select_line(self.editor.current_line())
        errors = len(result.errors)
        warnings = len(result.diagnostics) - errors
        if result.ok:
            self.size_label.setText(_("{size} / 255 bytes").format(size=len(result.record)))
            self.state_label.setText("✔ " + _("valid") + (", " + ngettext("{n} warning", "{n} warnings", warnings)
                                                           .format(n=warnings) if warnings else ""))
            self.state_label.setStyleSheet(f"color:{theme.colours(self.palette()).ok};")
            self.sim_panel.set_record(result.record, result.macro.name, self._declared(result))
            if self._device_panel is not None:      # else it is given the record when it is built
                self._device_panel.macro_changed(result.record)
        else:
            self.size_label.setText(_("– / 255 bytes"))
            self.state_label.setText("✖ " + ngettext("{n} error", "{n} errors", errors).format(n=errors))
            self.state_label.setStyleSheet(f"color:{theme.colours(self.palette()).error};")
            self.sim_panel.set_record(None)
        # The counts by sign, not in words: the dock is narrow and its title cannot wrap.
        self.problems_dock.setWindowTitle(_("Problems") + (f"  ✖ {errors}  ⚠ {warnings}" if result.diagnostics else ""))

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
        """What Compile & Flash writes: the editor's macro, checked now (never stale bytes). A macro
        whose only errors are the safety lint's still gives its bytes: the Device panel's safety
        check then names the danger and asks before writing them."""
        result = self.validate_now()
        if result.ok:
            return result.record, result.macro.name
        if result.macro is not None and result.errors and all(d.code.startswith("E3") for d in result.errors):
            forced = compile_source(self.text(), unsafe_ok=True)
            if forced.ok:
                return forced.record, forced.macro.name
        return None

    def _cursor_moved(self) -> None:
        cursor = self.editor.textCursor()
        self.pos_label.setText(_("Ln {line}, Col {column}").format(line=cursor.blockNumber() + 1,
                                                                   column=cursor.positionInBlock() + 1))

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

    def _visual_shown(self, visible: bool) -> None:
        """At 1366x768 the right-hand docks are a strip over the simulator with room for no card:
        while the Visual tab is in front it borrows height from the dock below (enough for
        several cards), and gives it back when it leaves, so the live plot and the simulator
        are not left squeezed."""
        borrowed, self._borrowed = self._borrowed, None
        if not visible:
            if borrowed is not None:
                dock, height = borrowed
                if dock.isVisible() and not dock.isFloating():
                    self.resizeDocks([dock], [height], Qt.Orientation.Vertical)
            return
        missing = VISUAL_MIN_HEIGHT - self.visual_dock.height()
        below = [d for d in (self.sim_dock, self.device_dock, self.problems_dock) if d.isVisible()
                 and not d.isFloating() and self.dockWidgetArea(d) == Qt.DockWidgetArea.BottomDockWidgetArea]
        if missing > 0 and below and not self.visual_dock.isFloating():
            self._borrowed = (below[0], below[0].height())
            self.resizeDocks(below[:1], [max(1, below[0].height() - missing)], Qt.Orientation.Vertical)

    def show_visual(self) -> None:
        self.visual_dock.show()
        self.visual_dock.raise_()

    def open_dialog(self) -> None:
        if not self.maybe_save():
            return
        start = text_value(self.settings, "lastDir", str(self.user_macros))
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
        from .logs import LogWindow      # the viewer's modules load only when a log is wanted
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

    def ask_close_run(self) -> str:
        """A macro runs on the charger: 'stop', 'leave' or 'cancel' (tests replace this)."""
        from .device.confirm_dialogs import ask_close_during_run
        panel = self.device_panel
        return ask_close_during_run(self, panel.run_name(), panel.connection.virtual_device is not None)

    def closeEvent(self, event) -> None:
        if not self.maybe_save():
            event.ignore()
            return
        if self._device_panel is not None and self._device_panel.is_running():
            answer = self.ask_close_run()
            if answer == "cancel":
                event.ignore()
                return
            if answer == "stop" and not self.device_panel.stop_and_wait():
                self.statusBar().showMessage(_("The charger did not confirm the stop: check it."), 10000)
        self.sim_panel.cancel()
        if self._device_panel is not None:
            self._device_panel.shutdown()
        self._saver.discard(self._recovery_key)
        self._saver.close()
        self.settings.setValue("lastOpen", self.path or "")
        self.settings.setValue("geometry", self.saveGeometry())
        self.settings.setValue("windowState", self.saveState(LAYOUT_VERSION))
        self.settings.sync()
        event.accept()

    def _restore_layout(self) -> None:
        """The saved geometry if it fits the screen now (it may be a smaller or scaled one),
        else a size made for the screen; then the docks' layout."""
        available = self.screen().availableGeometry()
        geometry = bytes_value(self.settings, "geometry")
        if geometry is None or not self.restoreGeometry(geometry) or not fits(self.frameGeometry(), available):
            self.setGeometry(first_geometry(available))
        state = bytes_value(self.settings, "windowState")
        if state is not None:
            self.restoreState(state, LAYOUT_VERSION)

    def reopen_last(self) -> bool:
        """At start without a file: the file open when the window last closed, if it is still there."""
        last = text_value(self.settings, "lastOpen", "")
        if not last or not Path(last).is_file():
            return False
        return self.open_file(last, ask=False)

    # -- messages and help ----------------------------------------------------------------
    def show_error(self, message: str) -> None:
        """Non-modal: an error never blocks the window (nor a test)."""
        self.statusBar().showMessage(message, 8000)
        box = QMessageBox(QMessageBox.Icon.Warning, APP_NAME, message, QMessageBox.StandardButton.Ok, self)
        box.setObjectName("errorBox")
        box.setAttribute(Qt.WidgetAttribute.WA_DeleteOnClose)
        box.open()

    def show_help(self) -> None:
        """F1: the command reference, at the command under the cursor."""
        cursor = self.editor.textCursor()
        if self._help is None:
            self._help = HelpBrowser(self)
        self._help.show_ops(ops_at(cursor.block().text(), cursor.positionInBlock()))
        self._help.show()
        self._help.raise_()
        self._help.search.setFocus()

    def about_text(self) -> str:
        from importlib.metadata import version      # 15 ms to import: not before the first paint

        return (f"ZUML Studio {version('zuml-studio')}\n\n"
                + _("Write, check, simulate and flash ZUML 2.0 charger macros."))

    def show_about(self) -> None:
        QMessageBox.about(self, APP_NAME, self.about_text())

    # -- preferences and zoom --------------------------------------------------------------
    def apply_preferences(self, prefs: Preferences) -> None:
        self.prefs = prefs
        theme.apply_theme(prefs.theme)
        if prefs.font_size:
            self.editor.set_font_size(prefs.font_size)

    def show_preferences(self) -> None:
        dialog = PreferencesDialog(self.prefs, self.editor.font_size(), self)
        if dialog.exec():
            self.set_preferences(dialog.chosen())

    def set_preferences(self, chosen: Preferences) -> None:
        """Keep and apply what the Preferences dialog chose; a new language needs a restart,
        which is offered."""
        language_changed = chosen.language != self.prefs.language
        chosen.save(self.settings)
        self.apply_preferences(chosen)
        if language_changed and self.ask_restart():
            self.restart()

    def ask_restart(self) -> bool:
        """The language applies at the next start: whether to restart now (tests replace this)."""
        box = QMessageBox(QMessageBox.Icon.Information, APP_NAME,
                          _("The new language applies when ZUML Studio starts again."), QMessageBox.StandardButton.NoButton,
                          self)
        now = box.addButton(_("Restart Now"), QMessageBox.ButtonRole.AcceptRole)
        box.addButton(_("Later"), QMessageBox.ButtonRole.RejectRole)
        box.exec()
        return box.clickedButton() is now

    def restart(self) -> bool:
        """Close (asking about unsaved work as always), then start again; False if the user
        kept the window open or the new process could not start."""
        self.settings.sync()
        if not self.close():
            return False
        if not restart():
            QMessageBox.warning(None, APP_NAME, _("ZUML Studio could not start again: start it yourself."))
            return False
        return True

    def reset_zoom(self) -> None:
        self.prefs.font_size = 0
        self.prefs.save(self.settings)
        self.editor.set_font_size(self.editor.default_font_size())

    def _font_size_changed(self, points: int) -> None:
        self.prefs.font_size = points
        self.prefs.save(self.settings)

    def changeEvent(self, event) -> None:  # noqa: N802
        super().changeEvent(event)
        if event.type() == QEvent.Type.PaletteChange and self.validator.last is not None:
            self._validated(self.validator.last)       # the status colours of the new palette

    # -- Arduino-style actions -------------------------------------------------------------
    def verify(self) -> bool:
        """Ctrl+R: check and compile now; the result in the status bar and the Problems list."""
        result = self.validate_now()
        errors = len(result.errors)
        warnings = len(result.diagnostics) - errors
        if result.ok:
            message = _("Verified: {size} of 255 bytes").format(size=len(result.record))
            if warnings:
                message += ", " + ngettext("{n} warning", "{n} warnings", warnings).format(n=warnings)
        else:
            message = _("Not verified: {errors}").format(
                errors=ngettext("{n} error", "{n} errors", errors).format(n=errors))
            self.problems_dock.show()
            self.problems_dock.raise_()
        self.statusBar().showMessage(message, 8000)
        return result.ok

    def upload(self) -> None:
        """Ctrl+U: the device panel's Compile & Flash, connecting to the chosen charger first."""
        self.device_dock.show()
        self.device_dock.raise_()
        if not self.verify():
            return
        if self.device_panel.is_connected():
            self.device_panel.flash()
        elif self.device_panel.connect_to():
            self._upload_pending = True

    def _device_connected(self, connected: bool) -> None:
        pending, self._upload_pending = self._upload_pending, False
        if connected and pending:
            self.device_panel.flash()

    def _device_call(self, method) -> None:
        self.device_dock.show()
        self.device_dock.raise_()
        method()
