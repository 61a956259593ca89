"""What ``zuml log info`` prints and the log viewer shows as totals: one dict per log."""
from __future__ import annotations

from .model import Log


def summarize(log: Log) -> dict:
    """format, device, samples, bad_records, duration_s, v_min, v_max, i_max_a (largest |I|),
    charge_in_mah, charge_out_mah (totals at the last sample), cells, phases, plus what the
    file adds (battery, channel, internal-resistance readings…), ``time_order`` where time goes
    back and a new record set follows the last (``model.in_time_order``) and ``out_of_range`` where samples
    no charger could have measured were (``model.MAX_MEASURED``)."""
    s = log.samples
    volts = [x.voltage_v for x in s]
    temps = [x.temp_c for x in s if x.temp_c is not None]
    current = log.meta.get("current_measured", True)
    out = {
        "format": log.format,
        "device": log.device,
        "samples": len(s),
        "bad_records": log.bad_records,
        "duration_s": round(s[-1].time_s - s[0].time_s, 3) if s else 0.0,
        "v_min": round(min(volts), 4) if s else None,
        "v_max": round(max(volts), 4) if s else None,
        "i_max_a": round(max(abs(x.current_a) for x in s), 4) if s and current else None,
        "charge_in_mah": round(s[-1].mah_in, 1) if s and current else None,
        "charge_out_mah": round(s[-1].mah_out, 1) if s and current else None,
        "cells": log.cells,
        "t_min_c": round(min(temps), 2) if temps else None,
        "t_max_c": round(max(temps), 2) if temps else None,
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
