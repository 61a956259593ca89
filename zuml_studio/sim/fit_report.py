"""The figures of a fit or a comparison as lines a person reads, in the installed language: what
``zuml fit``/``zuml compare`` print and the Compare with Log dialog shows. The keys are those of
their ``--json``, which stays English (a contract for scripts, like the phase-end reasons)."""
from __future__ import annotations

from ..domain.units import MAH_PER_AH
from ..i18n import N_, _
from .reasons import shown_reason

WHO = {"real": N_("real"), "model": N_("model")}
# Why the logged charge ended: the report's "kind" and this text ("why" holds it in English).
REAL_END = {
    "dv": N_("voltage {drop} mV per cell below its peak (-dV)"),
    "log_ends": N_("log ends"),
    "cv": N_("current tapered to {a} A ({share} of CC) at {v} V"),
    "cc": N_("log ends during constant current"),
    "cutoff": N_("voltage fell to {v} V ({per_cell} V per cell)"),
}


def real_end_why(kind: str, values: dict, translate: bool = True) -> str:
    """The logged charge's end in words: English for the report, translated to be shown."""
    template = REAL_END[kind]
    return (_(template) if translate else template).format(**values)


def _minutes(window: list[float]) -> str:
    return f"{window[0] / 60:.1f}–{window[1] / 60:.1f} min"


def figure_lines(report: dict) -> list[str]:
    """The figures, each with the span of the charge it is taken over."""
    lines = []
    discharge = report.get("direction") == "discharge"
    if report.get("window_s"):
        span = _minutes(report["window_s"])
        if discharge:
            lines.append(_("figures over {span} of the discharge (the time both ran)").format(span=span)
                         if "ends" in report else _("figures over {span} of the discharge").format(span=span))
        else:
            lines.append(_("figures over {span} of the charge (the time both ran)").format(span=span)
                         if "ends" in report else _("figures over {span} of the charge").format(span=span))
    if report.get("rmse_v_per_cell_mv") is not None:
        lines.append(_("RMSE voltage: {n} mV per cell").format(n=f"{report['rmse_v_per_cell_mv']:g}"))
    if report.get("rmse_i_cv_pct") is not None:
        lines.append(_("RMSE current in CV: {share} of the CC current").format(share=f"{report['rmse_i_cv_pct']:g} %"))
    elif report.get("no_cc_phase"):
        lines.append(_("RMSE current in CV: – (no CC phase: the charge started at its held voltage)"))
    if report.get("rmse_temp_c") is not None:
        lines.append(_("RMSE temperature: {n} °C").format(n=f"{report['rmse_temp_c']:g}"))
    if report.get("capacity"):
        c = report["capacity"]
        lines.append(_("delivered {real} mAh (real), {model} mAh (model), {off}").format(
            real=f"{c['real_mah']:g}", model=f"{c['model_mah']:g}",
            off=f"{(c['model_mah'] / c['real_mah'] - 1.0) * 100:+.1f} %" if c["real_mah"] else "–"))
    if report.get("weak_cell"):
        w = report["weak_cell"]
        lines.append(_("a weak cell: one cell holds {mah} mAh, {share} of the others' {others}; it empties at "
                       "{at} mAh, where the pack's voltage steps down by a cell's (RMSE {equal} mV per cell with "
                       "equal cells)").format(
            mah=f"{w['capacity_mah']:.0f}", share=f"{w['capacity_share'] * 100:.0f} %", others=f"{w['others_mah']:.0f}",
            at=f"{w['at_mah']:.0f}", equal=f"{w['rmse_equal_cells_mv']:g}"))
    if report.get("peak"):
        p = report["peak"]
        lines.append(_("peak at {real} mAh (real), {model} mAh (model)").format(real=f"{p['real_mah']:g}",
                                                                                 model=f"{p['model_mah']:g}"))
        lines.append(_("-dV {real} mV/cell (real), {model} (model)").format(real=f"{p['real_dv_mv_per_cell']:g}",
                                                                            model=f"{p['model_dv_mv_per_cell']:g}"))
    if report.get("temp_rise"):
        t = report["temp_rise"]
        lines.append(_("temperature rise {real} °C (real, {real_span}), {model} °C (model, {model_span})").format(
            real=f"{t['real_c']:g}", model=f"{t['model_c']:g}", real_span=_minutes(t["real_window_s"]),
            model_span=_minutes(t["model_window_s"])))
    for who, end in report.get("ends", {}).items():
        why = real_end_why(end["kind"], end["values"]) if "kind" in end else shown_reason(end["why"])
        lines.append(_("{who} ended at {minutes} min, {mah} mAh: {why}").format(
            who=_(WHO.get(who, who)), minutes=f"{end['time_s'] / 60:.1f}", mah=f"{end['mah']:g}", why=why))
    lines += bound_lines(report) + claim_lines(report)
    return lines


QUALITY = {
    "voltage": N_("RMSE voltage {rmse} mV per cell over {span}"),
    "held_current": N_("RMSE current where the voltage was held {rmse} of the constant current over {span}"),
    "temperature": N_("RMSE temperature {rmse} °C over {span}"),
}


def quality_lines(quality: dict) -> list[str]:
    """The fit's quality per quantity (``figures["quality"]``), each with its window; a held current with no CC
    current to measure it against is "–", with why."""
    lines = []
    for name, q in quality.items():
        if name not in QUALITY:
            continue
        if q["rmse"] is not None:
            lines.append(_(QUALITY[name]).format(rmse=f"{q['rmse']:g}" + (" %" if name == "held_current" else ""),
                                                 span=_minutes(q["window_s"])))
        elif q.get("note") == "no CC phase":
            lines.append(_("RMSE current where the voltage was held – over {span} (no CC phase: the charge started "
                           "at its held voltage)").format(span=_minutes(q["window_s"])))
    return lines


def claim_lines(report: dict) -> list[str]:
    """What the fit may not claim (sim/fit_checks.py): a capacity the window does not fix, heat terms whose
    rise misses the pack's, a model that does not deliver the log's charge."""
    lines = []
    cover = report.get("coverage")
    if cover and not cover["fixed"]:
        lines.append(_("⚠ capacity not fixed by this log: it covers {v0}–{v1} V per cell, {mah} mAh, {share} of the "
                       "range; a capacity and start state from it are not results").format(
            v0=f"{cover['v_per_cell'][0]:.3f}", v1=f"{cover['v_per_cell'][1]:.3f}", mah=f"{cover['mah']:.0f}",
            share=f"{cover['share'] * 100:.0f} %"))
    heat = report.get("heat")
    if heat and not heat["fitted"]:
        lines.append(_("⚠ heat terms not fitted: the model's temperature rise is {off} °C off the pack's (limit "
                       "±{limit} °C)").format(off=f"{heat['rise_error_c']:+.1f}", limit=f"{heat['limit_c']:g}"))
    delivered = (report.get("capacity") or {}).get("ok")
    if delivered is False:
        lines.append(_("⚠ not a fit: the model on the log's own current delivers {off} of the log's charge (limit "
                       "±{limit} %)").format(off=f"{report['capacity']['error_pct']:+.1f} %",
                                             limit=f"{report['capacity']['limit_pct']:g}"))
    return lines


def clock(seconds: float) -> str:
    """h:mm:ss on a log's clock."""
    s = int(round(seconds))
    return f"{s // 3600}:{s // 60 % 60:02d}:{s % 60:02d}"


def resistance_words(report: dict) -> str | None:
    """What a comparison says of the resistance it took from the log (None: it took none)."""
    r = report.get("resistance")
    if not r:
        return None
    if len(r["at_s"]) == 1:
        return _("resistance {r} mΩ/cell measured at the rest at {at}").format(
            r=f"{r['mohm_per_cell']:.0f}", at=clock(r["at_s"][0]))
    return _("resistance {r} mΩ/cell measured at {n} rests from {at}").format(
        r=f"{r['mohm_per_cell']:.0f}", n=len(r["at_s"]), at=clock(r["at_s"][0]))


def bound_lines(report: dict) -> list[str]:
    """A fit whose values ended at their bounds: which, and the likely cause."""
    ends = report.get("at_bound") or []
    if not ends:
        return []
    names = ", ".join(_(PARAM_WORDS.get(e["name"], e["name"])) for e in ends)
    if report.get("cells_guessed") not in (None, report.get("cells")):
        cause = _("the likely cause is the cell count: the fit used {cells}, the log looks like {guess} "
                  "(--cells {guess})").format(cells=report["cells"], guess=report["cells_guessed"])
    elif report.get("direction") == "discharge":
        cause = _("the model cannot follow this discharge: check the chemistry and the cell count")
    else:
        cause = _("the model cannot follow this charge: check the chemistry and the cell count")
    return [_("⚠ at the edge of what the fit allows: {names}; {cause}").format(names=names, cause=cause)]


PARAM_WORDS = {
    "capacity_mah": N_("capacity"), "start_soc": N_("charge at the start"), "r_scale": N_("internal resistance"),
    "ocv_offset_v": N_("rest voltage offset"), "ocv_scale": N_("rest voltage slope"),
    "w0": N_("charge acceptance"), "dv_o2_v": N_("end-of-charge voltage rise"),
    "k_t_v_per_k": N_("voltage per degree"), "ha_w_per_k": N_("heat loss"), "cth_j_per_k": N_("heat capacity"),
    "dip_v_per_charge": N_("end-of-charge dip"), "dip_tau_s": N_("dip recovery time"),
    "r2_ohm": N_("slow polarisation resistance"), "tau2_s": N_("slow polarisation time"),
    "k_charge_ohm": N_("charge polarisation"), "pol_tau_s": N_("polarisation time"),
    "pol_max_v": N_("polarisation limit"),
    "k_discharge_ohm": N_("discharge knee"),
}


def param_lines(params: dict, battery, report: dict | None = None) -> list[str]:
    """The fitted parameters in words and units (a fitted ``fit.Battery`` gives the resistance); those the
    fit's ``report`` withholds (fit_checks.withheld: said by ``claim_lines``) left out."""
    from .fit_checks import withheld
    params = {k: v for k, v in params.items() if k not in withheld(report or {})}
    chem, q_ah = battery.chem, battery.capacity_mah / MAH_PER_AH
    r_cell = (chem.r0_ohm + chem.r1_ohm) * chem.ref_capacity_ah / max(q_ah, 1e-6) * 1000.0
    text = {
        "capacity_mah": lambda v: _("capacity {n} mAh").format(n=f"{v:.0f}"),
        "start_soc": lambda v: _("{share} charged at the start").format(share=f"{v * 100:.0f} %"),
        "r_scale": lambda v: _("internal resistance {r} mΩ per cell, {x}× the model's").format(
            r=f"{r_cell:.0f}", x=f"{v:.2g}"),
        "ocv_offset_v": lambda v: _("rest voltage {mv} mV per cell from the model's").format(mv=f"{v * 1000:+.0f}"),
        "ocv_scale": lambda v: _("rest voltage curve {x}× as steep as the model's").format(x=f"{v:.2g}"),
        "w0": lambda v: _("charge acceptance falls off over the last {share} of the charge").format(
            share=f"{min(100.0, v * 300):.0f} %"),
        "dv_o2_v": lambda v: _("end-of-charge voltage rise {mv} mV per cell").format(mv=f"{v * 1000:.0f}"),
        "k_t_v_per_k": lambda v: _("voltage falls {mv} mV per cell per °C of warming").format(mv=f"{v * 1000:.1f}"),
        "ha_w_per_k": lambda v: _("heat loss to the air {w} W per °C").format(w=f"{v:.3g}"),
        "cth_j_per_k": lambda v: _("heat capacity {j} J per °C").format(j=f"{v:.0f}"),
        "dip_v_per_charge": lambda v: _("end-of-charge dip {mv} mV per cell for each capacity of overcharge").format(
            mv=f"{v * 1000:.0f}"),
        "dip_tau_s": lambda v: _("the dip recovers within {m} min").format(m=f"{v / 60:.0f}"),
        "r2_ohm": lambda v: _("slow polarisation resistance {r} mΩ per cell").format(r=f"{v * 1000:.1f}"),
        "tau2_s": lambda v: _("slow polarisation builds over {m} min").format(m=f"{v / 60:.0f}"),
        "k_charge_ohm": lambda v: _("charge polarisation {r} mΩ per cell").format(r=f"{v * 1000:.2f}"),
        "pol_tau_s": lambda v: _("polarisation builds over {m} min").format(m=f"{v / 60:.0f}"),
        "pol_max_v": lambda v: _("polarisation at most {mv} mV per cell").format(mv=f"{v * 1000:.0f}"),
        "k_discharge_ohm": lambda v: _("discharge knee {r} mΩ per cell at a tenth of the charge left").format(
            r=f"{v / 0.1 * chem.ref_capacity_ah / max(q_ah, 1e-6) * 1000:.0f}"),
    }
    return [text[k](v) if k in text else f"{k} {v:g}" for k, v in params.items()]
