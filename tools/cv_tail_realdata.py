"""Every lithium charge with a CV phase in shared/realdata (issue 35 §1): each stored as a curve at 10 s steps in
tests/data/cv_tail/ with its fitted figures in tests/data/cv_tail/figures.json, which tests/sim/test_cv_tail.py
holds the fit to. The same recording in a second format (a .lov of an extracted text log, an .osd's CSV, the
B6's frames and their decoding) is taken once.

    .venv/bin/python tools/cv_tail_realdata.py [SHARED_SAMPLES_DIR]
"""
from __future__ import annotations

import json
import sys
from pathlib import Path

from zuml_studio.logs import read_log
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
