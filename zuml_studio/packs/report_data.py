"""What the pack's printed report shows beyond its register entry (no Qt here): each session's charge or
discharge curve per cell, the spread of its cells over it (cell drift), and what the model fitted to the
pack predicts next to what its log measured, with the fit's quality (``sim.fit``'s figures; "–" where the
fit gives no such figure)."""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..logs import LogFormatError, read_log_file
from ..sim.fit import FitResult
from .register import Pack
from .sessions import Session
from .text import path_of
from ..i18n import _

# At most this many sessions' curves (the newest): more lines on one small plot are not read apart.
MAX_CURVES = 8
# Points per drawn curve: a long log is thinned to this (the page is 700 units wide).
CURVE_POINTS = 400
# The model's charge differs from the log's by more than this (relative): it is not to be trusted here.
TRUST = 0.15


@dataclass(frozen=True)
class SessionCurve:
    label: str                  # the session's date
    t_h: np.ndarray             # hours from the log's start
    v_cell: np.ndarray          # pack voltage / cells
    spread_mv: np.ndarray       # max − min cell (NaN where fewer than two cells are read)


def session_curves(pack: Pack, sessions: list[Session]) -> tuple[list[SessionCurve], list[str]]:
    """The newest sessions' curves, and one line per session that could not be drawn (its file gone or
    no longer read)."""
    curves, missing = [], []
    for s in sessions[-MAX_CURVES:]:
        path = path_of(s.file)
        try:
            log = read_log_file(path)
        except LogFormatError as exc:
            missing.append(str(exc))
            continue
        c = log.columns
        if not len(c):
            continue
        step = max(1, len(c) // CURVE_POINTS)
        cells = np.where(c.cells[::step] > 0, c.cells[::step], np.nan)
        spread = np.full(len(cells), np.nan)
        read = np.isfinite(cells).sum(axis=1) >= 2
        if read.any():
            spread[read] = (np.nanmax(cells[read], axis=1) - np.nanmin(cells[read], axis=1)) * 1000.0
        curves.append(SessionCurve(s.recorded[:10], (c.t[::step] - c.t[0]) / 3600.0,
                                   c.voltage[::step] / max(pack.cells, 1), spread))
    return curves, missing


def model_lines(result: FitResult | None, logged_file: str = "") -> list[str]:
    """The fit's quality and prediction as lines of the report; "–" for a figure the fit does not give."""
    if result is None:
        return [_("No model fitted to this pack yet: its figures are –.")]
    f = result.figures

    def fig(key: str, spec: str, unit: str) -> str:
        value = f.get(key)
        return "–" if value is None else f"{format(value, spec)} {unit}"

    lines = [_("Fitted to {file}").format(file=Path(logged_file or result.curve.name).name or "–"),
             _("fit quality (RMSE): voltage {v} per cell, CV current {i}, temperature {t}").format(
                     v=fig("rmse_v_per_cell_mv", ".1f", "mV"), i=fig("rmse_i_cv_pct", ".1f", "%"),
                     t=fig("rmse_temp_c", ".1f", "°C"))]
    peak = f.get("peak")
    logged, model = (peak["real_mah"], peak["model_mah"]) if peak else (_logged_mah(result), None)
    said = _("charge to the −ΔV peak: logged {logged}, the model predicts {model}") if peak else \
        _("charge to the end: logged {logged}, the model predicts {model}")
    lines.append(said.format(logged="–" if logged is None else f"{logged:.0f} mAh",
                             model="–" if model is None else f"{model:.0f} mAh"))
    if logged and model is not None and abs(model - logged) / logged > TRUST:
        lines.append(_("the model's charge differs from the log's by {pct:.0f} % (over {trust:.0f} %): do not trust "
                       "its predictions for this pack").format(pct=abs(model - logged) / logged * 100,
                                                              trust=TRUST * 100))
    return lines


def _logged_mah(result: FitResult) -> float | None:
    mah = getattr(result.curve, "mah", None)
    return None if mah is None or not len(mah) else float(mah[-1] - mah[0])
