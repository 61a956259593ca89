"""A per-cell fit (``fit_cells.CellsFit.report()``) as lines a person reads, in the installed language:
what ``zuml fit`` prints under the pack's figures. The report's keys stay English (``--json``)."""
from __future__ import annotations

from ..i18n import _
from .fit_report import PARAM_WORDS


def cell_lines(report: dict) -> list[str]:
    """Each cell, the spread of capacity and resistance, the weakest cell and the most resistive one."""
    cells = report["cells"]
    lines = [_("cells from the balance taps, each on the pack's current:")]
    for c in cells:
        line = _("  cell {n}: {mah} mAh, {r} mΩ, {share} charged at the start, RMSE {mv} mV").format(
            n=c["cell"], mah=f"{c['capacity_mah']:.0f}", r=f"{c['r_mohm']:.1f}",
            share=f"{c['start_soc'] * 100:.0f} %", mv=f"{c['rmse_v_mv']:.1f}")
        if c["held"]:
            line += _(" — held at {v} V by the charger for {share} of the charge while the others rose: it took "
                      "less than the pack's current, so its capacity is not measured").format(
                v=f"{c['top_v']:.3f}", share=f"{c['held_pct']:.0f} %")
        cover = c.get("coverage")
        if cover and not cover["fixed"]:
            line += _(" — its capacity is not fixed by this log: it covers {v0}–{v1} V, {share} of its range").format(
                v0=f"{cover['v_per_cell'][0]:.3f}", v1=f"{cover['v_per_cell'][1]:.3f}",
                share=f"{cover['share'] * 100:.0f} %")
        if c["at_bound"]:
            line += _(" — at the edge of what the fit allows: {names}; the model cannot follow this tap").format(
                names=", ".join(_(PARAM_WORDS[name]) for name in c["at_bound"]))
        lines.append(line)
    cap, res = report["capacity_mah"], report["r_mohm"]
    lines.append(_("capacity {lo}–{hi} mAh, mean {mean}, spread {spread}").format(
        lo=f"{cap['min']:.0f}", hi=f"{cap['max']:.0f}", mean=f"{cap['mean']:.0f}", spread=f"{cap['spread_pct']:.1f} %"))
    lines.append(_("resistance {lo}–{hi} mΩ, mean {mean}, spread {spread}").format(
        lo=f"{res['min']:.1f}", hi=f"{res['max']:.1f}", mean=f"{res['mean']:.1f}", spread=f"{res['spread_pct']:.1f} %"))
    for flag in report.get("implausible", ()):
        lines.append(_("⚠ the cells' {quantity} differ {ratio}× (more than {limit}× is not one pack's cells): the "
                       "per-cell figures are a fit's trade, not measurements").format(
            quantity=_("capacity") if flag["quantity"] == "capacity_mah" else _("resistance"),
            ratio=f"{flag['ratio']:.1f}", limit=f"{flag['limit']:g}"))
    if report.get("implausible"):
        return lines
    weak = cells[report["weakest"] - 1]
    lines.append(_("weakest: cell {n}, {mah} mAh, {share} below the mean").format(
        n=weak["cell"], mah=f"{weak['capacity_mah']:.0f}",
        share=f"{(1 - weak['capacity_mah'] / cap['mean']) * 100:.1f} %"))
    worst = cells[report["highest_resistance"] - 1]
    lines.append(_("highest resistance: cell {n}, {r} mΩ, {x}× the mean").format(
        n=worst["cell"], r=f"{worst['r_mohm']:.1f}", x=f"{worst['r_mohm'] / res['mean']:.2f}"))
    return lines
