"""What a fit may claim (issue 35 §2): a capacity only where the log covered enough of the cell's range to fix
it, heat terms only where the model's temperature rise follows the pack's, per-cell figures only where they
are physically possible next to each other. A figure that fails is withheld with the reason, not printed as a
result (docs/fit.md, "What a fit may claim")."""
from __future__ import annotations

import numpy as np

from ..domain.chemistry import Chemistry

# A window that moves the state of charge by less than this share of the capacity does not fix the capacity:
# the capacity is its charge over that share, and the share comes from the OCV table, whose error (a few
# per cent of charge) is then a large part of it (the Akkumatik 2S Li-ion discharge, 3.61 -> 3.33 V/cell,
# covered 33 % of what it was fitted to: 4386 mAh, where another start state fits 3000 as well).
MIN_COVERED = 0.5
HEAT_RISE_C = 3.0            # a model's temperature rise within this of the pack's, or its heat terms are not fitted
HEAT_PARAMS = ("k_t_v_per_k", "ha_w_per_k", "cth_j_per_k")
DELIVERED_PCT = 3.0          # a model run on the log's own current delivers the log's charge within this
# Cells of one pack, of one type and one age: a capacity ratio above this (or a resistance ratio above
# _R_RATIO) between two of them is no measurement but a fit that traded one figure for another.
CAPACITY_RATIO = 2.0
R_RATIO = 10.0


def coverage(chem: Chemistry, v_cell: tuple[float, float], window_mah: float, capacity_mah: float,
             start_soc: float, sloped: bool) -> dict:
    """How much of the range the window covered: the fitted share (its charge over the fitted capacity) and,
    where the OCV is ``sloped`` (lithium), the share the chemistry's OCV table puts between its first and last
    voltage per cell; the smaller decides. A nickel or lead cell's voltage under current lies off its flat OCV
    table by more than the table spans (the Akkumatik NiCd charge reads 1.49-1.71 V/cell, all above it), so there
    the fitted share alone. ``fixed``: whether the share is at least MIN_COVERED."""
    fitted = window_mah / max(capacity_mah, 1e-9)
    by_ocv = fitted if not sloped else abs(float(np.interp(v_cell[0], chem.ocv_v, chem.ocv_soc)) - float(np.interp(v_cell[1], chem.ocv_v,
                                                                                           chem.ocv_soc)))
    share = min(fitted, by_ocv)
    return {"fixed": bool(share >= MIN_COVERED), "share": round(float(share), 3),
            "v_per_cell": [round(float(v_cell[0]), 4), round(float(v_cell[1]), 4)],
            "mah": round(float(window_mah), 1), "start_soc": round(float(start_soc), 4)}


def heat_check(temp_rise: dict | None, fitted: bool) -> dict | None:
    """Whether fitted heat terms may be reported: the model's rise within HEAT_RISE_C of the pack's. None where
    no heat term was fitted or the log has no probe."""
    if not fitted or not temp_rise:
        return None
    off = temp_rise["model_c"] - temp_rise["real_c"]
    return {"fitted": bool(abs(off) <= HEAT_RISE_C), "rise_error_c": round(float(off), 2), "limit_c": HEAT_RISE_C}


def delivered_check(real_mah: float, model_mah: float) -> dict:
    """The model's charge over the log's window against the log's: within DELIVERED_PCT or not a fit."""
    off = (model_mah / real_mah - 1.0) * 100.0 if real_mah else 0.0
    return {"error_pct": round(float(off), 2), "ok": bool(abs(off) <= DELIVERED_PCT), "limit_pct": DELIVERED_PCT}


def withheld(report: dict) -> set[str]:
    """The fitted values a report may not print as results (capacity not fixed, heat not followed)."""
    out = set()
    if report.get("coverage") and not report["coverage"]["fixed"]:
        out |= {"capacity_mah", "start_soc"}
    if report.get("heat") and not report["heat"]["fitted"]:
        out |= set(HEAT_PARAMS)
    return out


def cells_plausible(capacities: list[float], resistances: list[float]) -> list[dict]:
    """The per-cell figures impossible next to each other in one pack: [{"quantity", "ratio", "limit"}]."""
    out = []
    for name, values, limit in (("capacity_mah", capacities, CAPACITY_RATIO), ("r_mohm", resistances, R_RATIO)):
        ratio = max(values) / max(min(values), 1e-9)
        if ratio > limit:
            out.append({"quantity": name, "ratio": round(float(ratio), 2), "limit": limit})
    return out
