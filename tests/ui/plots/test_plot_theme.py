"""Every plot follows the palette it is drawn with (ui/base/theme.py's PlotColours): dark paper and
light axes in a dark palette, and a plot already drawn takes the other colour set when the
theme changes at run time, keeping its curves and its view. The short axis titles are
translated where they hold a word."""
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

import numpy as np
import pytest
from PySide6.QtCore import Qt
from PySide6.QtGui import QColor
from PySide6.QtWidgets import QApplication

from helpers import MACROS, contrast_ratio
from zuml_studio import i18n
from zuml_studio.device.messages import DeviceEvent, Telemetry
from zuml_studio.ui.base import theme

DATA = Path(__file__).resolve().parents[2] / "data"
LOG = DATA / "logs" / "X8_LiPo_5S_2200mA_Charge_4.txt"
CURVE = DATA / "curves" / "lipo_4s_406duo_3c.csv"
KINDS = ("simulator", "live", "log", "compare")


@dataclass
class Shown:
    view: object                    # the pyqtgraph GraphicsLayoutWidget
    plots: list                     # its PlotItems
    stacked: bool                   # a StackedPlot (legends, bands, labels, readout)
    owner: object                   # the widget holding it, kept alive while the test runs


def _settle(rounds: int = 5) -> None:
    for _round in range(rounds):
        QApplication.processEvents()


def _simulator(qtbot, macro: str = "LiPo", battery: dict | None = None, sensor: bool = True) -> Shown:
    from zuml_studio.lang.compiler import compile_source
    from zuml_studio.ui.sim.sim_panel import SimulatorPanel

    panel = SimulatorPanel()
    qtbot.addWidget(panel)
    panel.resize(1000, 400)
    panel.show()
    panel.set_record(compile_source((MACROS / f"{macro}.zuml").read_text()).record, macro,
                     battery or {"chemistry": "LiPo", "series": 3, "capacity_mah": 2200})
    panel.form.sensor.setChecked(sensor)
    panel.simulate()
    assert panel.wait(60_000)
    qtbot.waitUntil(lambda: len(panel.plot.labels) == len(panel.plot._phases) > 0, timeout=10_000)
    return Shown(panel.plot, list(panel.plot.plots), True, panel)


def _frame(t: float) -> Telemetry:
    return Telemetry(t, "charge", "charge", 1, 0, 1, 1, True, False, True, 4.0 + t / 1000, 2.0, 25.0 + t / 100,
                     30.0, t / 3.6 * 2.0, 0.0)


def _live(qtbot) -> Shown:
    from zuml_studio.ui.device.live_view import LiveView

    view = LiveView()
    qtbot.addWidget(view)
    view.resize(1000, 400)
    view.show()
    series = view.series
    series.add_event(DeviceEvent(0, 0.0, "phase_start", "charge", 1))
    for k in range(200):
        series.add_telemetry(_frame(k * 5.0))
    series.add_event(DeviceEvent(1, 500.0, "phase_end", "charge", 1, detail="IF(V>4.1S) STOP_FAZE"))
    series.add_event(DeviceEvent(2, 500.0, "phase_start", "charge", 2))
    view.plot.set_follow(False)
    view.plot.refresh()
    view.plot.show_all()
    return Shown(view.plot, list(view.plot.plots), True, view)


def _log(qtbot) -> Shown:
    from zuml_studio.ui.logs import LogWindow

    window = LogWindow()
    qtbot.addWidget(window)
    window.resize(1000, 600)
    window.show()
    with qtbot.waitSignal(window.documentOpened, timeout=30_000) as blocker:
        window.open_path(str(LOG))
    plot = blocker.args[0].plot
    return Shown(plot, list(plot.plots), True, window)


def _compare(qtbot) -> Shown:
    from zuml_studio.ui.sim.compare_dialog import CompareDialog

    dialog = CompareDialog(lambda: None)
    qtbot.addWidget(dialog)
    dialog.show()
    assert dialog.load_log(str(CURVE))
    curve = dialog.curve
    dialog._draw(curve.t, curve.v * 1.01, "model")          # a model line without running a simulation
    return Shown(dialog.plots, [dialog.v_plot, dialog.d_plot], False, dialog)


MAKE: dict[str, Callable] = {"simulator": _simulator, "live": _live, "log": _log, "compare": _compare}


def _curves(shown: Shown) -> list:
    """(item, x, y) of every line with data, the area under the current included."""
    out = []
    for plot in shown.plots:
        for item in plot.listDataItems():
            x, y = item.getData()
            if x is not None and len(x):
                out.append((item, np.array(x), np.array(y)))
    return out


def _on_paper(colour: QColor, paper: QColor) -> QColor:
    """What a translucent colour shows as over the paper."""
    a = colour.alphaF()
    return QColor(*(round(p + (c - p) * a) for c, p in zip(colour.getRgb()[:3], paper.getRgb()[:3])))


def _assert_drawn_with(shown: Shown, colours: theme.Colours) -> None:
    look = colours.plot
    paper = shown.view.backgroundBrush().color()
    assert paper == QColor(look.paper)
    for plot in shown.plots:
        for name in ("left", "bottom"):
            axis = plot.getAxis(name)
            assert axis.pen().color() == QColor(look.axis), name
            assert axis.textPen().color() == QColor(look.ink), name
            assert contrast_ratio(axis.textPen().color(), paper) >= 4.5
    for item, _x, _y in _curves(shown):
        pen = item.opts["pen"]
        if pen is not None and QColor(pen.color()).alpha():
            assert contrast_ratio(pen.color(), paper) >= 3, pen.color().name()
    # What is drawn, not only what is set: the grabbed view is as light or dark as its paper.
    image = shown.view.grab().toImage()
    lightness = np.mean([image.pixelColor(x, y).lightness() for x in range(0, image.width(), 7)
                         for y in range(0, image.height(), 7)])
    assert (lightness < 90) if colours.dark else (lightness > 170)
    if not shown.stacked:
        legend = shown.view.legend
        assert legend.labelTextColor() == QColor(look.ink)
        assert all(label.opts["color"] == QColor(look.ink) for _sample, label in legend.items)
        return
    plot = shown.view
    assert plot.colours is colours
    assert plot.placeholder.color == QColor(look.placeholder)
    for legend in plot.legends.values():
        assert legend.ink == look.ink and legend.fill.color().lightness() == QColor(look.paper).lightness()
        assert all(contrast_ratio(QColor(hue), paper) >= 3 for _name, hue in legend.entries)
    assert plot.labels and all(label.color in (QColor(look.band_label), QColor(look.band_warning))
                               for label in plot.labels)
    bands = [band for item in plot.band_items for band in item._bands]
    assert bands
    for _x0, _x1, brush, _pen in bands:
        band = _on_paper(brush.color(), paper)
        assert abs(band.lightness() - paper.lightness()) < 60          # a tint of the paper, not a block
        assert contrast_ratio(QColor(look.band_label), band) >= 4.5
    readout = getattr(plot, "readout", None)
    if readout is not None and hasattr(readout, "label"):
        assert readout.label.color == QColor(look.ink)
        assert readout.lines[0].pen.color() == QColor(look.cursor)


def _drawn_in(qtbot, kind: str, name: str) -> Shown:
    """A plot of ``kind`` made in the theme ``name``, checked to be drawn in its colours."""
    theme.apply_theme(name)
    _settle()
    shown = MAKE[kind](qtbot)
    _settle()
    _assert_drawn_with(shown, theme.DARK if name == "dark" else theme.LIGHT)
    return shown


@pytest.mark.parametrize("kind", KINDS)
def test_each_plot_in_a_dark_palette_has_dark_paper_and_light_axes(qtbot, system_theme, kind):
    shown = _drawn_in(qtbot, kind, "dark")
    paper = shown.view.backgroundBrush().color()
    assert paper.lightness() < 64
    assert all(plot.getAxis("left").pen().color().lightness() > 128 for plot in shown.plots)


@pytest.mark.parametrize("kind", KINDS)
def test_switching_the_theme_recolours_a_drawn_plot_and_keeps_its_curves_and_view(qtbot, system_theme, kind):
    shown = _drawn_in(qtbot, kind, "light")
    vb = shown.plots[0].vb
    (x0, x1), _y = vb.viewRange()
    shown.plots[-1].setXRange(x0 + (x1 - x0) * 0.2, x0 + (x1 - x0) * 0.6, padding=0)   # the user zoomed in
    _settle()
    before_range = vb.viewRange()[0]
    before = [(x.copy(), y.copy()) for _item, x, y in _curves(shown)]
    theme.apply_theme("dark")
    _settle()
    _assert_drawn_with(shown, theme.DARK)
    assert vb.viewRange()[0] == pytest.approx(before_range)
    after = [(x, y) for _item, x, y in _curves(shown)]
    assert len(after) == len(before)
    for (bx, by), (ax, ay) in zip(before, after):
        np.testing.assert_array_equal(bx, ax)
        np.testing.assert_array_equal(by, ay)
    theme.apply_theme("light")
    _settle()
    _assert_drawn_with(shown, theme.LIGHT)


@pytest.mark.parametrize("scheme", [theme.LIGHT, theme.DARK], ids=["light", "dark"])
def test_every_curve_hue_and_the_ink_stand_out_from_the_paper(scheme):
    look = scheme.plot
    paper = QColor(look.paper)
    hues = {**{f"quantity {k}": v for k, v in scheme.quantities.items()},
            **{f"cell {k}": v for k, v in enumerate(look.cells)},
            **{f"pack cell {k}": v for k, v in enumerate(look.pack_cells)},
            **{f"overlay {k}": v for k, v in enumerate(look.overlays)},
            **{f"compare {k}": v for k, v in look.compare.items()}}
    for name, hue in hues.items():
        assert contrast_ratio(QColor(hue), paper) >= 3, name
    for name in ("ink", "band_label", "band_warning"):
        assert contrast_ratio(QColor(getattr(look, name)), paper) >= 4.5, name
    assert contrast_ratio(QColor(look.axis), paper) >= 3
    assert contrast_ratio(QColor(look.grid), paper) < 1.5            # a faint line, under the data
    assert theme.is_dark(theme.dark_palette()) and QColor(theme.DARK.plot.paper) == \
        theme.dark_palette().color(theme.dark_palette().ColorRole.Base)


def test_the_short_axis_titles_are_translated_where_they_hold_a_word(qtbot):
    from zuml_studio.ui.sim.sim_panel import SimulatorPanel

    i18n.install("ru")
    try:
        panel = SimulatorPanel()
        qtbot.addWidget(panel)
        plot = panel.plot
        plot._label_axes(short=True)            # what a plot too low for the words shows
        titles = [axis.labelText for axis in plot._title_axes()]
    finally:
        i18n.install("en")
    assert titles == ["V", "V/эл.", "A", "°C"]


def test_the_phase_tables_flagged_row_and_section_tints_follow_the_theme(qtbot, system_theme):
    """The table beside the simulator's plot: a phase a default ended is flagged in the warning
    colours of the palette's set, a section cell is tinted in its band's hue."""
    from zuml_studio.ui.plots.phase_table import PhaseTable

    # A NiMH charge without a sensor whose -dV never fires: the capacity default ends it, a flagged row.
    shown = _simulator(qtbot, "NiMh", {"chemistry": "NiMh", "series": 4, "capacity_mah": 2000}, sensor=False)
    table = shown.owner.findChild(PhaseTable)
    model = table.phases
    assert any(table.is_flagged(row) for row in range(model.rowCount()))
    for choice, scheme in (("dark", theme.DARK), ("light", theme.LIGHT)):
        theme.apply_theme(choice)
        _settle()
        assert model.colours is scheme
        for row in range(model.rowCount()):
            background = model.data(model.index(row, 1), Qt.ItemDataRole.BackgroundRole)
            if table.is_flagged(row):
                assert background == QColor(scheme.warning_row)
                foreground = model.data(model.index(row, 1), Qt.ItemDataRole.ForegroundRole)
                assert contrast_ratio(foreground, background) >= 4.5
            else:
                hue = scheme.plot.bands[model.phase(row).section]
                assert background.getRgb()[:3] == hue


@pytest.mark.parametrize("scheme", [theme.LIGHT, theme.DARK], ids=["light", "dark"])
def test_a_flagged_rows_text_is_readable_on_its_background(scheme):
    assert contrast_ratio(QColor(scheme.warning), QColor(scheme.warning_row)) >= 4.5


def test_a_logs_totals_follow_the_theme(qtbot, system_theme):
    theme.apply_theme("light")
    _settle()
    window = _log(qtbot).owner
    totals = window.tabs.currentWidget().totals
    assert f"color:{theme.LIGHT.key_text};" in totals.text()
    theme.apply_theme("dark")
    _settle()
    assert f"color:{theme.DARK.key_text};" in totals.text()
    window_colour = totals.palette().color(totals.backgroundRole())
    assert contrast_ratio(QColor(theme.DARK.key_text), window_colour) >= 4.5


def test_an_exported_plot_has_its_title_block_on_the_plots_paper(qtbot, system_theme):
    from PySide6.QtCore import QSize

    from zuml_studio.ui.plots.plot_export import render_with_header

    theme.apply_theme("dark")
    _settle()
    shown = _simulator(qtbot)
    image = render_with_header(shown.view, QSize(800, 500), "LiPo", ["3S 2200 mAh"])
    assert image.pixelColor(1, 1) == QColor(theme.DARK.plot.paper)


def test_the_simulators_run_line_hint_and_message_follow_the_theme(qtbot, system_theme):
    theme.apply_theme("light")
    _settle()
    panel = _simulator(qtbot).owner
    assert f"color:{theme.LIGHT.muted};" in panel.run_label.styleSheet()
    panel._show_message("no battery model", "error")
    assert f"color:{theme.LIGHT.error};" in panel.message.styleSheet()
    theme.apply_theme("dark")
    _settle()
    assert f"color:{theme.DARK.error};" in panel.message.styleSheet()
    for label in (panel.run_label, panel.hint):
        assert f"color:{theme.DARK.muted};" in label.styleSheet()
        assert contrast_ratio(QColor(theme.DARK.muted), label.palette().color(label.backgroundRole())) >= 4.5
