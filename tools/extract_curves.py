"""Write the validation curves under tests/data/curves/ from the shared real recordings.

    .venv/bin/python tools/extract_curves.py [SHARED_SAMPLES_DIR]

Each is the recording's main charge, or its main discharge where the entry says ``direction =
"discharge"`` (logs read with zuml_studio.logs; the two CSVs that no charger wrote with a few lines
here), decimated to one sample per 10 s, as a plain curve CSV (zuml_studio/sim/curve.py; a discharge's
current is negative). The list and the sources are tests/data/curves/training.toml."""
from __future__ import annotations

import csv
import sys
import tomllib
from pathlib import Path

import numpy as np

from zuml_studio.sim.curve import Curve, read_curve

HERE = Path(__file__).resolve().parent.parent / "tests" / "data" / "curves"
STEP_S = 10.0


def _pb(path: Path, direction: str) -> Curve:
    """MIT ulink AGM test: Excel-day time, calibrated A/V/°C; the charge is where the current flows in,
    the discharge where it flows out."""
    t, v, i, temp = [], [], [], []
    with open(path, newline="") as fh:
        for row in csv.DictReader(fh):
            t.append(float(row["Time Elapsed"]) * 86400.0)
            i.append(float(row["Current (Calibrated)"]))
            v.append(float(row["Voltage (Calibrated)"]))
            temp.append(float(row["Battery Temp (Calibrated)"]))
    t, v, i, temp = map(np.array, (t, v, i, temp))
    on = np.flatnonzero(i > 0.5 if direction == "charge" else i < -0.5)
    sel = np.arange(on[0], on[-1] + 1)
    return Curve(t[sel] - t[sel[0]], v[sel], i[sel], temp[sel], 0, path.name)


def _arbin(path: Path, direction: str) -> Curve:
    """Arbin CSV (A123 LFP): Test_Time s, Current A, Voltage V, Temperature °C."""
    rows = list(csv.DictReader(open(path, newline="")))
    t = np.array([float(r["Test_Time"]) for r in rows])
    return Curve(t - t[0], np.array([float(r["Voltage"]) for r in rows]),
                 np.array([float(r["Current"]) for r in rows]), np.array([float(r["Temperature"]) for r in rows]),
                 0, path.name)


def main() -> int:
    samples = Path(sys.argv[1]) if len(sys.argv) > 1 else Path("/work/shared/realdata/samples")
    table = tomllib.loads((HERE / "training.toml").read_text())
    for name, entry in table.items():
        src = samples / entry["source_file"]
        direction = entry.get("direction", "charge")
        reader = {"pb": _pb, "arbin": _arbin}.get(entry.get("reader", ""), read_curve)
        curve = reader(src, direction).decimated(STEP_S)
        (HERE / f"{name}.csv").write_text(f"# {entry['source_file']} (main {direction}, {STEP_S:g} s steps)\n"
                                          + curve.to_csv())
        mah = curve.mah[-1] if direction == "charge" else curve.delivered_mah[-1]
        print(f"{name}: {len(curve.t)} samples, {curve.t[-1] / 60:.0f} min, {mah:.0f} mAh")
    return 0


if __name__ == "__main__":
    sys.exit(main())
