"""h:mm formatting and the time axis's round tick steps."""
import pytest

from zuml_studio.ui.base.timefmt import TimeAxisItem, duration, hmm, hmmss, tick_label, tick_step


@pytest.mark.parametrize("seconds, short, full", [
    (0, "0:00", "0:00:00"), (59, "0:01", "0:00:59"), (3725, "1:02", "1:02:05"), (4884, "1:21", "1:21:24"),
    (29.4 * 3600, "29:24", "29:24:00"), (-90, "-0:02", "-0:01:30")])
def test_hmm_and_hmmss(seconds, short, full):
    assert hmm(seconds) == short
    assert hmmss(seconds) == full


def test_duration_reads_naturally():
    assert duration(45) == "45 s"
    assert duration(2776) == "46:16 min"
    assert duration(3870) == "1:04:30"


@pytest.mark.parametrize("span, px, step", [(4884, 500, 600), (4884, 200, 1800), (63045, 450, 2 * 3600),
                                            (120, 500, 15), (48 * 3600, 900, 3 * 3600)])
def test_tick_steps_are_round_clock_values(span, px, step):
    assert tick_step(span, px) == step


def test_tick_step_never_crowds_labels():
    for span in (10, 100, 1000, 10_000, 100_000, 1_000_000):
        for px in (120, 400, 1500):
            assert span / tick_step(span, px) <= max(1.0, px / 48.0)


def test_labels_switch_to_seconds_below_a_minute_step():
    assert tick_label(3600, 900) == "1:00"
    assert tick_label(75, 15) == "0:01:15"


def test_axis_item_ticks(qapp):
    axis = TimeAxisItem()
    (major, _), (minor, _) = axis.tickSpacing(0, 4884, 500)
    assert major == 600 and 0 < minor < major
    assert axis.tickStrings([0, 900, 3600], 1.0, 900) == ["0:00", "0:15", "1:00"]


def test_elapsed_time_never_reads_as_a_clock():
    from zuml_studio.ui.base.timefmt import elapsed

    assert elapsed(19 * 3600 + 43 * 60) == "19 h 43 min"
    assert elapsed(58 * 60) == "58 min"
    assert elapsed(45) == "45 s"


def test_the_time_axis_title_names_the_format_its_labels_use(qtbot):
    from zuml_studio.ui.sim.sim_panel import SimulatorPanel

    panel = SimulatorPanel()             # a bare pyqtgraph view crashes in close(); the panel does not
    qtbot.addWidget(panel)
    panel.resize(900, 300)
    panel.show()
    plot = panel.plot
    axis = plot.time_axis
    for span, expected in ((7200.0, "h:mm"), (90.0, "h:mm:ss")):
        plot.tplot.setXRange(0.0, span, padding=0)
        values = axis.tickValues(0.0, span, axis.width())
        step = values[0][0]
        labels = axis.tickStrings(values[0][1], 1.0, step)
        assert axis.labelText == f"time ({expected})"
        assert all(label.count(":") == expected.count(":") for label in labels)
