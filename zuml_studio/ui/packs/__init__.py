"""The Packs dock (the battery logbook's view) and how the main window takes it in. Imports
ui.sim (the simulator form's named batteries), ui.device (the folder backups start in),
ui.plots and ui.base."""
from __future__ import annotations

from PySide6.QtWidgets import QDockWidget

from ..sim.params_form import NAMED


def install_packs_dock(window) -> QDockWidget:
    """The Packs dock (a row of ``ui/window/docks.py``, tabbed with the Simulator and the Device):
    its panel, and the logbook, are made when it is first shown."""
    dock = window.packs_dock
    dock.visibilityChanged.connect(lambda visible: visible and dock_panel(window, dock))
    return dock


def dock_panel(window, dock: QDockWidget):
    """The dock's PacksPanel, made on first use: "simulate on this pack" sets the simulator's battery to the
    pack's model, its cells and capacity, and runs the macro there."""
    from .packs_panel import PacksPanel

    if isinstance(dock.widget(), PacksPanel):
        return dock.widget()
    panel = PacksPanel()
    panel.statusMessage.connect(lambda message: window.statusBar().showMessage(message, 6000))

    def simulate(battery: str, cells: int, capacity_mah: float) -> None:
        form = window.sim_panel.form
        form.add_named_batteries()
        form.set_values(chemistry=NAMED + battery, series=cells, capacity_mah=int(round(capacity_mah)))
        window.sim_dock.raise_()
        window.sim_panel.simulate()

    panel.simulateOnPack.connect(simulate)
    dock.setWidget(panel)
    return panel


def bind_live_runs(window, device_panel):
    """Live runs on ``device_panel`` recorded into their packs (asked once per port or passport serial);
    the Packs dock, when built, shows each as it is recorded."""
    from .live_attach import LiveAttach

    live = LiveAttach(device_panel, window)
    live.statusMessage.connect(lambda message: window.statusBar().showMessage(message, 6000))
    live.recorded.connect(lambda _result: window.packs_dock.widget().refresh()
                          if hasattr(window.packs_dock.widget(), "refresh") else None)
    return live
