"""Simulator-panel fixtures: a shown panel, compiled seed macros."""
import pytest

import helpers

RUN_TIMEOUT_MS = 60_000


@pytest.fixture
def compiled():
    """name of a seed macro, or a macro's text -> its record"""
    return helpers.compiled


@pytest.fixture
def panel(qtbot):
    from zuml_studio.ui.sim.sim_panel import SimulatorPanel

    p = SimulatorPanel()
    qtbot.addWidget(p)
    p.resize(1400, 380)
    p.show()
    yield p
    p.cancel()
    p.wait(10_000)


@pytest.fixture
def run(panel, qtbot):
    """Simulate a macro with the given form values; returns the SimResult."""

    def run(macro: str, declared=None, **values):
        panel.form.auto.setChecked(False)
        panel.set_record(helpers.compiled(macro), macro if "\n" not in macro else "T", declared)
        if values:
            panel.form.set_values(**values)
        with qtbot.waitSignal(panel.simulationFinished, timeout=RUN_TIMEOUT_MS) as blocker:
            panel.simulate()
        # The run is shown (simulationFinished) a moment before its thread ends: a test goes on
        # from a settled panel, however busy the machine.
        qtbot.waitUntil(lambda: not panel.is_running(), timeout=RUN_TIMEOUT_MS)
        return blocker.args[0]

    return run
