"""Write docs/validation.md and its figures: every training curve (tests/data/curves/training.toml,
charges and discharges) against the default model (only capacity and start fitted), the default with the
pack's resistance measured at its source log's rests (tests/data/curves/rest_steps.json) and the fitted
model.

    QT_QPA_PLATFORM=offscreen .venv/bin/python tools/validation.py [SHARED_SAMPLES_DIR]

The figures are drawn with pyqtgraph (the project's plotting library) offscreen. The answers to
the issue's questions are computed here from the recordings, so the page says what the data say.
SHARED_SAMPLES_DIR (default ../shared/realdata/samples beside the repository) is read for the Pb rest after charge
and the NiMH packs' voltage steps where the current stops, which the test curves leave out."""
from __future__ import annotations

import csv
import json
import os
import sys
import time
import tomllib
from dataclasses import replace
from pathlib import Path

import numpy as np

from cv_tail_cells import section as cells_tail_section   # beside this script (tools/)
from cv_tail_realdata import section as cv_tail_section
from zuml_studio.logs.rest_steps import rest_steps
from zuml_studio.domain.chemistry import load_chemistry
from zuml_studio.sim.curve import Curve, read_curve
from zuml_studio.sim.fit import LI, NI, cc_current, fit, measured, simulate_curve, smooth
from zuml_studio.sim.fit_discharge import discharging, end_voltage, fit_curve
from zuml_studio.sim.measured_r import MeasuredR, fit_with_measured_r

ROOT = Path(__file__).resolve().parent.parent
CURVES = ROOT / "tests" / "data" / "curves"
DOCS = ROOT / "docs"
FIG_DIR = DOCS / "validation"


def _claims_text(answers: dict, discharges: dict) -> str:
    """What a fit may claim (issue 35 §2: held discharge ends, windows that do not fix a capacity, cells, heat
    terms), its figures from today's fits."""
    fits = {name: a[2] for name, a in answers.items()} | {name: d[4] for name, d in discharges.items()}
    held = fits["nicd_4s_akkumatik_dis_1c"].figures
    short = [(name, f.figures["coverage"]) for name, f in fits.items()
             if f.figures.get("coverage") and not f.figures["coverage"]["fixed"]]
    withheld = ", ".join(f"{name} ({c['v_per_cell'][0]:.2f}–{c['v_per_cell'][1]:.2f} V/cell, {c['share']:.0%})"
                         for name, c in short)
    probe = {name: f.figures for name, f in fits.items() if f.figures.get("temp_rise")}
    heat = {name: f["heat"] for name, f in probe.items() if f.get("heat")}
    kept = [abs(h["rise_error_c"]) for h in heat.values() if h["fitted"]]
    dropped = "; ".join(f"{name}: its fitted model warms {probe[name]['temp_rise']['model_c']:.1f} °C where the "
                        f"pack warmed {probe[name]['temp_rise']['real_c']:.1f} °C ({h['rise_error_c']:+.1f} °C), "
                        "withheld" for name, h in heat.items() if not h["fitted"])
    no_probe = sorted(name for name, f in fits.items() if not f.figures.get("temp_rise") and f.chemistry in NI)
    return (
        '* **A held end.** The Akkumatik ends a discharge by holding its end voltage and stepping the current '
        "down: the NiCd pack's log goes from 1.0 A to 0.2 A at 3.40–3.45 V over its last 9 minutes, 10 % of its "
        "charge (and the issue's 2S Li-ion log 1.5 A to 0.35 A at 3.33 V/cell). The fit cut the model at the first "
        'sample at the end voltage and compared that to all the log delivered: 6.8 % short on the NiCd pack once '
        "its capacity was fitted freely, the issue's Li-ion log 33 % short (971 of 1 451 mAh). Such samples "
        '(within 2 % of the lowest voltage under current, below 0.92 of the current before) now drive the model by '
        'the log\'s voltage, as a charge\'s CV does, and its current is compared (RMSE "in CV" of the discharge '
        f"current): the NiCd discharge fits at {held['rmse_v_per_cell_mv']:.0f} mV/cell (was 31), current "
        f"{held['rmse_i_cv_pct']:.1f} %, delivered {held['capacity']['error_pct']:+.1f} %. Every "
        "discharge's report says its delivered error against the 3 % limit (`capacity.ok`); a model that misses it "
        'is "not a fit". Run on its own log\'s program (fit.md, "Its own program"), the hold is held too.\n'
        '* **A window too small to fix the capacity.** A capacity from a log is its charge over '
        'the share of the range it covered, and that share comes from the OCV table: on a third of the range a few '
        "per cent of error in the table is a large part of the capacity (the issue's log fitted 4 386 mAh at 51 % "
        'where another start state fits as well). A window is taken to fix the capacity where it covers at least '
        'half the range: by the fitted capacity, and for lithium also by the OCV table between its first and last '
        'voltage under current (nickel and lead voltages under current lie off their flat tables by more than the '
        'tables span). Below that the capacity and start state are withheld (`params` null in `--json`, `withheld` '
        f"names them) with the range covered. On the training curves: {withheld}: those figures were never a "
        "capacity.\n* **Cells impossible next to each other.** Cells of one pack differing more than 2× in "
        "capacity or 10× in resistance (the issue's 2 005 mAh / 382 mΩ next to 8 128 mAh / 8.6 mΩ) are flagged as "
        "a fit's trade, not measurements, and no weakest cell is named; each cell's capacity is withheld where its "
        "own tap covers under half its range.\n* **Heat terms.** They are fitted only where the log has a "
        f"temperature probe (a nickel charge or discharge without one keeps the chemistry's: {', '.join(no_probe)}; "
        "the eStation pack's heat loss, fitted to its voltage alone, went to its bound and warmed the model 20 °C), "
        "and reported only where the fitted temperature rise is within ±3 °C of the pack's: "
        f"{dropped or 'none withheld'}. The other probe logs' nickel fits are within "
        f"{min(kept):.1f}–{max(kept):.1f} °C."
    )

def _own_program_text(answers: dict, discharges: dict) -> str:
    """Each fitted model on its own log's program (issue 35 §4, sim/fit_predict.py), and why a miss misses."""
    from zuml_studio.sim.compare import real_end
    from zuml_studio.sim.fit_predict import predict_own

    fits = {name: a[2] for name, a in answers.items()} | {name: d[4] for name, d in discharges.items()}
    rows, misses = [], []
    for name, fitted in fits.items():
        p = predict_own(fitted)
        if p is None:
            rows.append(f"| {name} | – | – | – | – | no program: the log just stops |")
            continue
        rows.append(f"| {name} | {p['real_mah']:.0f} / {p['model_mah']:.0f} | {p['charge_error_pct']:+.1f} % | "
                    f"{p['real_s'] / 60:.0f} / {p['model_s'] / 60:.0f} | {p['time_error_pct']:+.1f} % | "
                    f"`{p['why']}` |")
        if max(abs(p["charge_error_pct"]), abs(p["time_error_pct"])) > 10.0:
            misses.append((name, fitted, p))
    why = []
    for name, fitted, p in misses:
        curve, series = fitted.curve, fitted.battery.series
        end = real_end(curve, fitted.chemistry, series)
        if end["kind"] != "dv":
            why.append(f"* {name}: {p['charge_error_pct']:+.1f} % charge, {p['time_error_pct']:+.1f} % time.")
            continue
        drop = float(end["values"]["drop"])
        s = smooth(curve.t, curve.v)
        first = int(np.flatnonzero(np.maximum.accumulate(s) - s >= drop * series / 1000.0)[0])
        why.append(
            f"* {name}: {p['charge_error_pct']:+.1f} % charge, {p['time_error_pct']:+.1f} % time, ended by "
            f"`{p['why']}`. The log's end is no -dV a program can state: its own 1-minute voltage falls the "
            f"{drop:g} mV/cell it ends below its peak already at {curve.mah[first]:.0f} mAh, "
            f"{(curve.t[-1] - curve.t[first]) / 60:.0f} min before the charger stopped at {curve.mah[-1]:.0f} mAh "
            f"({(curve.mah[first] / curve.mah[-1] - 1) * 100:+.0f} %), so the program's DELTA_PEAK would end the "
            f"log itself short. The model falls {fitted.figures['peak']['model_dv_mv_per_cell']:g} mV/cell after "
            f"its peak (the log {fitted.figures['peak']['real_dv_mv_per_cell']:g}) and runs on to the charger's "
            "own limit (tests/sim/test_fit_predict.py holds it as a strict xfail).")
    return "\n".join([
        "Each fitted model run on the program its own log ran (`sim/fit_predict.py`: the log's current and end as "
        "a macro, from the fit's start state, on the simulator; a discharge whose charger held its end voltage "
        "holds it too; fit.md \"Its own program\"), against the log: charge (mAh, log / model) and end time "
        "(min, log / model). The issue's limit is 10 % on each (tests/sim/test_fit_predict.py, one test per curve).",
        "",
        "| curve | charge, log / model (mAh) | off | end, log / model (min) | off | the model's end |",
        "|---|---|---|---|---|---|",
        *rows,
        "",
        f"{len(rows) - len(misses)} of {len(rows)} within 10 % on both."
        + (" The misses, measured:" if misses else ""),
        *([""] + why if why else []),
    ])


def _plot(name: str, curve, default, fitted, series: int, with_r=None) -> str:
    import pyqtgraph as pg
    from pyqtgraph.exporters import ImageExporter
    from PySide6.QtWidgets import QApplication

    QApplication.instance() or QApplication([])
    pg.setConfigOptions(background="w", foreground="k", antialias=True)
    win = pg.GraphicsLayoutWidget()
    win.resize(900, 560)
    t = curve.t / 60.0
    top = win.addPlot(row=0, col=0, title=f"{name}: voltage per cell")
    top.addLegend(offset=(10, 10))
    top.setLabel("left", "V per cell")
    top.plot(t, curve.v / series, pen=pg.mkPen("k", width=2), name="real")
    top.plot(t, default.run.v / series, pen=pg.mkPen((30, 90, 220), width=1.5), name="default model")
    if with_r is not None:
        top.plot(t, with_r.run.v / series, pen=pg.mkPen((30, 150, 60), width=1.5),
                 name="default, measured resistance")
    top.plot(t, fitted.run.v / series, pen=pg.mkPen((220, 40, 40), width=1.5, style=pg.QtCore.Qt.DashLine),
             name="fitted model")
    low = win.addPlot(row=1, col=0)
    low.setXLink(top)
    low.setLabel("bottom", "time", units="min")
    if curve.temp is not None and not fitted.cv.any():
        low.setLabel("left", "°C")
        low.plot(t, curve.temp, pen=pg.mkPen("k", width=2))
        low.plot(t, default.run.temp, pen=pg.mkPen((30, 90, 220), width=1.5))
        low.plot(t, fitted.run.temp, pen=pg.mkPen((220, 40, 40), width=1.5, style=pg.QtCore.Qt.DashLine))
    else:
        low.setLabel("left", "A")
        low.plot(t, curve.i, pen=pg.mkPen("k", width=2))
        low.plot(t, default.run.i, pen=pg.mkPen((30, 90, 220), width=1.5))
        low.plot(t, fitted.run.i, pen=pg.mkPen((220, 40, 40), width=1.5, style=pg.QtCore.Qt.DashLine))
    win.ci.layout.setRowStretchFactor(0, 3)
    win.ci.layout.setRowStretchFactor(1, 2)
    win.show()
    QApplication.processEvents()
    FIG_DIR.mkdir(parents=True, exist_ok=True)
    out = FIG_DIR / f"{name}.png"
    exporter = ImageExporter(win.scene())
    exporter.export(str(out))
    return f"validation/{out.name}"


def _fmt(x) -> str:
    return "–" if x is None else f"{x:g}"


def _row(kind: str, fig: dict) -> str:
    p, t, c = fig["peak"], fig["temp_rise"], fig.get("capacity")
    peak = f"{p['model_mah']:g} / {p['real_mah']:g}" if p else "–"
    dv = f"{p['model_dv_mv_per_cell']:g} / {p['real_dv_mv_per_cell']:g}" if p else "–"
    temp = f"{t['model_c']:g} / {t['real_c']:g}" if t else "–"
    delivered = f"{c['model_mah']:g} / {c['real_mah']:g}" if c else "–"
    return (f"| {kind} | {_fmt(fig['rmse_v_per_cell_mv'])} | {_fmt(fig['rmse_i_cv_pct'])} | {peak} | {dv} | "
            f"{temp} | {delivered} |")


def _capacity_off(fig: dict) -> str:
    c = fig.get("capacity")
    return f"{(c['model_mah'] / c['real_mah'] - 1) * 100:+.1f} %" if c else "–"


def _cv_tail(curve, chemistry: str) -> tuple[float, float, float]:
    """(CV minutes, share of the charge's time in CV, share of its mAh put in during CV)."""
    from zuml_studio.sim.fit import cv_mask
    cv = cv_mask(curve, chemistry)
    if not cv.any():
        return 0.0, 0.0, 0.0
    k = int(np.argmax(cv))
    mah = curve.mah
    return ((curve.t[-1] - curve.t[k]) / 60.0, (curve.t[-1] - curve.t[k]) / curve.t[-1],
            (mah[-1] - mah[k]) / mah[-1])


def _pb_rest(samples: Path, fitted) -> str:
    src = samples / "curves" / "PbAcid_12V_100Ah_Universal_UB121000_charge_rest_discharge_5s.csv"
    if not src.is_file():
        return "(the source recording was not found, so the rest after the charge is not analysed here)"
    rows = list(csv.DictReader(open(src, newline="")))
    t = np.array([float(r["Time Elapsed"]) * 86400.0 for r in rows])
    i = np.array([float(r["Current (Calibrated)"]) for r in rows])
    v = np.array([float(r["Voltage (Calibrated)"]) for r in rows])
    on = np.flatnonzero(i > 0.5)
    end = on[-1]
    after = np.flatnonzero(np.abs(i[end + 1:]) > 0.5)
    stop = end + 1 + (after[0] if len(after) else len(i) - end - 1)
    rest_t, rest_v = t[end + 1:stop] - t[end], v[end + 1:stop]
    minutes = (1, 10, 30, 60, 120)
    pick = {m: float(np.interp(m * 60.0, rest_t, rest_v)) for m in minutes}
    # The fitted model, rested after the same charge.
    curve = fitted.curve
    rest = np.arange(10.0, 7201.0, 10.0)
    longer = Curve(np.concatenate((curve.t, curve.t[-1] + rest)), np.concatenate((curve.v, np.full(len(rest), curve.v[-1]))),
                   np.concatenate((curve.i, np.zeros(len(rest)))), None, curve.cells, curve.name)
    cv = np.concatenate((fitted.cv, np.zeros(len(rest), bool)))
    run = simulate_curve(fitted.battery, longer, cv, fitted.params["start_soc"])
    model = {m: float(np.interp(curve.t[-1] + m * 60.0, longer.t, run.v)) for m in minutes}
    return (f"At the end of the absorption the pack reads {v[end]:.3f} V at {i[end]:.2f} A. Resting, it reads "
            + ", ".join(f"{pick[m]:.3f} V after {m} min" for m in minutes)
            + f" ({(pick[1] - pick[120]) / 6 * 1000:.0f} mV per cell between 1 and 120 min). The fitted model "
            "reads " + ", ".join(f"{model[m]:.3f} V" for m in minutes)
            + f" ({(model[1] - model[120]) / 6 * 1000:.0f} mV per cell). The surface charge of the real "
            "battery relaxes over tens of minutes and hours; the model's polarisation, fitted to the charge "
            f"(`pol_tau_s` {fitted.params['pol_tau_s']:.0f} s), is gone within minutes and its OCV is the table's. "
            "Here the data contradict the model; a second, slow polarisation time constant would be needed "
            "to simulate a rest or a float after absorption (not done: the charge itself fits within the limits).")


def _recordsets(path: Path) -> list[tuple[str, dict[str, np.ndarray]]]:
    """The notes' conversion of a DataExplorer .osd (realdata/samples/curves/*.csv): '### RECORDSET'
    blocks of a '# ... recordset='NAME' ...' line, a header and rows; columns keyed by their first word."""
    sets = []
    for block in path.read_text(encoding="utf-8").split("### RECORDSET")[1:]:
        lines = [ln for ln in block.strip().splitlines() if ln]
        name = lines[0].split("recordset='", 1)[1].split("'", 1)[0]
        head = next(csv.reader([lines[1]]))
        rows = np.array([[float(x) for x in ln.split(",")] for ln in lines[2:] if not ln.startswith("#")])
        sets.append((name, {h.split(" [")[0].split()[0]: rows[:, k] for k, h in enumerate(head)}))
    return sets


def _ni_resistance(samples: Path) -> dict | None:
    """Each NiMH pack's resistance per cell (Ω) where its recording shows the voltage step of the charge
    current stopping: 1 s after the end of every charge (Ultramat, Polaron Pro), 3 s into the eStation
    BC6's once-a-minute pauses (its first 1.5 s sample often straddles the pause's start); plus the
    Polaron's own Ri channel and the Ultramat's charge current range."""
    files = {"ultramat": (4, "NiMH_4S_Ultramat_ACDC_EQ_cycle.csv"), "polaron": (5, "NiMH_5S_PolaronPro_cycle_with_temp.csv"),
             "estation": (4, "NiMH_AA_Rx_eStationBC6_cycle.csv")}
    if not all((samples / "curves" / f).is_file() for _, f in files.values()):
        return None
    out: dict = {}
    for key, (cells, fname) in files.items():
        sets = _recordsets(samples / "curves" / fname)
        charges = [(k, d) for k, (n, d) in enumerate(sets) if "laden" in n.lower() and "entladen" not in n.lower()]
        steps = []
        for k, d in charges:
            v, i = d["Spannung"], d["Strom"]
            if key == "estation":
                on = float(np.median(i))
                t = d["time_s"]
                steps += [s.ohm_per_cell(cells) for s in rest_steps(t, v, i, min_current_a=0.9 * on, delay_s=3.0)]
                out.setdefault("estation_first", []).extend(
                        s.ohm_per_cell(cells) for s in rest_steps(t, v, i, min_current_a=0.9 * on, delay_s=1.5))
            elif k + 1 < len(sets):
                # The rest is the next record set, its first sample at the step (the current still on).
                rest = sets[k + 1][1]
                steps += [s.ohm_per_cell(cells) for s in rest_steps(
                        np.r_[0.0, rest["time_s"][1:]], np.r_[v[-1], rest["Spannung"][1:]],
                        np.r_[i[-1], rest["Strom"][1:]])]
        out[key] = np.array(steps)
        if "BatteríeRi" in charges[0][1]:
            ri = np.concatenate([d["BatteríeRi"] for _, d in charges])
            out["polaron_ri"] = ri[ri > 0] / 1000.0 / cells
        if key == "ultramat":
            out["ultramat_i"] = np.concatenate([d["Strom"][5:] for _, d in charges])
    return out


def _ultramat_resistance(samples: Path, answers: dict, default) -> str:
    r = _ni_resistance(samples)
    if r is None:
        return "(the source recordings were not found, so the packs' resistance is not measured here)"
    u, p, e = r["ultramat"], r["polaron"], r["estation"]
    mohm = ", ".join(f"{x * 1000:.0f}" for x in u)
    peak = {k: answers[n][2].figures["peak"]["real_mah"] / 1000.0 for k, n in
            (("u", "nimh_4s_ultramat_05c"), ("p", "nimh_5s_polaron_03c"), ("e", "nimh_4s_estation_1c"))}
    rc = {"u": u.mean() * peak["u"] / 2, "p": p.mean() * peak["p"] / 2, "e": np.median(e) * peak["e"] / 2}
    like = rc["p"] * 2 / peak["u"]        # a pack of the Ultramat's capacity with the Polaron's R × C
    return ("* **The pack's resistance.** The Ultramat log rests after every charge. One second after the "
            f"0.5 A charge current stops the pack's fall per cell and ampere is {mohm} mΩ (mean "
            f"{u.mean() * 1000:.0f}). The Polaron Pro pack's is {p.mean() * 1000:.0f} mΩ at the end "
            f"of its charge, and its charger's own Ri channel reads {np.median(r['polaron_ri']) * 1000:.0f} mΩ "
            "per cell (median over the charge); the eStation BC6 pauses its 1 A charge every minute "
            f"and its pack's is {np.median(e) * 1000:.0f} mΩ (median of {len(e)} pauses, 3 s into "
            "them). Per capacity (R × C at 2 Ah, C the charge at the peak) that is "
            f"{rc['u'] * 1000:.0f} mΩ for the Ultramat pack, {rc['p'] * 1000:.0f} for the Polaron and "
            f"{rc['e'] * 1000:.0f} for the eStation: the Ultramat pack, as its charger sees it through leads and "
            "connectors, has about twice the resistance of the others. At 0.5 A that is "
            f"{0.5 * (u.mean() - like) * 1000:.0f} mV per cell more drop than a pack of its capacity with the "
            "Polaron's R × C from the 1 s step alone, more with the slower polarisation: most of the offset "
            "above. The default model's step at the capacity it fits "
            f"({default.params['capacity_mah']:.0f} mAh) is {_model_step(default) * 1000:.0f} mΩ per cell, the "
            f"fitted model's {_model_step(answers['nimh_4s_ultramat_05c'][2]) * 1000:.0f}. The AkkuMaster log "
            "(one 0.15 A charge, no rest) shows no step.\n"
            f"* **Not the measuring convention.** The Ultramat charge current is {r['ultramat_i'].min():.3f}–"
            f"{r['ultramat_i'].max():.3f} A at every 1 s sample of its five charges: it measures with the current "
            "flowing, as the Polaron does and as the compared eStation samples are (the fit leaves out its "
            "pause samples). The AkkuMaster CSV shows 0.150 A at every sample; nothing in `realdata/` says it "
            "measures in current-off pauses.")


def _model_step(result, after_s: float = 1.0) -> float:
    """The model's fall per cell and ampere `after_s` after the current stops: R0 and that much of R1."""
    b = result.battery
    scale = b.chem.ref_capacity_ah * 1000.0 / b.capacity_mah
    return scale * (b.chem.r0_ohm + b.chem.r1_ohm * (1.0 - np.exp(-after_s / b.chem.tau1_s)))


def _measured_r_text(answers: dict, defaults: dict, with_r: dict, steps: dict) -> str:
    """Decision (a) of issue 26: what the default makes of each NiMH charge with the resistance measured
    at its log's rests."""
    names = [n for n in ("nimh_4s_ultramat_05c", "nimh_5s_polaron_03c", "nimh_4s_estation_1c") if n in with_r]
    parts = [f"{n} {with_r[n][0].figures['rmse_v_per_cell_mv']:.1f} mV/cell (was "
             f"{defaults[n].figures['rmse_v_per_cell_mv']:.1f}; {steps[n]['mohm_per_cell']:.0f} mΩ per cell, "
             f"R × {with_r[n][1]:.2f})" for n in names]
    return ("So the cause is a property of this pack (its resistance), not of the charger or the start; the "
            "log measures it, but in the rests around the charges, not in the extracted charge (its own start, "
            "from rest into 0.33 then 0.50 A, reads 300 mΩ per cell: the overvoltage of an emptied cell, not "
            "its resistance). Decision (a) of issue 26: where a log has a current step or a rest, "
            "`zuml compare` (and Compare with Log) measures the pack's resistance there and runs the default "
            "model with R0 and R1 scaled so that its step at the same delay is the measured one, as it takes "
            "the start voltage and the capacity from the log, and says so in its header line ("
            "`zuml_studio/sim/measured_r.py`). The curves here leave the rests out, so the resistance is "
            "measured on the whole source log by `tools/extract_curves.py` (`tests/data/curves/rest_steps.json`: "
            "the steps of the curve's own direction and at least half its current, within it or in the ten "
            "minutes after it, else anywhere in the log; read 1 s after the current stops, or at twice the "
            "period of a log sampled slower). That is the table's middle column: "
            + "; ".join(parts) + f"; the AkkuMaster log has no step and keeps its "
            f"{defaults['nimh_4s_akkumaster_02c'].figures['rmse_v_per_cell_mv']:.1f}. The plain default keeps "
            "its figure (and its marked miss) in the first column.")


def _nicd_cells_text() -> str:
    """Why the Akkumatik NiCd pack is 4 cells: its log names no cell count (the .osd's cell-voltage records
    are all 0), so the voltages decide."""
    a = read_curve(CURVES / "nicd_4s_akkumatik_08c.csv")
    d = read_curve(CURVES / "nicd_4s_akkumatik_dis_1c.csv")
    per = {n: (float(a.v.max()) / n, float(np.median(a.v)) / n, end_voltage(d) / n) for n in (4, 5)}
    return ("Its log (`Akkumatik_2015-03-27_NiCd_E-L_Cycle.osd`) names no cell count: its six cell-voltage "
            "records read 0 throughout. Its voltages say 4 cells: as 4 the charge peaks at "
            f"{per[4][0]:.2f} V/cell (median {per[4][1]:.2f}) and the discharge stops at {per[4][2]:.3f}; as 5 "
            f"it would peak at {per[5][0]:.2f} V/cell (median {per[5][1]:.2f}), below a full NiCd cell's rest "
            f"voltage, and stop at {per[5][2]:.3f}, no charger's end voltage. The charge curve was first taken as "
            "5 cells, and the NiCd default (resistance × 0.15, OCV 37 mV lower) was tuned on that; with the "
            "resistance its rests show the default then lost its -dV. As 4 cells "
            "(`nicd_4s_akkumatik_08c`) its rests step 194 mΩ per cell 1 s after the current stops: with its "
            "leads about 10× a 1.2 Ah NiCd cell's own, which at 2C would stop a charge at 1.8 V/cell before "
            "full. The NiCd default keeps a cell's own resistance (R0 + R1 22 mΩ at 1 Ah, split 10:1 as the "
            "rests' step is 0.9× the fitted R0 + R1) and takes the rest of its charge shape (OCV, `w0`, "
            "`dv_o2_v`, dip, heat) from the fit of this charge with its own resistance; so the plain default "
            "misses this pack by its resistance (marked), and with the measured resistance it meets the "
            "limits with its -dV (the table's middle column).")


# The packs recorded both ways: (charge curve, discharge curve).
_BOTH_WAYS = (("nimh_4s_ultramat_05c", "nimh_4s_ultramat_dis_05c"),
              ("nimh_5s_polaron_03c", "nimh_5s_polaron_dis_03c"),
              ("nimh_4s_estation_1c", "nimh_4s_estation_dis_1c"),
              ("nimh_4s_akkumaster_02c", "nimh_4s_akkumaster_dis_015c"),
              ("nicd_4s_akkumatik_08c", "nicd_4s_akkumatik_dis_1c"))


def _hysteresis_text(answers: dict, discharges: dict) -> str:
    """Each pack's discharge against the model fitted to its own charge (capacity and start fitted, no
    hysteresis): where it lies below, over the middle of the discharge (10-80 % of what it delivered)."""
    rows, gaps = [], []
    for charge, discharge in _BOTH_WAYS:
        entry, curve, fitted = answers[charge]
        d_entry, d_curve = discharges[discharge][:2]
        chem = replace(fitted.battery.chem, hyst_v=0.0)
        on_charge = fit_curve(d_curve, chem.name, d_entry["cells"], only_capacity=True, base=chem)
        use = discharging(d_curve)
        mah = d_curve.delivered_mah[use]
        mid = (mah > 0.1 * mah[-1]) & (mah < 0.8 * mah[-1])
        gap = float(np.mean((on_charge.run.v[use] - d_curve.v[use])[mid]) / d_entry["cells"] * 1000.0)
        amps = float(np.median(-d_curve.i[use]))
        rows.append(f"| {entry['chemistry']} {entry['cells']}S ({charge.split('_')[2]}) | {amps:.2f} A | "
                    f"{fitted.params['r_scale']:.2f} | {gap:+.0f} |")
        if entry["chemistry"] == "NiMh":
            gaps.append(gap)
    chem = load_chemistry("NiMh")
    return "\n".join([
        "Each pack recorded both ways, its discharge run on the model fitted to its own charge (only the "
        "capacity and start state fitted to the discharge, no hysteresis), the discharge's mean error over "
        "10-80 % of what it delivered:",
        "",
        "| pack | discharge current | charge fit's resistance (× default) | model above the discharge (mV/cell) |",
        "|---|---|---|---|",
        *rows,
        "",
        f"Every pack's discharge lies below its charge's model, the NiMH packs by {min(gaps):.0f}–{max(gaps):.0f} "
        f"mV/cell (median {float(np.median(gaps)):.0f}). At one current a charge cannot tell its OCV from its "
        "resistance (both shift the voltage at constant current), so part of each gap may be resistance the "
        "charge fit gave to the OCV; but the gaps do not grow with the current as a resistance would (the "
        "AkkuMaster and Polaron packs at 0.15 and 0.6 A, the eStation at 1 A), and all lie on the same "
        "side: NiMH's charge/discharge OCV hysteresis, as the literature has it. The model holds it in the "
        "simplest form that follows these data, one state h (Plett): the cell's voltage is lowered by "
        "`hyst_v` × (1 − h) / 2; h moves towards +1 (the charge branch, the OCV table) while charging and "
        "towards −1 (the discharge branch) while discharging, e-fold over `hyst_soc` of the capacity "
        f"(sim/battery.py). NiMH: `hyst_v` {chem.hyst_v * 1000:.0f} mV (a shift scanned from 0 to 50 mV on "
        "the four NiMH discharges: the default within twice the limits on the Ultramat, Polaron and eStation "
        f"ones from 45 mV), `hyst_soc` {chem.hyst_soc:g}; a pack starts on its charge branch, so charges "
        "are unchanged. The NiCd pack's gap comes with a resistance 10× the default's at one current and "
        "cannot be told from it: NiCd and the others keep `hyst_v` 0 (their runs are unchanged).",
    ])


def _discharge_text(discharges: dict) -> str:
    """What the recorded discharges say: end voltage, delivered charge, where the model misses."""
    rows, biases = [], {}
    for name, (entry, curve, default, with_r, fitted) in discharges.items():
        use = discharging(curve)
        bias = float(np.mean((default.run.v[use] - curve.v[use]) / entry["cells"] * 1000.0))
        biases[name] = bias
        rows.append(f"| {name} | {entry['chemistry']} {entry['cells']}S | {entry['rate']} | "
                    f"{curve.delivered_mah[-1]:.0f} | {end_voltage(curve) / entry['cells']:.3f} | {bias:+.0f} | "
                    f"{_capacity_off(default.figures)} | {_capacity_off(fitted.figures)} |")
    return "\n".join([
        "| curve | battery | rate | delivered (mAh) | end (V/cell) | default's mean error (mV/cell) | "
        "delivered, default | delivered, fitted |",
        "|---|---|---|---|---|---|---|---|",
        *rows,
        "",
        "* The fitted model meets the discharge limits on every recording (the AkkuMaster pack's with its weak "
        "cell), and the delivered capacity within 3 % on all. The default (capacity and start fitted) meets "
        "twice the voltage limit on all but the AkkuMaster pack (its weak cell) and the Akkumatik NiCd pack "
        "(its resistance).",
        "* The default NiMH OCV is fitted to four charges; its discharge branch lies `hyst_v` lower (see "
        "\"Hysteresis\" below). The default's mean error on the NiMH discharges: "
        + ", ".join(f"{n.split('_')[2]} {biases[n]:+.0f}" for n in biases if n.startswith("nimh")) + " mV/cell.",
        "* The AkkuMaster pack (0.15 A) falls from 4.6 to 3.45 V within a minute at 145 min, by one cell's "
        "1.15 V, then goes on at 3 × 1.15 V: one cell of the four empties first. A pack of identical cells "
        "cannot show that (the default misses by "
        f"{discharges['nimh_4s_akkumaster_dis_015c'][2].figures['rmse_v_per_cell_mv']:.0f} mV/cell, marked, "
        "and the fit with equal cells by "
        f"{discharges['nimh_4s_akkumaster_dis_015c'][4].figures['weak_cell']['rmse_equal_cells_mv']:.0f}). "
        "The discharge fit finds the weak cell from that step (fit.md, \"A weak cell\"): one cell of "
        f"{discharges['nimh_4s_akkumaster_dis_015c'][4].figures['weak_cell']['capacity_mah']:.0f} mAh, "
        f"{discharges['nimh_4s_akkumaster_dis_015c'][4].figures['weak_cell']['capacity_share'] * 100:.0f} % "
        f"of the others' {discharges['nimh_4s_akkumaster_dis_015c'][4].figures['weak_cell']['others_mah']:.0f}, "
        f"at {discharges['nimh_4s_akkumaster_dis_015c'][4].figures['rmse_v_per_cell_mv']:.0f} mV/cell; no other "
        "recorded discharge steps by a cell. The log has no taps: which cell it is, it cannot say.",
        "* The Akkumatik NiCd discharge ends at 3.40 V, 4 × 0.85 V (NiCd's usual end voltage). " + _nicd_cells_text(),
        "* The eStation BC6 and Ultramat discharges end 30 s before their next record set starts: no step "
        "to measure there; the Pb battery rests after its discharge (8 mΩ per cell 10 s after 10 A stops).",
        _pb_lead(discharges["pb_6s_ub121000_dis_01c"][1]),
    ])


def _pb_lead(curve) -> str:
    """The Pb recording's current column reads -10 A for minutes before the pack's voltage moves."""
    k = int(np.argmax(curve.v < curve.v[0] - 0.1))
    j = k + int(np.argmax(curve.t[k:] >= curve.t[k] + 60.0))
    return (f"* The Pb recording's current column reads -10 A for its first {curve.t[k] / 60:.0f} min while the "
            f"voltage stays at the rest's {curve.v[0]:.2f} V, then falls {curve.v[k - 1] - curve.v[j]:.2f} V within "
            "a minute: the load came on later than the column says. The curve keeps the file's values; the "
            f"delivered capacity counts those minutes ({curve.t[k] / 3600 * 10:.1f} Ah of "
            f"{curve.delivered_mah[-1] / 1000:.1f}), and the models, driven by the same column, count them too.")


def _bias_and_spread(result, series: int) -> tuple[float, float]:
    """The default's mean error over the compared samples (model - real, mV/cell) and what is left of
    its RMSE once that mean is taken out (RMSE² = mean² + spread²)."""
    use = measured(result.curve, result.cv)
    err = (result.run.v[use] - result.curve.v[use]) / series * 1000.0
    return float(err.mean()), float(err.std())


def _no_default_text(answers: dict, defaults: dict) -> str:
    """Why no default of this model's form meets all four NiMH packs: the shift each pack's mean error
    allows, as a function of what a default can know (rate, current, capacity)."""
    rows, bounds = [], {}
    limit = 40.0
    for name, (entry, curve, _) in answers.items():
        if entry["chemistry"] != "NiMh":
            continue
        d = defaults[name]
        bias, spread = _bias_and_spread(d, entry["cells"])
        room = float(np.sqrt(max(limit ** 2 - spread ** 2, 0.0)))
        lo, hi = -room - bias, room - bias
        amps = float(cc_current(curve, d.cv))
        ah = d.figures["peak"]["real_mah"] / 1000.0
        bounds[name] = (lo, hi, amps / ah, ah)
        rows.append(f"| {name} | {amps / ah:.2f}C | {amps:.2f} A | {ah:.2f} Ah | {bias:+.1f} | {spread:.1f} | "
                    f"{lo:+.1f} … {hi:+.1f} |")
    u, e, a = (bounds[f"nimh_4s_{n}"] for n in ("ultramat_05c", "estation_1c", "akkumaster_02c"))
    return "\n".join([
        "No default of this model's form can meet all four, whatever its values: the table gives each "
        "pack's default mean error (model − real over the compared samples) and the spread left around "
        "that mean. A change of the default that moves a pack's charge voltage by g mV/cell (an offset, a "
        "resistance, any overvoltage of the current) keeps RMSE² = (mean + g)² + spread² within the "
        f"{limit:.0f} mV/cell limit only for g in the last column (with the spread it has now).",
        "",
        "| curve | rate | current | capacity | mean error (mV/cell) | spread | g that meets 40 |",
        "|---|---|---|---|---|---|---|",
        *rows,
        "",
        f"The Ultramat pack at {u[2]:.2f}C needs g ≥ {u[0]:+.0f} mV/cell while the eStation pack at "
        f"{e[2]:.2f}C allows at most {e[1]:+.0f}: the shift would have to fall as the rate rises, and no "
        "overvoltage of a charging current does that. By current in amperes it sits between the "
        f"AkkuMaster pack ({a[2] * a[3]:.2f} A, at most {a[1]:+.0f}) and the eStation pack ({e[2] * e[3]:.2f} A, "
        f"at most {e[1]:+.0f}) as well, so neither a resistance that scales with the capacity (the model's "
        "R × Ah: a function of the rate) nor one per ampere can do it. "
        "What a default knows (chemistry, cells, capacity, current, ambient) does not tell this pack from "
        "the others; its resistance does (below), and a user gets it by fitting the pack's own log "
        "(`zuml fit`, then the named battery).",
    ])


def main() -> int:
    samples = Path(sys.argv[1]) if len(sys.argv) > 1 else ROOT.parent / "shared" / "realdata" / "samples"
    os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")
    training = tomllib.loads((CURVES / "training.toml").read_text())
    steps = json.loads((CURVES / "rest_steps.json").read_text())
    sections, summary, answers, defaults, with_r, discharges = [], [], {}, {}, {}, {}
    started = time.perf_counter()
    for name, entry in training.items():
        chem, series = entry["chemistry"], entry["cells"]
        curve = read_curve(CURVES / f"{name}.csv")
        t0 = time.perf_counter()
        default = fit_curve(curve, chem, series, only_capacity=True)
        fitted = fit_curve(curve, chem, series)
        seconds = time.perf_counter() - t0
        if steps.get(name):
            with_r[name] = fit_with_measured_r(curve, chem, series, MeasuredR.from_dict(steps[name]))
        measured_r = with_r.get(name, (None,))[0]
        png = _plot(name, curve, default, fitted, series, measured_r)
        if curve.direction == "discharge":
            discharges[name] = (entry, curve, default, measured_r, fitted)
        else:
            answers[name] = (entry, curve, fitted)
        defaults[name] = default
        r_text = (f"{_fmt(measured_r.figures['rmse_v_per_cell_mv'])} ({steps[name]['mohm_per_cell']:.0f} mΩ)"
                  if measured_r else "no step")
        summary.append(f"| [{name}](#{name}) | {chem} {series}S | {curve.direction} | {entry['rate']} | "
                       f"{_fmt(default.figures['rmse_v_per_cell_mv'])} | {r_text} | "
                       f"{_fmt(fitted.figures['rmse_v_per_cell_mv'])} | {_capacity_off(fitted.figures)} |")
        params = ", ".join(f"{k} {v:.4g}" for k, v in fitted.params.items())
        moved = (f"{curve.mah[-1]:.0f} mAh put in" if curve.direction == "charge" else
                 f"{curve.delivered_mah[-1]:.0f} mAh taken out to {end_voltage(curve) / series:.3f} V/cell")
        rows = [_row("default (capacity and start fitted)", default.figures)]
        if measured_r:
            rows.append(_row(f"default, resistance measured at the rests ({steps[name]['mohm_per_cell']:.0f} mΩ "
                             f"per cell, R × {with_r[name][1]:.2f})", measured_r.figures))
        sections.append("\n".join([
            f"### {name}", "",
            f"`{entry['source_file']}` — {chem}, {series} cells, {curve.direction}, {entry['rate']}; "
            f"{curve.t[-1] / 60:.0f} min, {moved}. Default and fitted in {seconds:.1f} s.", "",
            f"![{name}]({png})", "",
            "| model | RMSE V (mV/cell) | RMSE I in CV (% of CC) | peak at (mAh, model / real) | "
            "-dV (mV/cell, model / real) | temperature rise (°C, model / real) | delivered (mAh, model / real) |",
            "|---|---|---|---|---|---|---|",
            *rows,
            _row("fitted", fitted.figures), "",
            f"Fitted: {params}.", ""]))
    total = time.perf_counter() - started
    dv_rows = []
    for name, (entry, curve, fitted) in answers.items():
        if entry["chemistry"] in NI:
            p = fitted.figures["peak"]
            s = smooth(curve.t, curve.v)
            k = int(np.argmax(s))
            rise = (f"{curve.temp[k] - curve.temp[0]:.1f} °C to the peak, {curve.temp[-1] - curve.temp[k]:+.1f} °C "
                    "after it") if curve.temp is not None else "not recorded"
            dv_rows.append(f"| {name} | {entry['chemistry']} | {entry['rate']} | {p['real_dv_mv_per_cell']:g} | "
                           f"{p['real_mah']:g} of {curve.mah[-1]:.0f} | {rise} |")
    cv_rows = []
    for name, (entry, curve, fitted) in answers.items():
        if entry["chemistry"] in LI + ("Pb",):
            minutes, share_t, share_q = _cv_tail(curve, entry["chemistry"])
            i_cc = cc_current(curve, fitted.cv)
            cv_rows.append(f"| {name} | {entry['chemistry']} | {entry['rate']} | {minutes:.1f} | {share_t:.0%} | "
                           f"{share_q:.0%} | {curve.i[-1] / i_cc:.0%} |")
    text = "\n".join([
        "# The battery models against real charges and discharges",
        "",
        "Generated by `tools/validation.py` (do not edit by hand). Every curve in `tests/data/curves/` "
        "(sources: `tests/data/README.md`) is run through `zuml_studio.sim.fit` (a discharge through "
        "`sim/fit_discharge.py`, see [fit.md](fit.md)) three times: **default** keeps the "
        "chemistry's TOML and fits only the capacity and the start state of charge; **default, measured "
        "resistance** does the same with R0 and R1 scaled so that the model's step where the current stops "
        "is the one measured at the rests of the curve's source log (issue 26, decision (a): what `zuml "
        "compare` runs; \"no step\" where the log has none); **fitted** also fits the "
        "resistance (one factor on R0, R1 and, where not fitted itself, R2), an OCV offset and scale per cell "
        "(about the table's mean), and per family: NiCd/NiMH charge acceptance `w0`, O2 overvoltage `dv_o2_v`, "
        "the overcharge dip `dip_v_per_charge` and `dip_tau_s`, "
        "temperature coefficient `k_t_v_per_k`, heat loss `ha_w_per_k`; Li the slow RC pair `r2_ohm`, "
        "`tau2_s` (the CV tail) and solid-state diffusion `diffusion_tau_s`; Pb the charge polarisation "
        "`k_charge_ohm`, `pol_tau_s`, `pol_max_v` (absorption and taper) and its charge acceptance `w0` and "
        "gassing voltage `dv_o2_v` (the absorption's tail). The model is driven by the log's current, and in the "
        "CV part (from where the voltage comes within 0.5 % of its maximum, while the current is below 92 % of the "
        "CC current and the voltage within 1 % of the hold's own median) by the log's voltage, its current then "
        "compared. Peak and -dV are read from a 1-minute moving average. "
        "`scipy.optimize.least_squares` (trust region, finite differences) does the fitting; the stages, "
        "weights and bounds are in [fit.md](fit.md). NiCd/NiMH also fit the heat capacity `cth_j_per_k`; the heat "
        "terms only where the log has a temperature probe. "
        "A discharge whose voltage steps down by a cell's also fits a weak cell (its capacity over the "
        "others'), kept where it lowers the RMSE materially (fit.md, \"A weak cell\").",
        "",
        "The limits (tests/sim/test_validation.py): Li RMSE(V) ≤ 15 mV/cell over CC and CV current within "
        "10 % of the CC current; NiMH/NiCd RMSE(V) ≤ 20 mV/cell, peak charge within 10 %, -dV within "
        "3 mV/cell, temperature rise within 5 °C where recorded; Pb RMSE(V) ≤ 25 mV/cell and the absorption "
        "current within 15 % of the bulk current. A discharge (issue 26): RMSE(V) ≤ 20 mV/cell Li, "
        "25 NiMH/NiCd, 30 Pb, and the delivered capacity (to the log's end voltage) within 3 %. The default "
        "model must meet twice these, with the measured resistance too. Where a curve misses, the test is "
        "marked with the reason and this page shows the figure.",
        "",
        f"All {len(training)} curves, default and fitted: {total:.0f} s on this machine.",
        "",
        "| curve | battery | direction | rate | RMSE V default (mV/cell) | default, measured resistance | "
        "fitted | delivered, fitted |",
        "|---|---|---|---|---|---|---|---|",
        *summary,
        "",
        "## What the data say",
        "",
        "### -dV depth per cell and rate; NiMH -dV at 0.1–0.2C; temperature rise",
        "",
        "| curve | chemistry | rate | -dV at the end (mV/cell) | peak at (mAh) | temperature |",
        "|---|---|---|---|---|---|",
        *dv_rows,
        "",
        "* -dV deepens with rate: NiMH 3–5 mV/cell at 0.2–0.45C (where the charger stopped it), 12 mV/cell "
        "at 1.1C; NiCd 10 mV/cell at 0.85C. 0.5C vs 1C is 3–5 vs 12 mV/cell for NiMH; no 2C recording is "
        "in the set, so 2C is not settled by data. The model's -dV threshold per cell in the macros "
        "(5 mV NiMH, 10–12 mV NiCd) is reached on every one of these packs. The model's dip comes from the "
        "overcharge the O2 cycle has taken and not yet relaxed (`dip_tau_s`), so it levels off at "
        "`dip_v_per_charge` × C-rate × `dip_tau_s` / 3600: for the default NiMH 15 mV/cell at 0.2C, 75 at 1C, "
        "150 at 2C, deeper at a higher rate as the data say.",
        "* NiMH **does** show -dV at 0.2C: the AkkuMaster C4 AA pack at 0.15 A falls 4.8 mV/cell after its "
        "peak, the Polaron 5S pack at 0.3C 4.2 mV/cell. This contradicts the old model note (\"NiMH 0.2C: "
        "plateau, no -ΔV\", battery-models.md §2.4) and agrees with seed 001 (about 5 mV). The only 0.1C "
        "recording (iCharger 3010B, 2500 mAh at 0.24 A) was stopped at 684 mAh, before any peak, so 0.1C "
        "stays open. The old model plateaued at 0.2C; the data win: the retuned default NiMH dips at 0.2C too "
        f"({defaults['nimh_4s_akkumaster_02c'].figures['peak']['model_dv_mv_per_cell']:.1f} mV/cell on the "
        "AkkuMaster curve), and tests/sim/test_acceptance.py and test_battery.py now assert a dip there.",
        "* NiMH temperature rise before the end: the Polaron pack (0.3C) rose 2.1 °C over the three hours "
        "to its peak and 2.5 °C more in the five minutes after it: the heat comes at the very end. The "
        f"retuned default model rises {defaults['nimh_5s_polaron_03c'].figures['temp_rise']['model_c']:.1f} °C "
        f"over the same charge, the fitted one {answers['nimh_5s_polaron_03c'][2].figures['temp_rise']['model_c']:.1f} °C. The NiCd pack's case sensor (1 °C steps) rose 1 °C to the peak and 1 °C after it. "
        "A model that makes its -dV from heat cannot have both (the earlier one fitted the NiCd dip with a "
        "13 °C rise, and its retuned NiMH fired a false -dV 10 minutes into a 2C charge); with the dip "
        "driven by the overcharge, the NiCd default rises "
        f"{with_r['nicd_4s_akkumatik_08c'][0].figures['temp_rise']['model_c']:.1f} °C and dips "
        f"{with_r['nicd_4s_akkumatik_08c'][0].figures['peak']['model_dv_mv_per_cell']:.1f} mV/cell on this curve "
        "with the pack's measured resistance.",
        "",
        "### CV tail: LiPo vs LiFe, and the Pb absorption",
        "",
        "| curve | chemistry | rate | CV minutes | CV share of time | CV share of charge | end current / CC |",
        "|---|---|---|---|---|---|---|",
        *cv_rows,
        "",
        "Hobby chargers end the CV at 9–13 % of the CC current here. LiPo at 2.7–3C: 4 minutes of CV, 17–22 % of "
        "the time and 7–9 % of the charge, ending at 13 % of CC. LiFe at 0.5C (a top-up): 8.4 minutes, 56 % "
        "of the time and 24 % of the charge, ending at 9 %: even at a sixth of the rate the LFP tail is "
        "twice as long, consistent with the LFP voltage rising only in the last few percent, so the "
        "charger reaches its limit with more charge still to go. That rise is curved, not the straight line "
        "from 90 to 100 % of the PyBaMM-based table: the LiFe OCV now has points at 95 % (3.40 V) and 98 % "
        "(3.48 V) fitted to this recording. The slow RC pair of the Li models carries this tail "
        "(fitted `tau2_s` in the sections below). The Pb absorption takes 3 hours (55 % of the time, 18 % "
        "of the charge) and ends at 3 % of the bulk current.",
        "",
        "### The CV tail against PyBaMM and on every lithium charge (issue 35)",
        "",
        cv_tail_section(),
        "",
        "### The CV tail on a 9S pack",
        "",
        cells_tail_section(samples),
        "",
        "### Pb surface charge",
        "",
        _pb_rest(samples, next(f for e, _, f in answers.values() if e["chemistry"] == "Pb")),
        "",
        "### Discharges",
        "",
        _discharge_text(discharges),
        "",
        "### What a fit may claim (issue 35)",
        "",
        _claims_text(answers, discharges),
        "",
        "### A fitted model on its own log's program (issue 35 §4)",
        "",
        _own_program_text(answers, discharges),
        "",
        "### Hysteresis",
        "",
        _hysteresis_text(answers, discharges),
        "",
        "### Where the default model misses",
        "",
        "One default cannot meet the Ultramat NiMH pack and the other three together: at a fifth of its "
        "charge it reads 1.449 V/cell at 0.45C, where the AkkuMaster pack reads 1.351 at 0.2C, the Polaron "
        "1.373 at 0.3C and the eStation 1.489 at 1.1C: 60 mV above the line through the others, 100 mV "
        "near the end. The default model misses it by "
        f"{defaults['nimh_4s_ultramat_05c'].figures['rmse_v_per_cell_mv']:.0f} mV/cell RMSE (limit 40). "
        "The test marks it (strict xfail); fitted, the pack meets the limits.",
        "",
        _no_default_text(answers, defaults),
        "",
        "Why, from the recordings themselves (the whole `.osd` files, not only the extracted charges):",
        "",
        _ultramat_resistance(samples, answers, defaults["nimh_4s_ultramat_05c"]),
        "* **Not the start.** Every charge starts right after a discharge: the Ultramat's after 0.5 A down to "
        "0.80 V/cell and a 3 min rest (1.185 V/cell at its end), the Polaron's after 0.6 A down to "
        "0.80 V/cell and a 3 min rest (1.126 V/cell), the eStation's after 1 A down to 0.95 V/cell with no "
        "rest. No Ultramat temperature is recorded.",
        "* **Not the cell count or capacity.** 4 cells: 1.52 V/cell 3 min after the charge, 1.16 V/cell "
        "on average under the 0.5 A discharge (5 cells would read 0.93 there and peak at 1.32 V/cell); the five cycles discharge "
        "970–1031 mAh and charge 1085–1139 mAh, so 0.5 A is 0.45–0.5C.",
        "",
        _measured_r_text(answers, defaults, with_r, steps),
        "",
        "## What changed in the models (the data win)",
        "",
        "Each changed value in `resources/chemistries/*.toml` names the recordings it was fitted to "
        "and its old value.",
        "",
        "* NiCd/NiMH: a new end-of-charge dip, `dip_v_per_charge` × the overcharge not yet relaxed "
        "(`dip_tau_s`): the -dV no longer needs heat. Tuned on the recordings with the default model (capacity "
        "and start fitted): NiMH 0.3 V per capacity, 900 s; NiCd 0.66 V, 13200 s (fitted as 4 cells with its own resistance).",
        "* NiMH: resistance ×3.3 (hobby AA packs with leads and welds, 66 + 50 mΩ per cell at 2 Ah), OCV 1.3× "
        "steeper and 17 mV higher, `w0` 0.032, `dv_o2_v` 0.035 V (the geometric means of the four NiMH fits); "
        "heat capacity 93 J/K and heat loss 0.10 W/K (the Polaron pack's sensor; were 28 J/K and 0.05 W/K "
        "before issue 14), `k_t_v_per_k` 1 mV/K (was 2, then 5 while heat made the dip).",
        "* NiCd (the Akkumatik pack as 4 cells, see Discharges): OCV the textbook table stretched 0.79× "
        "about its mean (was 37 mV below it, tuned as 5 cells), R0 + R1 a cell's 22 mΩ at 1 Ah split 10:1 (was "
        "3.3 mΩ), `w0` 0.126, `dv_o2_v` 0.28 V, `k_t_v_per_k` 7 mV/K, dip 0.66 V per capacity relaxing over "
        "13200 s, heat capacity 243 J/K and heat loss 0.42 W/K (its case sensor rose 2 °C), `charging_v` "
        "1.48 V (the pack's 1.59 under charge and the textbook 1.40).",
        "* LiPo: resistance ×0.37 (both hobby LiPo packs fit 0.23–0.58× the Ai2020 pouch). Heat capacity "
        "286 J/K per 2.28 Ah (was 30, a bare cell's): the two packs' sensors rose 2.1 °C in 18 min at 3C and "
        "2.4 °C in 23 min at 2.7C, fitted with the default model (heat loss kept) 233 and 351 J/K; the old "
        "model rose 9–11 °C, and a simulated 3C charge stopped after 6 minutes on the default "
        "dT/dt > 1 °C/min. A sensor on a pack sees the cells' heat through the wrap and their neighbours; "
        "that sensor is what a charger's dT/dt reads, so the model follows it. The default now rises "
        f"{defaults['lipo_4s_406duo_3c'].figures['temp_rise']['model_c']:.1f} and "
        f"{defaults['lipo_5s_x8_27c'].figures['temp_rise']['model_c']:.1f} °C on these curves. The LiFe "
        "recording's sensor (+2.4 °C at 0.5C, a top-up) jumps 1.2 °C in the second minute and falls while the "
        "charge goes on (and read 0 °C for one second, a dropout the curve reader now bridges): not the "
        "cells' heat, so LiFe is unchanged.",
        "* Pb: charge polarisation `k_charge_ohm` 0.028 Ω, `pol_tau_s` 204 s, `pol_max_v` 0.31 V, OCV 25 mV "
        "higher and 7 % steeper (UB121000 AGM).",
        "* LiFe: OCV points at 95 % (3.40 V) and 98 % (3.48 V), the knee of the 308DUO recording (was one "
        "straight line from 90 to 100 %); R0 30 mΩ (Prada2013's model value; was 20).",
        "* LiIon: solid-state diffusion, `diffusion_tau_s` 410 s, with R0 13.7 mΩ (was 20) and the slow pair "
        "28 mΩ / 360 s (was 15 mΩ / 900 s), fitted to PyBaMM's DFN CV tail of Chen2020; the OCV's top from "
        "PyBaMM at C/100 (see \"The CV tail against PyBaMM\"). Every other chemistry has `diffusion_tau_s` 0 "
        "(their runs are unchanged).",
        "* Test figures moved with the data (tests/sim): NiMH 1C peak window 1.42–1.52 → 1.45–1.68 V/cell "
        "(eStation 1C 1.625, Ultramat 1.65); NiCd -dV end at ≤ 1.30 × capacity (Akkumatik as 4 cells 1.20–1.22); "
        "\"NiCd dips more than NiMH\" dropped (eStation NiMH fell 1.9 mV/cell/min, Akkumatik NiCd 1.3); "
        "NiMH 60 % overcharge peaks above 50 °C, not 60 (the fitted heat loss); NiMH at 0.2C dips "
        "(3–20 mV/cell) instead of plateauing; the trickle test's thresholds follow the new NiMH OCV; "
        "a 2C NiMH charge ends by -dV at full (new test).",
        "",
        "## Per curve",
        "",
        *sections,
    ])
    (DOCS / "validation.md").write_text(text + "\n")
    print(f"docs/validation.md: {len(training)} curves in {total:.0f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
