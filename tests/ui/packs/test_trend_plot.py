"""The trend plots (issue 33 §2): unknown resistance draws no line and says "–", the axis reads
"mΩ/cell" without a scale factor, and the plots follow the light and dark themes."""
from zuml_studio.packs.health import TrendPoint
from zuml_studio.ui.base import theme
from zuml_studio.ui.packs.trend_plot import PackTrendPlot

POINTS = [TrendPoint("2024-01-01", "a.lov", 95.0, None, 10.0), TrendPoint("2024-06-01", "b.lov", 92.0, None, 12.0)]


def test_unknown_resistance_draws_no_line_and_the_axis_has_no_scale_factor(qtbot):
    plot = PackTrendPlot()
    qtbot.addWidget(plot)
    plot.show_trend(POINTS)
    x, y = plot.points["resistance_mohm_per_cell"]
    assert len(x) == 0 and len(plot.points["capacity_pct"][0]) == 2
    resistance = plot.plots["resistance_mohm_per_cell"]
    assert not [item for item in resistance.listDataItems() if len(item.getData()[0] or ())]
    assert resistance.getAxis("left").labelText == "mΩ/cell" and not resistance.getAxis("left").autoSIPrefix


def test_the_trend_follows_the_theme(qtbot):
    plot = PackTrendPlot()
    qtbot.addWidget(plot)
    plot.show_trend(POINTS)
    try:
        for choice in ("light", "dark"):
            theme.apply_theme(choice)
            qtbot.waitUntil(lambda: plot.look is theme.colours(plot.palette()))
            assert plot.backgroundBrush().color().name() == plot.look.plot.paper.lower()
            assert len(plot.points["capacity_pct"][0]) == 2         # redrawn, not emptied
    finally:
        theme.apply_theme("system")
