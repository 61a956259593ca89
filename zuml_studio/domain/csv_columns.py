"""The column names of ZUML Studio's own CSV files, named once.

Four files share one vocabulary: the simulator's sample CSV (``SAMPLE_COLUMNS``), the device panel's
session CSV (the same plus ``event``), ``zuml monitor --csv`` (``MONITOR_COLUMNS``: the frame's own
fields as well) and a measured curve (``CURVE_COLUMNS``, ``temp_c`` optional). ``zuml log export``
writes a log's samples under its own names (``EXPORT_COLUMNS``: ``t_s``, ``charge_in_mah`` …,
``state``), which ``logs/session_csv.py`` reads back. The names are a file format: users' files and
the tests' exports hold them byte for byte, so they never change."""
from __future__ import annotations

# -- the simulator's, the session's, the monitor's and a curve's columns ------------------------
TIME_S = "time_s"                 # the macro's clock, s
SECTION = "section"               # discharge / charge (the simulator: 0 / 1)
PHASE = "phase"                   # the phase's run number, 1-based (0: none)
VOLTAGE_V = "voltage_v"
CURRENT_A = "current_a"           # charge current positive
TEMP_C = "temp_c"                 # the battery's sensor
HEATSINK_C = "heatsink_c"
MAH_IN = "mah_in"
MAH_OUT = "mah_out"
EVENT = "event"                   # an event row's text; empty on a telemetry row
BALANCE_MASK = "balance_mask"     # bit k-1 set while cell k bleeds
# the monitor's frame fields besides
RUNNING, PAUSED, REPETITION, CYCLE, RUN = "running", "paused", "repetition", "cycle", "run"

# -- ``zuml log export``'s columns ----------------------------------------------------------
T_S = "t_s"                       # the log's clock, s
CHARGE_IN_MAH = "charge_in_mah"
CHARGE_OUT_MAH = "charge_out_mah"
STATE = "state"                   # charge, discharge, pause, idle

SAMPLE_COLUMNS = (TIME_S, SECTION, PHASE, VOLTAGE_V, CURRENT_A, TEMP_C, HEATSINK_C, MAH_IN, MAH_OUT)
SESSION_COLUMNS = SAMPLE_COLUMNS + (EVENT,)
MONITOR_COLUMNS = (TIME_S, RUNNING, PAUSED, SECTION, REPETITION, CYCLE, PHASE, RUN, VOLTAGE_V, CURRENT_A, TEMP_C,
                   HEATSINK_C, MAH_IN, MAH_OUT, EVENT)
CURVE_COLUMNS = (TIME_S, VOLTAGE_V, CURRENT_A)
EXPORT_COLUMNS = (T_S, VOLTAGE_V, CURRENT_A, TEMP_C, CHARGE_IN_MAH, CHARGE_OUT_MAH, STATE)


def cell_column(k: int) -> str:
    """Cell k's voltage (k from 1, the pack's negative end): ``cell3_v``."""
    return f"cell{k}_v"


def cell_columns(cells: int) -> tuple[str, ...]:
    """``cell1_v`` … ``cellN_v``."""
    return tuple(cell_column(k) for k in range(1, cells + 1))


def is_cell_column(name: str) -> bool:
    """A cell's voltage column, as written by ``cell_column`` (read loosely: ``cell…_v``)."""
    return name.startswith("cell") and name.endswith("_v")
