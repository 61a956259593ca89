"""The main window's docks as one table: each row names a dock, the widget it holds, where it
starts and in which modes it shows. A new dock is one row (``dock_specs``); the View menu lists
it, each mode's first layout places it, and saved layouts keep it."""
from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from PySide6.QtCore import Qt
from PySide6.QtWidgets import QDockWidget, QMainWindow, QToolBar, QWidget

from ...i18n import _

Area = Qt.DockWidgetArea
WRITE, SIMULATE, CHARGE = "write", "simulate", "charge"
MODES = (WRITE, SIMULATE, CHARGE)


@dataclass(frozen=True)
class DockSpec:
    name: str                               # the window's attribute ``<name>_dock``
    object_name: str                        # the key of its place in saved layouts: never change it
    title: str
    widget: Callable[[Any], QWidget]        # called with the window
    area: Area
    modes: tuple[str, ...] = (WRITE,)       # the modes whose first layout shows it
    beside: str = ""                        # side by side with this dock (a dock listed before it)
    tab_with: str = ""                      # a tab beside this dock (a dock listed before it)
    width: int = 0                          # its first width, px (0: as the window's layout gives)
    height: int = 0                         # its first height, px
    narrow_tab_with: str = ""               # a tab beside this dock instead, when the window leaves it
    readable_width: int = 0                 # less than this width beside its neighbours (px)


PROBLEMS_READABLE_PX = 240     # a message of the Problems list reads a few words a line, its place and code beside
SEPARATOR_PX = 12              # the splitter between two docks side by side, and the area's margins


def dock_specs() -> list[DockSpec]:
    """Every dock of the window (titles translated when called). The first of a set of tabs is
    the one in front."""
    return [
        DockSpec("library", "libraryDock", _("Library"), lambda w: w.library, Area.LeftDockWidgetArea, width=230),
        DockSpec("hex", "hexDock", _("Bytes"), lambda w: w.hex_view, Area.RightDockWidgetArea, width=420),
        DockSpec("visual", "visualDock", _("Visual"), lambda w: w.visual, Area.RightDockWidgetArea, tab_with="hex"),
        # Beside the simulator it reads a message a few words a line; a window too narrow for that
        # beside the device panel (a 1024 px screen) makes it a tab of the simulator's set instead.
        DockSpec("problems", "problemsDock", _("Problems"), lambda w: w.problems, Area.BottomDockWidgetArea,
                 width=330, narrow_tab_with="sim", readable_width=PROBLEMS_READABLE_PX),
        DockSpec("sim", "simulatorDock", _("Simulator"), lambda w: w.sim_panel, Area.BottomDockWidgetArea,
                 (WRITE, SIMULATE), beside="problems", width=1170, height=400),
        DockSpec("device", "deviceDock", _("Device"), lambda w: QWidget(), Area.BottomDockWidgetArea,
                 (WRITE, CHARGE), tab_with="sim"),
        DockSpec("packs", "packsDock", _("Packs"), lambda w: QWidget(), Area.BottomDockWidgetArea,
                 (WRITE,), tab_with="sim"),
    ]


def build_docks(window: QMainWindow, specs: list[DockSpec]) -> dict[str, QDockWidget]:
    """One dock per row, set on the window as ``<name>_dock``; the mode places them (``place``), once:
    a second tabifying before the window is shown leaves Qt's first tab bar behind, shown with the
    window at its corner."""
    docks: dict[str, QDockWidget] = {}
    for spec in specs:
        dock = QDockWidget(spec.title, window)
        dock.setObjectName(spec.object_name)
        dock.setWidget(spec.widget(window))
        dock.setFeatures(QDockWidget.DockWidgetFeature.DockWidgetMovable |
                         QDockWidget.DockWidgetFeature.DockWidgetFloatable |
                         QDockWidget.DockWidgetFeature.DockWidgetClosable)
        window.addDockWidget(spec.area, dock)
        setattr(window, f"{spec.name}_dock", dock)
        docks[spec.name] = dock
    return docks


def tab_of(window: QMainWindow, specs: list[DockSpec], docks: dict[str, QDockWidget], spec: DockSpec) -> str:
    """The dock ``spec``'s dock is a tab with ('' for none) at the window's present width."""
    if spec.narrow_tab_with and too_narrow(window, specs, docks, spec):
        return spec.narrow_tab_with
    return spec.tab_with


def too_narrow(window: QMainWindow, specs: list[DockSpec], docks: dict[str, QDockWidget], spec: DockSpec) -> bool:
    """Whether the window leaves ``spec``'s dock less than its readable width beside the set of
    tabs it would otherwise stand beside (those need their widest one's minimum width)."""
    first = spec.narrow_tab_with
    group = [docks[s.name] for s in specs if s.name == first or s.tab_with == first]
    needed = max(dock.minimumSizeHint().width() for dock in group) + spec.readable_width + SEPARATOR_PX
    return window.width() < needed


def _tabbed_away(window: QMainWindow, specs: list[DockSpec], docks: dict[str, QDockWidget], name: str) -> bool:
    spec = next(s for s in specs if s.name == name)
    return tab_of(window, specs, docks, spec) != spec.tab_with


def place(window: QMainWindow, specs: list[DockSpec], docks: dict[str, QDockWidget], mode: str) -> None:
    """The first layout of ``mode``: every dock back in its area, beside or tabbed with the one
    the table names, shown if the mode lists it."""
    size = window.size()
    if not in_place(window, specs, docks):
        arrange(window, specs, docks)
    for spec in specs:
        docks[spec.name].setVisible(mode in spec.modes)
    for spec in specs:                      # the front tab: the first of its set the mode shows
        shown_tabs = [s for s in specs if s.tab_with == spec.name and mode in s.modes]
        if mode not in spec.modes and shown_tabs:
            docks[shown_tabs[0].name].raise_()
        elif not tab_of(window, specs, docks, spec):
            docks[spec.name].raise_()
    toolbar = window.findChild(QToolBar, "mainToolBar")
    if toolbar is not None:
        # Its commands are the editor's (New, Save, Verify, Upload, Simulate): watching a charge, the
        # plot takes its row; the menus keep every command, and the mode's layout keeps the choice.
        toolbar.setVisible(mode != CHARGE)
    shown = [s for s in specs if mode in s.modes and not _tabbed_away(window, specs, docks, s.name)]
    for orientation, length in ((Qt.Orientation.Horizontal, lambda s: s.width),
                                (Qt.Orientation.Vertical, lambda s: s.height)):
        sized = [s for s in shown if length(s)]
        window.resizeDocks([docks[s.name] for s in sized], [length(s) for s in sized], orientation)
    window.resize(size)


READABLE_SHARE = 0.6    # a dock restored narrower (or lower) than this share of its first size gets that size back


def make_readable(window: QMainWindow, specs: list[DockSpec], docks: dict[str, QDockWidget]) -> list[str]:
    """Docks a restored layout left too small to read (a layout saved in a wider window, or on another
    screen: the Problems dock came back 70-130 px wide, one word per line) back at their first size;
    the neighbours give the room. Returns the names of the docks resized."""
    size = window.size()
    resized = []
    for orientation, length, now in ((Qt.Orientation.Horizontal, lambda s: s.width, QDockWidget.width),
                                     (Qt.Orientation.Vertical, lambda s: s.height, QDockWidget.height)):
        small = [s for s in specs if length(s) and docks[s.name].isVisible() and not docks[s.name].isFloating()
                 and now(docks[s.name]) < length(s) * READABLE_SHARE]
        if small:
            window.resizeDocks([docks[s.name] for s in small], [length(s) for s in small], orientation)
            resized += [s.name for s in small]
    window.resize(size)
    return resized


def width_changed_place(window: QMainWindow, specs: list[DockSpec], docks: dict[str, QDockWidget]) -> bool:
    """Whether a dock placed by the window's width (``narrow_tab_with``) stands in the other place
    now: beside its neighbours in a window too narrow for it, or a tab in one wide enough."""
    for spec in specs:
        dock = docks[spec.name]
        if not spec.narrow_tab_with or dock.isFloating() or window.dockWidgetArea(dock) != spec.area:
            continue                        # moved by the user: left where it is
        tabbed = docks[spec.narrow_tab_with] in window.tabifiedDockWidgets(dock)
        if tabbed != _tabbed_away(window, specs, docks, spec.name):
            return True
    return False


def in_place(window: QMainWindow, specs: list[DockSpec], docks: dict[str, QDockWidget]) -> bool:
    """Every dock docked in its area, in its set of tabs. The modes differ only in which docks
    show: then only that changes, for Qt leaves a shown tab bar behind each time docks are tabified
    anew (over the menu, or peeping out under the plot)."""
    for spec in specs:
        dock = docks[spec.name]
        if dock.isFloating() or window.dockWidgetArea(dock) != spec.area:
            return False
        first = tab_of(window, specs, docks, spec) or spec.name
        tabs = {docks[s.name] for s in specs if s.name == first or tab_of(window, specs, docks, s) == first} - {dock}
        if set(window.tabifiedDockWidgets(dock)) != tabs:
            return False
    return True


def arrange(window: QMainWindow, specs: list[DockSpec], docks: dict[str, QDockWidget]) -> None:
    """Every dock back in its area, beside or tabbed with the one the table names."""
    for spec in specs:          # hidden while they move: side by side for a moment they would widen the window
        docks[spec.name].hide()
    for spec in specs:
        dock = docks[spec.name]
        dock.setFloating(False)
        window.addDockWidget(spec.area, dock)
    for spec in specs:
        if spec.beside and not _tabbed_away(window, specs, docks, spec.beside):
            window.splitDockWidget(docks[spec.beside], docks[spec.name], Qt.Orientation.Horizontal)
    for spec in specs:
        if spec.tab_with:
            window.tabifyDockWidget(docks[spec.tab_with], docks[spec.name])
    for spec in specs:                      # after its set's own tabs: the last tab
        if _tabbed_away(window, specs, docks, spec.name):
            window.tabifyDockWidget(docks[spec.narrow_tab_with], docks[spec.name])
