"""The Device panel: connect to a charger (or the built-in virtual one), flash the editor's
macro, start and stop it, watch its telemetry live; the serial monitor, calibration and
firmware install dialogs, and the questions asked before what cannot be undone. Imports only
ui.plots and ui.base.

``DevicePanel`` is loaded on first use."""
from __future__ import annotations


def __getattr__(name: str):
    if name == "DevicePanel":
        from .device_panel import DevicePanel
        return DevicePanel
    raise AttributeError(name)


__all__ = ["DevicePanel"]
