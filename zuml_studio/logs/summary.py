"""What ``zuml log info`` prints and the log viewer shows as totals: one dict per log."""
from __future__ import annotations

import numpy as np

from .model import Log


def summarize(log: Log) -> dict:
    """format, device, samples, bad_records, duration_s, v_min, v_max, i_max_a (largest |I|),
    charge_in_mah, charge_out_mah (totals at the last sample), cells, phases, plus what the
    file adds (battery, channel, internal-resistance readings…), ``time_order`` where time goes
    back and a new record set follows the last (``model.in_time_order``) and ``out_of_range`` where samples
    no charger could have measured were (``model.MAX_MEASURED``)."""
    c = log.columns
    s = len(c) > 0
    temps = c.temp[np.isfinite(c.temp)]
    current = log.meta.get("current_measured", True)
    out = {
        "format": log.format,
        "device": log.device,
        "samples": len(c),
        "bad_records": log.bad_records,
        "duration_s": round(float(c.t[-1] - c.t[0]), 3) if s else 0.0,
        "v_min": round(float(c.voltage.min()), 4) if s else None,
        "v_max": round(float(c.voltage.max()), 4) if s else None,
        "i_max_a": round(float(np.abs(c.current).max()), 4) if s and current else None,
        "charge_in_mah": round(float(c.mah_in[-1]), 1) if s and current else None,
        "charge_out_mah": round(float(c.mah_out[-1]), 1) if s and current else None,
        "cells": log.cells,
        "t_min_c": round(float(temps.min()), 2) if len(temps) else None,
        "t_max_c": round(float(temps.max()), 2) if len(temps) else None,
        "phases": [p.as_dict() for p in log.phases()],
    }
    if log.resistance:
        last = log.resistance[-1]
        out["resistance"] = {"readings": len(log.resistance), "last_pack_mohm": last[1],
                             "last_cells_mohm": list(last[2])}
    for key in ("battery", "channel", "header", "record_sets", "events", "other_channel_records",
                "other_channel_lines", "csv_columns", "csv_assumed", "time_order", "out_of_range", "charge_check",
                "started"):
        if key in log.meta:
            out[key] = log.meta[key]
    return out
