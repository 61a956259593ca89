"""The simulator panel: start parameters, the run's V/I/T plot and its phase table, the worker
that runs a simulation in a child process, and the dialog comparing a run with a measured log.
Imports only ui.plots and ui.base.

``SimulatorPanel`` is loaded on first use: the simulation's child process imports
``sim_process`` from here and must not import Qt."""
from __future__ import annotations


def __getattr__(name: str):
    if name == "SimulatorPanel":
        from .sim_panel import SimulatorPanel
        return SimulatorPanel
    raise AttributeError(name)


__all__ = ["SimulatorPanel"]
