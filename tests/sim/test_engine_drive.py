"""The fit's objective on the C engine (sim/engine.py drive, firmware/model/drive.c, issue 35 §4): a pack
driven along a curve in C is the Python loop's, bit for bit, for a one-state pack and a pack of unequal cells,
driven by current, by a charge's CV voltage and by a discharge's hold, and a discharge's run-on past the log."""
import tomllib
from unittest import mock

import numpy as np
import pytest

from helpers import ROOT
from zuml_studio.sim import engine
from zuml_studio.sim.cell_pack import CellSpec
from zuml_studio.domain.chemistry import load_chemistry
from zuml_studio.sim.curve import Curve, read_curve
from zuml_studio.sim.fit import Battery, cv_mask, fit_samples, simulate_curve
from zuml_studio.sim.fit_discharge import hold_mask, model_delivered

CURVES = ROOT / "tests" / "data" / "curves"
TRAINING = tomllib.loads((CURVES / "training.toml").read_text())

pytestmark = pytest.mark.skipif(engine.library() is None, reason="the C engine is not built")


def python_only():
    """The Python loop (the reference) wherever the fit would drive the model in C."""
    return mock.patch.object(engine, "drivable", lambda pack: False)


def same(a, b) -> bool:
    return all(np.array_equal(x, y, equal_nan=True) for x, y in zip(a, b))


@pytest.mark.parametrize("name", sorted(TRAINING))
@pytest.mark.parametrize("unequal", [False, True], ids=["pack", "cells"])
def test_a_curve_driven_in_c_is_the_python_loop_bit_for_bit(name, unequal):
    entry = TRAINING[name]
    work = fit_samples(read_curve(CURVES / f"{name}.csv"))
    held = cv_mask(work, entry["chemistry"]) if work.direction == "charge" else hold_mask(work)
    series = entry["cells"]
    cells = (CellSpec(1000.0),) * (series - 1) + (CellSpec(800.0, 1.3),) if unequal else None
    battery = Battery(load_chemistry(entry["chemistry"]), 1000.0, series, cells)
    assert engine.drivable(battery.pack(0.3, 25.0))
    c_pack, py_pack = battery.pack(0.3, work.ambient_c), battery.pack(0.3, work.ambient_c)
    in_c = simulate_curve(battery, work, held, 0.3, pack=c_pack)
    with python_only():
        in_python = simulate_curve(battery, work, held, 0.3, pack=py_pack)
    assert same((in_c.v, in_c.i, in_c.temp), (in_python.v, in_python.i, in_python.temp))
    # ... and the pack is left in the same state (a discharge's run-on goes on from it).
    assert (c_pack.voltage, c_pack.soc, c_pack.temp_c) == (py_pack.voltage, py_pack.soc, py_pack.temp_c)


def test_the_run_on_past_the_logs_end_is_the_python_loops():
    battery = Battery(load_chemistry("NiMh"), 2000.0, 4)
    pack = battery.pack(1.0, 25.0)
    t, v = [0.0], [pack.step(-1.0, 1e-3)]
    while v[-1] > 4.0:
        t.append(t[-1] + 10.0)
        v.append(pack.step(-1.0, 10.0))
    half = len(t) // 2
    curve = Curve(np.array(t[:half]), np.array(v[:half]), np.full(half, -1.0), None, 0)
    end_v = float(v[-1])
    in_c = model_delivered(battery, curve, 1.0, end_v)
    with python_only():
        in_python = model_delivered(battery, curve, 1.0, end_v)
    assert in_c[1] == in_python[1] and in_c[1] > 1.8 * float(curve.delivered_mah[-1])
    # A model that never reaches the end voltage runs on to three times the log's charge, in C as in Python.
    in_c = model_delivered(battery, curve, 1.0, 0.0)
    with python_only():
        in_python = model_delivered(battery, curve, 1.0, 0.0)
    assert in_c[1] == in_python[1]


def test_a_track_stops_after_the_first_sample_at_the_stop_voltage():
    pack = Battery(load_chemistry("NiMh"), 1000.0, 1).pack(0.5, 25.0)
    n = 500
    track = engine.Track(np.full(n, 60.0), np.full(n, -1.0), np.zeros(n), np.zeros(n, bool))
    v, i, temp = engine.drive(pack, track, 1.0)
    assert 0 < len(v) < n and v[-1] <= 1.0 < v[-2]
    assert (i == -1.0).all() and len(temp) == len(v)
    assert pack.voltage == v[-1]
