"""The main window's commands as one table: each row is an action (its text, what it calls,
its keys, its tip) and the menus it stands in. A new command is one row; ``build_menus``
places it (a group number change in a menu puts a separator before it)."""
from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from PySide6.QtCore import Qt
from PySide6.QtGui import QAction, QActionGroup, QKeySequence
from PySide6.QtWidgets import QMainWindow, QMenu, QToolBar

from ...i18n import _
from .icons import toolbar_icon

K = QKeySequence.StandardKey
Keys = str | QKeySequence.StandardKey | tuple | None


@dataclass(frozen=True)
class ActionSpec:
    name: str                              # the window's attribute ``act_<name>``
    text: str
    slot: Callable[[Any], object]          # called with the window
    keys: Keys = None                      # one key, or a tuple: the first is the one menus show
    tip: str = ""
    menus: tuple[str, ...] = ()            # "menu" or "menu:group"; group 0 when not given
    icon: str = ""                         # a toolbar icon's name (``icons.toolbar_icon``): on the toolbar
    everywhere: bool = False               # the keys work in every window of the application (floating docks)


def action_specs() -> list[ActionSpec]:
    """Every command of the window, in menu order (texts translated when called)."""
    return [
        ActionSpec("new", _("&New"), lambda w: w.new_file(), K.New, _("A new macro"), ("file",), "new"),
        ActionSpec("wizard", _("New from &Wizard…"), lambda w: w.new_from_wizard(), "Ctrl+Shift+N",
                   _("Answer a few questions about the battery"), ("file",)),
        ActionSpec("open", _("&Open…"), lambda w: w.open_dialog(), K.Open, menus=("file",), icon="open"),
        ActionSpec("open_log", _("Open &Log…"), lambda w: w.open_log(), "Ctrl+L",
                   _("View a charger's log file: iCharger, LogView, DataExplorer, session CSV"), ("file",)),
        ActionSpec("save", _("&Save"), lambda w: w.save(), K.Save, _("Save the macro (a standard macro: as a copy)"),
                   ("file:1",), "save"),
        ActionSpec("save_as", _("Save &As…"), lambda w: w.save_as(), K.SaveAs, menus=("file:1",)),
        ActionSpec("export", _("Export &Byte Record…"), lambda w: w.export_record(), "Ctrl+Shift+E",
                   _("Write the compiled record (.bin)"), ("file:1",)),
        ActionSpec("quit", _("&Quit"), lambda w: w.close(), K.Quit, menus=("file:2",)),

        ActionSpec("undo", _("&Undo"), lambda w: w.editor.undo(), K.Undo, menus=("edit",)),
        ActionSpec("redo", _("&Redo"), lambda w: w.editor.redo(), ("Ctrl+Y", K.Redo), menus=("edit",)),
        ActionSpec("find", _("&Find…"), lambda w: w.editor.show_find(False), K.Find, menus=("edit:1",)),
        # Ctrl+H, which the editor also handles: the platform's Replace key is empty on some desktops.
        ActionSpec("replace", _("&Replace…"), lambda w: w.editor.show_find(True), "Ctrl+H", menus=("edit:1",)),
        ActionSpec("toggle_comment", _("Toggle &Comment"), lambda w: w.editor.toggle_comment(), "Ctrl+/",
                   menus=("edit:1",)),
        ActionSpec("prefs", _("&Preferences…"), lambda w: w.show_preferences(), (K.Preferences, "Ctrl+,"),
                   menus=("edit:2",)),

        ActionSpec("mode_write", _("&Write Mode"), lambda w: w.switch_mode("write"), "Ctrl+1",
                   _("The editor in front, with the library, the bytes and the problems"), ("view",)),
        ActionSpec("mode_simulate", _("S&imulate Mode"), lambda w: w.switch_mode("simulate"), "Ctrl+2",
                   _("The simulator's plot takes the window"), ("view",)),
        ActionSpec("mode_charge", _("C&harge Mode"), lambda w: w.switch_mode("charge"), "Ctrl+3",
                   _("The charger's live plot and controls take the window"), ("view",)),
        ActionSpec("reset_layout", _("Reset &Layout"), lambda w: w.switch_mode(None), None,
                   _("This mode's panels back where they started"), ("view",)),
        ActionSpec("visual", _("&Visual Editor"), lambda w: w.show_visual(), "Ctrl+Shift+V", menus=("view:1",)),
        ActionSpec("zoom_in", _("Zoom &In"), lambda w: w.editor.zoom(1), ("Ctrl+=", "Ctrl++"), menus=("view:2",)),
        ActionSpec("zoom_out", _("Zoom &Out"), lambda w: w.editor.zoom(-1), "Ctrl+-", menus=("view:2",)),
        ActionSpec("zoom_reset", _("&Reset Zoom"), lambda w: w.reset_zoom(), "Ctrl+0", menus=("view:2",)),

        ActionSpec("verify", _("&Verify"), lambda w: w.verify(), "Ctrl+R", _("Check and compile the macro"),
                   ("macro",), "verify"),
        ActionSpec("upload", _("&Upload"), lambda w: w.upload(), "Ctrl+U",
                   _("Compile & Flash the macro to the charger (connecting first if needed)"),
                   ("macro", "device:1"), "upload"),

        ActionSpec("connect", _("&Connect"), lambda w: w.device_call(lambda p: p.connect_to()), menus=("device",)),
        ActionSpec("disconnect", _("&Disconnect"), lambda w: w.device_call(lambda p: p.disconnect()),
                   menus=("device",)),
        ActionSpec("start", _("&Start the Macro"), lambda w: w.device_call(lambda p: p.start()), menus=("device:1",)),
        ActionSpec("stop", _("S&top the Charger"), lambda w: w.emergency_stop(), ("Shift+Esc", "Ctrl+Shift+T"),
                   _("Stop the charger now, from any tab or window"), ("device:1",), everywhere=True),
        ActionSpec("serial_monitor", _("Serial &Monitor"), lambda w: w.show_serial_monitor(), "Ctrl+Shift+M",
                   _("The port's raw bytes as text or hex, and a line to send"), ("device:2",)),
        ActionSpec("install_firmware", _("&Install Firmware on an iMAX B6…"), lambda w: w.install_firmware(),
                   tip=_("Save the charger's original, then write the ZUML firmware"), menus=("device:3",)),

        ActionSpec("simulate", _("&Simulate"), lambda w: w.sim_panel.simulate(), "F5", menus=("simulate",),
                   icon="simulate"),
        ActionSpec("cancel_sim", _("&Cancel Simulation"), lambda w: w.sim_panel.cancel(), "Shift+F5",
                   menus=("simulate",)),
        ActionSpec("export_csv", _("Export Samples as &CSV…"), lambda w: w.export_csv(), menus=("simulate:1",)),
        ActionSpec("export_png", _("Export Plot as &PNG…"), lambda w: w.export_png(), menus=("simulate:1",)),
        ActionSpec("compare_log", _("Compare with &Log…"), lambda w: w.compare_with_log(), None,
                   _("A real charge log against the simulation; fit the model to it"), ("simulate:2",)),

        ActionSpec("reference", _("&Command Reference"), lambda w: w.show_help(), K.HelpContents,
                   _("Help on the command under the cursor"), ("help",)),
        ActionSpec("about", _("&About ZUML Studio"), lambda w: w.show_about(), menus=("help",)),
    ]


def menu_titles() -> dict[str, str]:
    """The menu bar, in order: a row's menu key -> its title."""
    return {"file": _("&File"), "edit": _("&Edit"), "view": _("&View"), "macro": _("&Macro"),
            "device": _("&Device"), "simulate": _("&Simulate"), "help": _("&Help")}


TOOLBAR = ("new", "open", "save", None, "verify", "upload", None, "simulate")     # None: a separator


def _key_list(keys: Keys) -> list[QKeySequence]:
    out: list[QKeySequence] = []
    for key in keys if isinstance(keys, tuple) else (keys,):
        if key is None:
            continue
        found = QKeySequence.keyBindings(key) if isinstance(key, QKeySequence.StandardKey) else [QKeySequence(key)]
        out += [k for k in found if not k.isEmpty() and k not in out]
    return out


def build_actions(window: QMainWindow, specs: list[ActionSpec]) -> dict[str, QAction]:
    """One QAction per row, set on the window as ``act_<name>``."""
    made: dict[str, QAction] = {}
    for spec in specs:
        action = QAction(spec.text, window)
        action.setObjectName(f"act_{spec.name}")
        action.setShortcuts(_key_list(spec.keys))
        if spec.tip:
            action.setStatusTip(spec.tip)
        if spec.everywhere:
            action.setShortcutContext(Qt.ShortcutContext.ApplicationShortcut)
            window.addAction(action)            # its keys work while its menu is closed, whatever has focus
        action.triggered.connect(lambda _checked=False, s=spec: s.slot(window))
        setattr(window, f"act_{spec.name}", action)
        made[spec.name] = action
    modes = QActionGroup(window)
    for name in ("mode_write", "mode_simulate", "mode_charge"):
        made[name].setCheckable(True)
        modes.addAction(made[name])
    return made


def _menu_place(entry: str) -> tuple[str, int]:
    menu, _sep, group = entry.partition(":")
    return menu, int(group or 0)


def build_menus(window: QMainWindow, specs: list[ActionSpec], actions: dict[str, QAction]) -> dict[str, QMenu]:
    """The menu bar from the table; the menus, by key, for what the window adds itself (the
    templates, the recent files, the docks' toggles)."""
    menus = {key: window.menuBar().addMenu(title) for key, title in menu_titles().items()}
    last_group: dict[str, int] = {}
    for spec in specs:
        for entry in spec.menus:
            key, group = _menu_place(entry)
            if key in last_group and last_group[key] != group:
                menus[key].addSeparator()
            last_group[key] = group
            menus[key].addAction(actions[spec.name])
    return menus


def build_toolbar(window: QMainWindow, actions: dict[str, QAction], specs: list[ActionSpec]) -> QToolBar:
    """The Arduino-style row: files, then Verify and Upload, then Simulate; icons drawn in the
    palette's text colour (``refresh_icons`` after a theme change)."""
    bar = QToolBar(_("Main"), window)
    bar.setObjectName("mainToolBar")
    bar.setMovable(False)
    bar.setToolButtonStyle(Qt.ToolButtonStyle.ToolButtonTextBesideIcon)
    for name in TOOLBAR:
        if name is None:
            bar.addSeparator()
            continue
        action = actions[name]
        bar.addAction(action)
        tip = action.statusTip() or action.text().replace("&", "")
        key = action.shortcut()
        action.setToolTip(f"{tip} ({key.toString(QKeySequence.SequenceFormat.NativeText)})" if not key.isEmpty()
                          else tip)
    refresh_icons(window, actions, specs)
    window.addToolBar(Qt.ToolBarArea.TopToolBarArea, bar)
    return bar


def refresh_icons(window: QMainWindow, actions: dict[str, QAction], specs: list[ActionSpec]) -> None:
    """The toolbar's icons in the window's current palette (readable on light and dark)."""
    for spec in specs:
        if spec.icon:
            actions[spec.name].setIcon(toolbar_icon(spec.icon, window.palette()))
