"""What the pack's printed report shows beyond its register entry (no Qt here): each session's charge or
discharge curve per cell, the spread of its cells over it (cell drift), and what the model fitted to the
pack predicts next to what its log measured, with the fit's quality (``sim.fit``'s figures; "–" where the
fit gives no such figure)."""
from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path

import numpy as np

from ..domain.units import SECONDS_PER_HOUR
from ..logs import LogFormatError, read_log_file
from ..sim.fit_predict import prediction_line, trust_words
from ..sim.fit_report import quality_lines
from .register import Pack
from .sessions import Session
from .text import path_of
from ..i18n import _

# At most this many sessions' curves (the newest): more lines on one small plot are not read apart.
MAX_CURVES = 8
# Points per drawn curve: a long log is thinned to this (the page is 700 units wide).
CURVE_POINTS = 400


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
        curves.append(SessionCurve(s.recorded[:10], (c.t[::step] - c.t[0]) / SECONDS_PER_HOUR,
                                   c.voltage[::step] / max(pack.cells, 1), spread))
    return curves, missing


def model_lines(quality: dict | None, logged_file: str = "") -> list[str]:
    """The fit's quality and its prediction of its own log's program (``packs.model.fit_quality``) as lines of
    the report, worded as the window words them; "–" for a figure the fit does not give."""
    if quality is None:
        return [_("No model fitted to this pack yet: its figures are –.")]
    lines = [_("Fitted to {file}").format(file=Path(logged_file).name or "–")]
    lines += quality_lines(quality["quality"]) or [_("fit quality (RMSE): –")]
    prediction = quality["own_program"]
    if prediction is None:
        lines.append(_("Its own log's charge cannot be predicted: the log does not show what ended the charge "
                       "(it stopped without a -dV or a held voltage, or ran on long after its -dV)"))
        return lines
    lines.append(prediction_line(prediction))
    warning = trust_words(prediction)
    if warning:
        lines.append(warning)
    return lines


