"""The CV tail (issue 35 §1). Every lithium charge with a CV phase in shared/realdata: each stored as a curve at
10 s steps in tests/data/cv_tail/ with its fitted figures in tests/data/cv_tail/figures.json, which
tests/sim/test_cv_tail.py holds the fit to; and `section`, docs/validation.md's text on the tail (tools/validation.py
puts it in the page), with the LiIon model against PyBaMM's figures (tools/pybamm_cv_reference.py). The same recording in a second format (a .lov of an extracted text log, an .osd's CSV, the
B6's frames and their decoding) is taken once.

    .venv/bin/python tools/cv_tail_realdata.py [SHARED_SAMPLES_DIR]
"""
from __future__ import annotations

import json
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np

from zuml_studio.logs import read_log
from zuml_studio.sim.battery import Pack
from zuml_studio.domain.chemistry import load_chemistry
from zuml_studio.sim.curve import charge_from_log, read_curve
from zuml_studio.sim.fit import cv_mask, fit

ROOT = Path(__file__).resolve().parent.parent
OUT = ROOT / "tests" / "data" / "cv_tail"
STEP_S = 10.0
# (name, source under shared/realdata/samples, chemistry, cells): the lithium charges whose voltage is held at
# the end. The cell count is the log's taps where it has them, else its voltage (7.2 V held: LiFe 2S).
LOGS = (
    ("liion_2s_polaron", "dataexplorer/PolaronACDC_2014-08-15_LiIo_2_4000.osd", "LiIon", 2),
    ("life_2s_308duo", "icharger/308DUO_LiFe_2.3Ah_Laden_0_CH1.txt", "LiFe", 2),
    ("life_2s_4010duo", "icharger/4010DUO_LiFe_2S_3A_Charge_1_CH1.txt", "LiFe", 2),
    ("lipo_4s_406duo", "icharger/406DUO_Turnigy_4S_1500_A_Charge_0_CH1.txt", "LiPo", 4),
    ("lipo_5s_x6", "icharger/X6_LiPo_Cycle_1.txt", "LiPo", 5),
    ("lipo_5s_x8", "icharger/X8_LiPo_5S_2200mA_Charge_4.txt", "LiPo", 5),
    ("lipo_3s_106bplus", "icharger/iCharger106Bplus_Laden.extracted_lines.txt", "LiPo", 3),
    ("lipo_3s_306b", "icharger/iCharger306B_2013-01-07_RB_1000.extracted_lines.txt", "LiPo", 3),
    ("lipo_3s_imaxb6", "imaxb6_serial/iMaxB6_Ladung3S450mAh_frames.txt", "LiPo", 3),
)
# Lithium charges left out, and why (docs/validation.md says the same).
LEFT_OUT = {
    "icharger/X6_LiFe_10-3A_Cycle_2.txt": "no CC phase: a full pack topped up, held at 3.60 V/cell from its "
                                          "first 10 s (10 A falling to 0.04 A), so there is no CC current to "
                                          "measure the CV current against",
    "curves/LFP_A123_18650_1.1Ah_Arbin_6C-1C_fastcharge_snippet_CH33.csv": "no CV phase (a fast-charge snippet)",
    "skyrc_hid/B6ACv2_logged_Charging-0.3A-1000mAh.csv": "no CV phase",
}


PYBAMM = ROOT / "tests" / "data" / "pybamm_cv_chen2020.json"
# Chen2020 (LG M50): 5.0 Ah nominal (1C = 5 A), 5.14 Ah between 2.5 and 4.2 V by its own OCV (PyBaMM at C/100).
CHEN_MAH = 5140.0
NOMINAL_A = 5.0


def cc_cv(chem, rate: float, ref: dict) -> tuple[float, float]:
    """A cell from empty charged as PyBaMM's experiment ``ref`` does: rate x 5 A until its v_max, then that held
    until C/end_c, the current the interpreter's CC-CV gives (the lower of the set current and the one that holds
    the voltage). Returns the CV phase's duration (s) and its current half-way through it (A)."""
    pack = Pack(chem, CHEN_MAH, 1, 0.0)
    i_cc, i_end = rate * NOMINAL_A, NOMINAL_A / ref["end_c"]
    t, t_cv, times, amps = 0.0, None, [], []
    while t < 6 * 3600.0:
        i = min(i_cc, pack.current_for_voltage(ref["v_max"], 1.0))
        if t_cv is None and i < i_cc:
            t_cv = t
        if t_cv is not None and i < i_end:
            break
        pack.step(i, 1.0)
        t += 1.0
        times.append(t)
        amps.append(i)
    cv_s = t - t_cv
    return cv_s, float(np.interp(t_cv + cv_s / 2.0, times, amps))


def section() -> str:
    """docs/validation.md's "The CV tail against PyBaMM and on every lithium charge" from the stored figures."""
    ref = json.loads(PYBAMM.read_text())
    real = json.loads((OUT / "figures.json").read_text())
    chem = load_chemistry("LiIon")
    rows = []
    for rate in ref["rates"]:
        key = f"{rate:g}C"
        dfn, spm = ref["models"]["DFN"][key], ref["models"]["SPM"][key]
        ours = cc_cv(chem, rate, ref)
        none = cc_cv(replace(chem, diffusion_tau_s=0.0), rate, ref)
        cells = []
        for j, unit in ((0, 60.0), (1, 1.0)):
            d = (dfn["cv_s"], dfn["cv_half_a"])[j]
            cells += [f"{d / unit:.{1 if j == 0 else 3}f}"] + [
                f"{x / unit:.{1 if j == 0 else 3}f} ({(x / d - 1) * 100:+.0f} %)"
                for x in ((spm["cv_s"], spm["cv_half_a"])[j], ours[j], none[j])]
        rows.append(f"| {key} | " + " | ".join(cells) + " |")
    logs = [f"| {name} | `{c['source']}` | {c['chemistry']} {c['cells']}S | {c['rmse_v_per_cell_mv']:.2f} | "
            f"{c['rmse_i_cv_pct']:.2f} | {c['params'].get('diffusion_tau_s', 0):.0f} |"
            for name, c in real["curves"].items()]
    left = [f"* `{source}`: {why}." for source, why in real["left_out"].items()]
    return "\n".join([
        f"PyBaMM's DFN of Chen2020 (LG M50, the LiIon default's cell), from empty, CC to {ref['v_max']} V then CV "
        f"to C/{ref['end_c']} (`{PYBAMM.relative_to(ROOT)}`, written by `tools/pybamm_cv_reference.py` from a "
        "venv of its own), against the LiIon model (a 5.14 Ah cell, Chen2020's charge between 2.5 and 4.2 V, 1C = "
        "5 A, driven as the interpreter's CC-CV does); the CV phase's duration (min) and its current half-way "
        "through it (A), and in brackets the difference from the DFN:",
        "",
        "| rate | CV min, DFN | SPM | model | model without diffusion | half-way A, DFN | SPM | model | "
        "model without diffusion |",
        "|---|---|---|---|---|---|---|---|---|",
        *rows,
        "",
        "The model meets the DFN within 10 % at every rate (tests/sim/test_cv_tail.py). PyBaMM's SPM, which has no "
        "electrolyte, does not: its CV ends 18–24 % early and its half-way current is 12–21 % low, more so at a "
        "higher rate. What does it in the model is **solid-state diffusion** (`diffusion_tau_s`, sim/battery.py): "
        "the OCV is read at the particles' surface, which leads their bulk by the charge of `diffusion_tau_s` "
        "seconds of current (R²/15D, the steady gain of Fick's law in a sphere) and relaxes towards it with that "
        "time constant. In CV the surface sits near the steep top of the OCV while the bulk catches up, so the "
        "tail's shape follows the OCV's curvature, which an RC pair's overvoltage, linear in the current, cannot. "
        "Its fitted value, 410 s, is Chen2020's positive particle's own R²/15D (454 s). Fitted with it: R0 "
        "13.7 mΩ (was 20), the slow pair 28 mΩ / 360 s (was 15 mΩ / 900 s), and the OCV's top from PyBaMM at "
        "C/100 (flat from 85 to 94 %, then curving up to 4.2 V: was one straight line from 80 to 100 %). Without "
        "diffusion the best R0 and slow pair still miss the 2C tail by 13 % (duration) and 9 % (half-way "
        "current); the old default missed the DFN by 21–35 % and 36–58 %. One more state per cell costs the C "
        "engine nothing measurable (benchmarks/bench_simulate.py; the 1C charge now lasts as long as the DFN's, "
        "1.94 h instead of 1.76 h).",
        "",
        "On every lithium charge with a CV phase in `shared/realdata` (each once: the same recording in a "
        "second format is left out), stored at the fit's 10 s steps in `tests/data/cv_tail/` by "
        "`tools/cv_tail_realdata.py`, the fit (`zuml_studio.sim.fit`, which now fits `diffusion_tau_s` for "
        "lithium as well) meets the issue's limits, CV current RMSE ≤ 10 % of the CC current with the voltage "
        "within 15 mV per cell (tests/sim/test_cv_tail.py holds each figure):",
        "",
        "| curve | log | battery | RMSE V (mV/cell) | RMSE I in CV (% of CC) | fitted diffusion_tau_s (s) |",
        "|---|---|---|---|---|---|",
        *logs,
        "",
        "The hobby chargers' short tails (LiPo at 0.3–3C, a few minutes of CV) need no diffusion: their fits put "
        "`diffusion_tau_s` at its 1 s floor and carry the tail with the slow RC pair; the long ones (the Polaron "
        "Li-ion top-up, the X6 LiPo's 70 min, the 4010DUO LiFe) use it.",
        "",
        "The LiIon default is now Chen2020's cell as the DFN sees it: on the one LiIon log, a 2S 4 Ah pack of "
        "another make topped up at 0.25C, it misses more than before with only its capacity and start fitted and "
        "less with the resistance its rests measure (its section below; both within twice the limits).",
        "",
        "Left out:",
        *left,
        "",
        "No log here is beyond a pack-level model: the X6 5S log, whose tail one high-resistance cell makes "
        "(below), fits at 1.4 mV/cell and 1.7 % because the fit gives the whole pack that cell's resistance "
        "(`r_scale` 9.0): the figures are reached, the resistance is the one cell's, not the pack's. Run as a "
        "charger from its measured cells, without a fit, a pack of identical cells misses it by 14.3 % and the "
        "per-cell ceiling by 9.9 % (below). That is the one log whose tail a pack-level *default* cannot follow.",
    ])


def figures_of(curve, chemistry: str, cells: int) -> dict:
    result = fit(curve, chemistry, cells)
    f = result.figures
    return {"chemistry": chemistry, "cells": cells, "cv_samples": int(cv_mask(curve, chemistry).sum()),
            "rmse_v_per_cell_mv": f["rmse_v_per_cell_mv"], "rmse_i_cv_pct": f["rmse_i_cv_pct"],
            "params": {k: (round(v, 6) if isinstance(v, float) else v) for k, v in result.params.items()}}


def main() -> int:
    samples = Path(sys.argv[1]) if len(sys.argv) > 1 else ROOT.parent / "shared" / "realdata" / "samples"
    OUT.mkdir(exist_ok=True)
    table = {"left_out": LEFT_OUT, "curves": {}}
    for name, source, chemistry, cells in LOGS:
        path = samples / source
        curve = charge_from_log(read_log(path.read_bytes(), path.name), path.name).decimated(STEP_S)
        target = OUT / f"{name}.csv"
        target.write_text(f"# {source} (main charge, {STEP_S:g} s steps)\n" + curve.to_csv())
        stored = read_curve(target)       # the figures of what the test reads back
        table["curves"][name] = {"source": source, **figures_of(stored, chemistry, cells)}
        print(name, table["curves"][name])
    (OUT / "figures.json").write_text(json.dumps(table, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
