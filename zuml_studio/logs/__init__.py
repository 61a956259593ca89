"""Charger log files: read them (one module per format), summarise, export, and write the session CSV of
a live connection (``session_log``). No Qt here.

``read_log(data, name)`` recognises the format from the bytes (``registry.detect``) and
returns a ``Log``: the samples as numpy columns (``model.Columns``; ``log.samples`` makes each a
``protocol.messages.Telemetry`` when asked for), the bad-record count and what the file says about the charger.

May import: ``streams`` (a capture decoded by a charger's driver), ``protocol``, ``lang``, ``domain`` and the
top-level modules below; not ``sim``, which reads logs to fit and compare."""
from .model import Log, LogFormatError, Phase
from .registry import FORMATS, LogReader, detect, read_log, read_log_file

__all__ = ["FORMATS", "Log", "LogFormatError", "LogReader", "Phase", "detect", "read_log", "read_log_file"]
