"""The simulation's child process side (no Qt): what it imports, and the run it sends back."""
import pickle
import subprocess
import sys

import numpy as np

import helpers
from zuml_studio.sim.interpreter import StartParams
from zuml_studio.sim.simulate import BatterySetup, prepare
from zuml_studio.ui.sim import sim_process

LIPO = StartParams(task="charge", capacity_mah=2000, current_a=2.0, series=3)


def test_the_child_imports_no_qt():
    # Unpickling a request that lived beside the Qt worker imported PySide6 in every child (100 ms a run).
    code = ("import pickle, sys; from zuml_studio.ui.sim import sim_process; "
            "pickle.loads(sys.stdin.buffer.read()); "
            "sys.exit('PySide6' in sys.modules)")
    request = sim_process.SimRequest(helpers.compiled("LiPo"), LIPO, BatterySetup(), "LiPo")
    done = subprocess.run([sys.executable, "-c", code], input=pickle.dumps(request), timeout=120)
    assert done.returncode == 0


def round_trip(result):
    kind, back = pickle.loads(sim_process.dumps((sim_process.DONE, result)))
    assert kind == sim_process.DONE
    return back


def test_a_finished_run_comes_back_whole():
    result = prepare(helpers.compiled("LiPo"), LIPO, BatterySetup())
    result.interpreter.run()
    back = round_trip(result)
    assert back.totals() == result.totals() and len(back.log) == len(result.log) > 1000
    assert [p.reason for p in back.phases] == [p.reason for p in result.phases]
    for name, column in result.log.arrays().items():
        assert np.array_equal(back.log.arrays()[name], column), name


def test_a_run_stopped_between_chunks_comes_back_with_its_unsealed_samples():
    result = prepare(helpers.compiled("LiPo"), LIPO, BatterySetup())
    it = result.interpreter
    it.advance(1234)                    # less than a sealed chunk: the samples are still staged
    it.stop("cancelled")
    back = round_trip(result)
    assert back.interpreter.end_reason == "cancelled" and len(back.log) == len(result.log) > 1000
    assert np.array_equal(back.log.arrays()["voltage_v"], result.log.arrays()["voltage_v"])
