"""Write the validation curves under tests/data/curves/ from the shared real recordings.

    .venv/bin/python tools/extract_curves.py [SHARED_SAMPLES_DIR]

Each is the recording's main charge, or its main discharge where the entry says ``direction =
"discharge"`` (logs read with zuml_studio.logs; the two CSVs that no charger wrote with a few lines
here), decimated to one sample per 10 s, as a plain curve CSV (zuml_studio/sim/curve.py; a discharge's
current is negative). The list and the sources are tests/data/curves/training.toml.

The curves leave out the rests around them, where a log shows the pack's resistance (issue #26): it is
measured on the whole source log (``sim.measured_r``: the steps of the curve's direction within it or in
the rest after it, else anywhere in the log) and written to tests/data/curves/rest_steps.json, null
where the log has no step."""
from __future__ import annotations

import csv
import json
import sys
import tomllib
from pathlib import Path

import numpy as np

from zuml_studio.sim.curve import Curve, read_curve_and_log
from zuml_studio.sim.measured_r import MeasuredR, measure, measure_curve

HERE = Path(__file__).resolve().parent.parent / "tests" / "data" / "curves"
STEP_S = 10.0


def _pb_columns(path: Path) -> tuple[np.ndarray, ...]:
    t, v, i, temp = [], [], [], []
    with open(path, newline="") as fh:
        for row in csv.DictReader(fh):
            t.append(float(row["Time Elapsed"]) * 86400.0)
            i.append(float(row["Current (Calibrated)"]))
            v.append(float(row["Voltage (Calibrated)"]))
            temp.append(float(row["Battery Temp (Calibrated)"]))
    return tuple(map(np.array, (t, v, i, temp)))


def _pb(path: Path, direction: str) -> tuple[Curve, MeasuredR | None]:
    """MIT ulink AGM test: Excel-day time, calibrated A/V/°C; the charge is where the current flows in,
    the discharge where it flows out; the resistance where the current stops (6 cells)."""
    t, v, i, temp = _pb_columns(path)
    on = np.flatnonzero(i > 0.5 if direction == "charge" else i < -0.5)
    sel = np.arange(on[0], on[-1] + 1)
    return (Curve(t[sel] - t[sel[0]], v[sel], i[sel], temp[sel], 0, path.name),
            measure(t, v, i, 6, direction, (float(t[sel[0]]), float(t[sel[-1]])), float(np.median(np.abs(i[sel])))))


def _arbin(path: Path, direction: str) -> tuple[Curve, MeasuredR | None]:
    """Arbin CSV (A123 LFP): Test_Time s, Current A, Voltage V, Temperature °C."""
    rows = list(csv.DictReader(open(path, newline="")))
    t = np.array([float(r["Test_Time"]) for r in rows])
    return Curve(t - t[0], np.array([float(r["Voltage"]) for r in rows]),
                 np.array([float(r["Current"]) for r in rows]), np.array([float(r["Temperature"]) for r in rows]),
                 0, path.name), None


def main() -> int:
    samples = Path(sys.argv[1]) if len(sys.argv) > 1 else Path("/work/shared/realdata/samples")
    table = tomllib.loads((HERE / "training.toml").read_text())
    steps: dict[str, dict | None] = {}
    for name, entry in table.items():
        src = samples / entry["source_file"]
        direction = entry.get("direction", "charge")
        reader = {"pb": _pb, "arbin": _arbin}.get(entry.get("reader", ""))
        if reader:
            curve, measured = reader(src, direction)
        else:
            curve, log = read_curve_and_log(src, direction)
            measured = measure_curve(log, curve, entry["cells"])
        steps[name] = measured.to_dict() if measured else None
        curve = curve.decimated(STEP_S)
        (HERE / f"{name}.csv").write_text(f"# {entry['source_file']} (main {direction}, {STEP_S:g} s steps)\n"
                                          + curve.to_csv())
        mah = curve.mah[-1] if direction == "charge" else curve.delivered_mah[-1]
        r = f", {measured.ohm_per_cell * 1000:.0f} mOhm/cell at rests" if measured else ""
        print(f"{name}: {len(curve.t)} samples, {curve.t[-1] / 60:.0f} min, {mah:.0f} mAh{r}")
    (HERE / "rest_steps.json").write_text(json.dumps(steps, indent=1) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main())
