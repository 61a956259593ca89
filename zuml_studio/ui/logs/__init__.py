"""The log viewer: a charger's log file as a document (plot, totals, cursor readout, overlays)."""
from .log_window import LogWindow

__all__ = ["LogWindow"]
