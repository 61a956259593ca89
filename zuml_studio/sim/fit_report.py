"""The figures of a fit or a comparison as lines a person reads, in the installed language: what
``zuml fit``/``zuml compare`` print and the Compare with Log dialog shows. The keys are those of
their ``--json``, which stays English (a contract for scripts, like the phase-end reasons)."""
from __future__ import annotations

from ..i18n import N_, _
from .reasons import shown_reason

WHO = {"real": N_("real"), "model": N_("model")}
# Why the logged charge ended: the report's "kind" and this text ("why" holds it in English).
REAL_END = {
    "dv": N_("voltage {drop} mV per cell below its peak (-dV)"),
    "log_ends": N_("log ends"),
    "cv": N_("current tapered to {a} A ({share} of CC) at {v} V"),
    "cc": N_("log ends during constant current"),
}


def real_end_why(kind: str, values: dict, translate: bool = True) -> str:
    """The logged charge's end in words: English for the report, translated to be shown."""
    template = REAL_END[kind]
    return (_(template) if translate else template).format(**values)


def figure_lines(report: dict) -> list[str]:
    lines = []
    if report.get("rmse_v_per_cell_mv") is not None:
        lines.append(_("RMSE voltage: {n} mV per cell").format(n=f"{report['rmse_v_per_cell_mv']:g}"))
    if report.get("rmse_i_cv_pct") is not None:
        lines.append(_("RMSE current in CV: {share} of the CC current").format(share=f"{report['rmse_i_cv_pct']:g} %"))
    if report.get("peak"):
        p = report["peak"]
        lines.append(_("peak at {real} mAh (real), {model} mAh (model)").format(real=f"{p['real_mah']:g}",
                                                                                 model=f"{p['model_mah']:g}"))
        lines.append(_("-dV {real} mV/cell (real), {model} (model)").format(real=f"{p['real_dv_mv_per_cell']:g}",
                                                                            model=f"{p['model_dv_mv_per_cell']:g}"))
    if report.get("temp_rise"):
        t = report["temp_rise"]
        lines.append(_("temperature rise {real} °C (real), {model} °C (model)").format(real=f"{t['real_c']:g}",
                                                                                        model=f"{t['model_c']:g}"))
    for who, end in report.get("ends", {}).items():
        why = real_end_why(end["kind"], end["values"]) if "kind" in end else shown_reason(end["why"])
        lines.append(_("{who} ended at {minutes} min, {mah} mAh: {why}").format(
            who=_(WHO.get(who, who)), minutes=f"{end['time_s'] / 60:.1f}", mah=f"{end['mah']:g}", why=why))
    return lines
