"""The live view without a charger: the readout's colours follow the palette (light and dark),
and the live plot's legends sit off the traces. Frames are fed to the series directly."""
import numpy as np
import pytest
from PySide6.QtGui import QColor
from PySide6.QtWidgets import QApplication

from helpers import contrast_ratio
from zuml_studio.device.messages import Telemetry
from zuml_studio.ui.base import theme
from zuml_studio.ui.device.live_view import LiveView
from zuml_studio.ui.plots.stacked_plot import covered


def frame(t, v, i, temp=25.0, heatsink=30.0):
    return Telemetry(t, "charge", "charge", 1, 0, 1, 1, True, False, temp is not None, v, i, temp, heatsink,
                     t / 3.6 * max(i, 0.0), 0.0)


@pytest.mark.parametrize("choice", ["light", "dark"])
def test_the_readout_takes_its_colours_from_the_palette(qtbot, system_theme, choice):
    view = LiveView()
    qtbot.addWidget(view)
    view.show()
    view.show_readings(frame(10.0, 5.6, 2.0))
    theme.apply_theme(choice)
    QApplication.processEvents()
    colours = theme.DARK if choice == "dark" else theme.LIGHT
    text = view.readings.text()
    background = view.readings.palette().color(view.readings.backgroundRole())
    assert theme.is_dark(view.readings.palette()) == (choice == "dark")
    for name in ("voltage", "current", "temp", "heatsink"):
        hue = colours.quantities[name]
        assert f"color:{hue};" in text, (name, text)                    # redrawn on the palette change
        assert contrast_ratio(QColor(hue), background) >= 4.5, (name, hue, background.name())


@pytest.mark.parametrize("scheme, base", [(theme.LIGHT, "#ffffff"), (theme.LIGHT, "#efefef"), (theme.DARK, "#1e1e1e"),
                                          (theme.DARK, "#353535")])
def test_every_readout_colour_is_readable_on_its_background(scheme, base):
    for name, hue in scheme.quantities.items():
        assert contrast_ratio(QColor(hue), QColor(base)) >= 4.5, name


def test_a_steep_edge_between_two_samples_counts_as_crossing():
    t = np.array([0.0, 10.0, 20.0])
    y = np.array([0.0, 0.0, 10.0])
    assert covered(t, y, 12.0, 18.0, 4.0, 6.0) == 1            # no sample inside, the edge crosses it
    assert covered(t, y, 12.0, 18.0, 11.0, 12.0) == 0
    assert covered(t, np.array([0.0, np.nan, 10.0]), 4.0, 6.0, -1.0, 11.0) == 0    # a gap crosses nothing


def _place_now(qtbot, plot):
    plot.refresh()
    qtbot.waitUntil(lambda: not plot._legend_timer.isActive(), timeout=5000)
    QApplication.processEvents()


def _legend_cover(plot, legend, series) -> int:
    r = legend.mapRectToParent(legend.boundingRect())
    a, b = legend.vb.mapToView(r.topLeft()), legend.vb.mapToView(r.bottomRight())
    (x0, x1), (y0, y1) = sorted((a.x(), b.x())), sorted((a.y(), b.y()))
    return sum(covered(t, y, x0, x1, y0, y1) for t, y in series)


@pytest.mark.parametrize("width", [420, 900])
def test_the_live_legends_sit_off_the_traces(qtbot, width):
    """The voltage climbs into the top right, the current steps down at the end and the
    temperatures rise across the plot: each legend finds a free corner, also after the y
    ranges follow new data."""
    view = LiveView()
    qtbot.addWidget(view)
    view.resize(width, 420)
    view.show()
    plot = view.plot
    plot.start()
    series = view.series
    for k in range(600):
        t = k * 2.0
        v = 5.0 + 1.2 * (t / 1200.0) ** 0.5
        i = 2.0 if t < 1100 else 0.2
        series.add_telemetry(frame(t, v, i, 25.0 + 5.0 * t / 1200.0, 28.0 + 6.0 * t / 1200.0))
        if k in (150, 599):
            _place_now(qtbot, plot)
    for p, names in ((plot.vplot, ("voltage",)), (plot.iplot, ("current",)), (plot.tplot, ("temp", "heatsink"))):
        legend = plot.legends[p]
        assert legend.isVisible()
        assert _legend_cover(plot, legend, [plot._display(n) for n in names]) == 0, (legend.names(), legend.corner)
    plot.stop()
