"""ZUML Studio's main window: the editor in the centre, the library on the left, the bytes on
the right, problems and the simulator below, in one of three modes (Write, Simulate, Charge).
It builds itself from its parts (the other modules of ``ui/window/``: the actions and menus, the docks, the modes,
a maximised plot, the document's files) and wires the panels together."""
from __future__ import annotations

from pathlib import Path

from PySide6.QtCore import QEvent, QSettings, Qt, QTimer, Signal
from PySide6.QtWidgets import QLabel, QMainWindow, QMessageBox

from ... import data
from ...i18n import _, ngettext
from ...lang import opcodes as ops
from ...lang.compiler import CompileResult, compile_source
from ...recovery import BackgroundSaver, RecoveryStore
from ...user_dirs import config_dir
from ..base import theme
from ..editor.code_editor import EditorWithFind
from ..editor.highlighter import ops_at
from ..editor.help_browser import HelpBrowser
from ..editor.hex_view import HexView
from ..editor.library import LibraryBrowser
from ..packs import bind_live_runs, install_packs_dock
from .preferences import Preferences, PreferencesDialog
from ..editor.problems import ProblemsView
from ..base.settings_values import bytes_value
from ..sim.sim_panel import SimulatorPanel
from ..editor.validation import Validator
from ..visual import VisualEditor
from . import actions as window_actions
from .docks import CHARGE, WRITE, build_docks, dock_specs, make_readable, place, width_changed_place
from .documents import APP_NAME, EMPTY_MACRO, DocumentFiles
from .modes import Modes
from .plot_focus import PlotFocus
from ..base.window_geometry import first_geometry, fits, saved_frame

DEVICE_PANEL_DELAY_MS = 300      # built after the first paint: its tab is not the one in front
VISUAL_MIN_HEIGHT = 440          # the Visual tab, when shown, takes this much height from the docks below
EDITOR_MIN_WIDTH = 340           # ... and the width for its two sections from the editor, down to this
LAYOUT_VERSION = 6      # raise when docks or toolbars are added or removed: an older saved layout is then ignored


class MainWindow(DocumentFiles, QMainWindow):
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
        self.file = None
        self._untitled = 0
        self._recovery_key = ""
        self._help: HelpBrowser | None = None
        self._upload_pending = False
        self._monitor = None             # the serial monitor, made on first use
        self.restart_wanted = False      # closed by Restart Now: the application builds the window again
        self._borrowed = None        # (dock, height) the Visual tab borrowed height from
        self._borrowed_width = None  # the right-hand docks' width before the Visual tab widened them
        self.prefs = Preferences.load(self.settings)

        self._build_widgets()
        self._build_commands()
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

        self.dock_specs = dock_specs()
        self.docks = build_docks(self, self.dock_specs)
        self.visual_dock.visibilityChanged.connect(self._visual_shown)
        self.device_dock.visibilityChanged.connect(lambda visible: visible and self.device_panel)
        QTimer.singleShot(DEVICE_PANEL_DELAY_MS, self, lambda: self.isVisible() and self.device_panel)
        self.modes = Modes(self, self.settings, self.editor_box,
                           lambda mode: place(self, self.dock_specs, self.docks, mode), LAYOUT_VERSION,
                           lambda: make_readable(self, self.dock_specs, self.docks))
        self.plot_focus = PlotFocus(self, self.editor_box)
        # A dock placed by the window's width (Problems: beside the simulator, or its tab when the
        # window is too narrow) moves when the window crosses that width, or when a mode's layout
        # saved at another width comes back: the mode's first layout at this width.
        self._refit = QTimer(self, singleShot=True, interval=0)
        self._refit.timeout.connect(self._refit_docks)
        self.modes.changed.connect(lambda _mode: self._refit.start())
        self.plot_focus.watch(self.sim_panel.plot, self.sim_dock)
        install_packs_dock(self)
        self.statusBar().messageChanged.connect(self._status_while_hidden)

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
            from ..device.device_panel import DevicePanel

            panel = DevicePanel(self._current_record, self.config / "sessions")
            panel.statusMessage.connect(lambda message: self.statusBar().showMessage(message, 6000))
            panel.connectedChanged.connect(self._device_connected)
            panel.startFinished.connect(self._watch_started_run)
            self._device_panel = panel
            self.live_runs = bind_live_runs(self, panel)
            self.device_dock.setWidget(panel)
            self.plot_focus.watch(panel.plot, self.device_dock, keep=(panel.readings,))
            if self.validator.last_valid is not None:
                panel.macro_changed(self.validator.last_valid.record)
        return self._device_panel

    def _build_commands(self) -> None:
        """The actions, menus and toolbar from their table (``window/actions.py``), then what the
        window adds to the menus itself: the templates, the recent files, each dock's toggle."""
        self.action_specs = window_actions.action_specs()
        self.actions_by_name = window_actions.build_actions(self, self.action_specs)
        menus = window_actions.build_menus(self, self.action_specs, self.actions_by_name)
        self.menus = menus
        for name in ("undo", "redo"):          # the editor's own keys do it; the menu shows them
            self.actions_by_name[name].setShortcutContext(Qt.ShortcutContext.WidgetShortcut)
        self.editor.undoAvailable.connect(self.act_undo.setEnabled)
        self.editor.redoAvailable.connect(self.act_redo.setEnabled)

        file_menu = menus["file"]
        templates = file_menu.insertMenu(self.act_open, file_menu.addMenu(_("New from &Template")))
        template_menu = templates.menu()
        for path in data.standard_macros():
            template_menu.addAction(path.stem, lambda p=path: self.new_from_template(p))
        self.recent_menu = file_menu.addMenu(_("Open &Recent"))
        file_menu.insertMenu(self.act_open_log, self.recent_menu)
        self._fill_recent()

        view = menus["view"]
        view.insertSeparator(self.act_visual)
        view.addSeparator()
        for dock in self.docks.values():
            view.addAction(dock.toggleViewAction())
        view.addAction(self.plot_focus.back)
        menus["device"].addSeparator()
        menus["device"].addAction(self.device_dock.toggleViewAction())
        self.modes.changed.connect(lambda mode: self.actions_by_name[f"mode_{mode}"].setChecked(True))
        self.toolbar = window_actions.build_toolbar(self, self.actions_by_name, self.action_specs)

    def install_firmware(self) -> None:
        from ..device.firmware_install_dialog import FirmwareInstallDialog
        FirmwareInstallDialog(self).open()

    def compare_with_log(self):
        from ..sim.compare_dialog import CompareDialog
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
        last_valid = self.validator.last_valid
        self.problems.set_diagnostics(result.diagnostics, [] if result.ok or last_valid is None
                                      else last_valid.warnings)
        self.hex_view.show_result(result, self.validator.last_valid)
        self.hex_view.select_line(self.editor.current_line())
        errors, warnings = len(result.errors), len(result.warnings)
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
        notes = len(result.diagnostics) - errors - warnings
        self.problems_dock.setWindowTitle(_("Problems") + (f"  ✖ {errors}  ⚠ {warnings}" if result.diagnostics else "")
                                          + (f"  ℹ {notes}" if notes else ""))

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

    def _visual_shown(self, visible: bool) -> None:
        """At 1366x768 the right-hand docks are a strip over the simulator with room for no card:
        while the Visual tab is in front it borrows height from the dock below (enough for
        several cards), and gives it back when it leaves, so the live plot and the simulator
        are not left squeezed."""
        borrowed, self._borrowed = self._borrowed, None
        width, self._borrowed_width = self._borrowed_width, None
        if not visible:
            if borrowed is not None:
                dock, height = borrowed
                if dock.isVisible() and not dock.isFloating():
                    self.resizeDocks([dock], [height], Qt.Orientation.Vertical)
            if width is not None and self.hex_dock.isVisible() and not self.hex_dock.isFloating():
                self.resizeDocks([self.hex_dock], [width], Qt.Orientation.Horizontal)
            return
        # The two sections side by side (docs/gui.md): the width they lack comes from the editor,
        # which keeps EDITOR_MIN_WIDTH; given back when the tab leaves.
        wider = min(self.visual.side_by_side_missing(), self.editor_box.width() - EDITOR_MIN_WIDTH)
        if wider > 0 and not self.visual_dock.isFloating() and self.editor_box.isVisible():
            self._borrowed_width = self.visual_dock.width()
            self.resizeDocks([self.visual_dock], [self.visual_dock.width() + wider], Qt.Orientation.Horizontal)
        missing = VISUAL_MIN_HEIGHT - self.visual_dock.height()
        below = [d for d in (self.sim_dock, self.device_dock, self.problems_dock) if d.isVisible()
                 and not d.isFloating() and self.dockWidgetArea(d) == Qt.DockWidgetArea.BottomDockWidgetArea]
        if missing > 0 and below and not self.visual_dock.isFloating():
            self._borrowed = (below[0], below[0].height())
            self.resizeDocks(below[:1], [max(1, below[0].height() - missing)], Qt.Orientation.Vertical)

    def resizeEvent(self, event) -> None:
        super().resizeEvent(event)
        self._refit_docks()             # now: what a test or the user sees after a resize is the layout

    def _refit_docks(self) -> None:
        if self.plot_focus.maximised() is None and width_changed_place(self, self.dock_specs, self.docks):
            place(self, self.dock_specs, self.docks, self.modes.current)

    def switch_mode(self, mode: str | None) -> None:
        """View > a mode (None: Reset Layout). A maximised plot is put back first: its layout is not
        one the mode should keep."""
        self.plot_focus.restore()
        if mode is None:
            self.modes.reset()
        else:
            self.modes.switch(mode)

    def show_visual(self) -> None:
        self.visual_dock.show()
        self.visual_dock.raise_()

    def ask_close_run(self) -> str:
        """A macro runs on the charger: 'stop', 'leave' or 'cancel' (tests replace this)."""
        from ..device.confirm_dialogs import ask_close_during_run
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
        if self._monitor is not None:
            self._monitor.close_port()
        if self._device_panel is not None:
            self._device_panel.shutdown()
        self._saver.discard(self._recovery_key)
        self._saver.close()
        self.settings.setValue("lastOpen", self.path or "")
        self.settings.setValue("geometry", self.saveGeometry())
        self.plot_focus.restore()
        self.modes.save()
        self.settings.sync()
        event.accept()

    def _restore_layout(self) -> None:
        """The saved geometry if it fits the screen now (it may be a smaller or scaled one),
        else a size made for the screen; then the mode it closed in, with its docks' layout."""
        available = self.screen().availableGeometry()
        geometry = bytes_value(self.settings, "geometry")
        frame = saved_frame(geometry) if geometry is not None else None
        if (geometry is None or frame is None or not fits(frame, available) or not self.restoreGeometry(geometry)
                or not fits(self.frameGeometry(), available)):
            self.setGeometry(first_geometry(available))
        self.modes.restore()

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
        """Close (asking about unsaved work as always) and ask to be built again: the application's
        loop (``app.run_windows``) then installs the new language and opens a new window with the
        same file, in this process (a new process showed an empty window for seconds while it loaded,
        and left the terminal it was started from). False if the user kept the window open."""
        self.settings.sync()
        self.restart_wanted = True
        if not self.close():
            self.restart_wanted = False
            return False
        return True

    def reset_zoom(self) -> None:
        self.prefs.font_size = 0
        self.prefs.save(self.settings)
        self.editor.set_font_size(self.editor.default_font_size())

    def _font_size_changed(self, points: int) -> None:
        self.prefs.font_size = points
        self.prefs.save(self.settings)

    def changeEvent(self, event) -> None:
        super().changeEvent(event)
        if event.type() == QEvent.Type.PaletteChange and hasattr(self, "toolbar"):
            window_actions.refresh_icons(self, self.actions_by_name, self.action_specs)
        if event.type() == QEvent.Type.PaletteChange and self.validator.last is not None:
            self._validated(self.validator.last)       # the status colours of the new palette

    # -- Arduino-style actions -------------------------------------------------------------
    def verify(self) -> bool:
        """Ctrl+R: check and compile now; the result in the status bar and the Problems list."""
        result = self.validate_now()
        errors, warnings = len(result.errors), len(result.warnings)
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
            from ..device.unsafe_dialog import upload_refusal
            self.device_panel.show_message(upload_refusal(self.validate_now().errors), "error")
            return
        if self.device_panel.is_connected():
            self.device_panel.flash()
        elif self.device_panel.connect_to():
            self._upload_pending = True

    def _watch_started_run(self, ok: bool, _text: str) -> None:
        """A run started from the Write mode: the Charge mode, where its curve can be read (in the
        Write mode the live plot is a strip under the editor, a few pixels high beside the Visual tab).
        A floating Device window is the user's own layout: it stays."""
        if ok and self.modes.current == WRITE and not self.device_dock.isFloating():
            self.modes.switch(CHARGE)
            self.device_panel.show_message(self.device_panel.message_text() + "\n"
                                           + _("The Charge mode shows the run (View ▸ Write goes back)."), "ok")

    def _device_connected(self, connected: bool) -> None:
        pending, self._upload_pending = self._upload_pending, False
        if connected and pending:
            self.device_panel.flash()

    def device_call(self, method) -> None:
        """A Device menu command: the Device tab in front, then ``method(panel)``."""
        self.device_dock.show()
        self.device_dock.raise_()
        method(self.device_panel)

    def show_serial_monitor(self):
        """Device ▸ Serial Monitor: the raw bytes of the port the Device panel shows (off while the
        panel is connected to it)."""
        if self._monitor is None:
            from ..device.serial_monitor import SerialMonitor

            panel = self.device_panel
            self._monitor = SerialMonitor(lambda: (panel.ports.target(), panel.ports.baudrate()),
                                          panel.is_connected, self)
            panel.connectedChanged.connect(lambda _connected: self._monitor.refresh())
            panel.ports.changed.connect(self._monitor.refresh)
        self._monitor.refresh()
        self._monitor.show()
        self._monitor.raise_()
        return self._monitor

    def _status_while_hidden(self, text: str) -> None:
        """The Charge mode hides the status line: what it says goes to the device panel's message line."""
        panel = self._device_panel
        if text and not self.statusBar().isVisible() and panel is not None and panel.message_text() != text:
            panel.message.say(text, "info")

    def emergency_stop(self) -> None:
        """Shift+Esc from any tab or window: STOP to the charger at once, without moving a panel
        (a charge may be watched in the Simulate mode or a floating dock)."""
        if self._device_panel is None or not self._device_panel.is_connected():
            self.statusBar().showMessage(_("Stop: no charger is connected."), 6000)
            return
        self._device_panel.stop()
        self.statusBar().showMessage(_("Stop sent to the charger."), 6000)
