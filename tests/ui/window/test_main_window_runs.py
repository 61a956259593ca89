"""Issue 15 (3, 4): closing during a charge asks whether to stop the charger; another macro
opened resets the simulator's start values from it."""
from device_helpers import connect, flash_and_start
from helpers import MACROS, seed_text

LIPO_3S = seed_text("LiPo").replace("  AKK_TYPE=LiPo\n", "  AKK_TYPE=LiPo\n  SERIES=3\n  CAPACITY=2200\n")


def _running_window(qtbot, make_window):
    w = make_window(str(MACROS / "NiMh-dV.zuml"))
    panel = w.device_panel
    connect(qtbot, panel)
    ok, text = flash_and_start(qtbot, panel)
    assert ok, text
    assert panel.is_running()
    return w, panel, panel.connection.virtual_device


def test_closing_during_a_run_asks_and_cancel_keeps_the_window(qtbot, make_window):
    w, panel, device = _running_window(qtbot, make_window)
    asked = []
    w.ask_close_run = lambda: asked.append(1) or "cancel"
    assert not w.close()
    assert asked and w.isVisible() and panel.is_connected() and device.state == "running"


def test_closing_during_a_run_can_stop_the_charger_first(qtbot, make_window):
    w, panel, device = _running_window(qtbot, make_window)
    w.ask_close_run = lambda: "stop"
    assert w.close()
    assert device.state != "running"


def test_another_macro_opened_resets_the_simulators_start_values(make_window, tmp_path):
    three = tmp_path / "lipo3s.zuml"
    three.write_text(LIPO_3S)
    w = make_window(str(three))
    form = w.sim_panel.form
    assert (form.series.value(), form.capacity.value()) == (3, 2200)
    form.set_values(current_a=5.0, task="discharge")
    w.open_file(str(MACROS / "NiMh.zuml"))
    assert (form.series.value(), form.capacity.value(), form.current.value()) == (4, 2000, 2.0)
    assert form.task.currentData() == "charge"
    w.open_file(str(three))
    assert (form.series.value(), form.capacity.value()) == (3, 2200)
