"""The log viewer: a charger's log file as a document (plot, totals, cursor readout, overlays)
and its CSV import dialog. Imports only ui.plots and ui.base."""
from .log_window import LogWindow

__all__ = ["LogWindow"]
