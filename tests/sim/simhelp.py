"""Helpers for simulator tests: compile a macro (file or text) and simulate it."""
from helpers import MACROS
from zuml_studio.lang.compiler import compile_source
from zuml_studio.sim.interpreter import StartParams
from zuml_studio.sim.simulate import BatterySetup, prepare, simulate


def record_of(name_or_text: str) -> bytes:
    text = name_or_text if "\n" in name_or_text else (MACROS / f"{name_or_text}.zuml").read_text()
    result = compile_source(text)
    assert result.ok, result.diagnostics
    return result.record


def run(macro: str, task="charge", *, capacity=2000, current=None, series=1, sensor=True, soc=None,
        ambient=25.0, repetitions=1, voltage=None, model=None, **kw):
    params = StartParams(task, repetitions, capacity, current, voltage, series, sensor)
    return simulate(record_of(macro), params, BatterySetup(model, soc, ambient), **kw)


def start(macro: str, task="charge", *, capacity=2000, current=None, series=1, sensor=True, soc=None, **kw):
    params = StartParams(task, 1, capacity, current, None, series, sensor)
    return prepare(record_of(macro), params, BatterySetup(None, soc), **kw)


def macro(body_charge: str = "", body_discharge: str = "", intro: str = "AKK_TYPE=NiMh", tail: str = "") -> str:
    return (f"MACRO T\n{intro}\nDISCHARGE_SECTION\n{body_discharge}\nEND_SECTION\n"
            f"CHARGE_SECTION\n{body_charge}\nEND_SECTION\n{tail}\nEND_MACRO\n")
