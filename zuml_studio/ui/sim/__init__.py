"""The simulator panel: start parameters, the run's V/I/T plot and its phase table."""
from .sim_panel import SimulatorPanel

__all__ = ["SimulatorPanel"]
