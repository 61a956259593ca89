"""The checks of test_truncation.py find what they look for: a button clipped to a strip under a
two-line message, and tick labels that run into each other (pyqtgraph's own axes squeezed; the
stacked plots' axes leave such labels out)."""
import pyqtgraph as pg
from PySide6.QtCore import Qt
from PySide6.QtWidgets import QLabel, QPushButton, QVBoxLayout, QWidget

from helpers import MACROS
from window_checks import _cut_controls, _overlapping_ticks, _settle


def test_a_button_clipped_to_a_strip_is_found(qtbot):
    box = QWidget()
    qtbot.addWidget(box)
    layout = QVBoxLayout(box)
    layout.addWidget(QLabel("A message\non two lines"))
    button = QPushButton("Backup…")
    layout.addWidget(button)
    box.setFixedSize(300, 48)           # what a dock too low for its content does to it
    box.show()
    qtbot.waitExposed(box)
    assert any("Backup" in problem for problem in _cut_controls(box))
    box.setFixedSize(300, 120)
    qtbot.waitUntil(lambda: not _cut_controls(box))


def test_overlapping_tick_labels_are_found_and_a_squeezed_stacked_plot_has_none(make_window, qtbot):
    plain = pg.GraphicsLayoutWidget()       # pyqtgraph's own axes, three plots stacked in 130 px
    qtbot.addWidget(plain)
    for row in range(3):
        plain.addPlot(row=row, col=0).setYRange(0, 1, padding=0)
    plain.resize(300, 130)
    plain.show()
    qtbot.waitExposed(plain)
    assert _overlapping_ticks(plain)

    w = make_window(str(MACROS / "NiMh.zuml"))
    w.resize(1366, 768)
    w.sim_panel.simulate()
    w.sim_panel.wait(60_000)
    w.resizeDocks([w.sim_dock], [100], Qt.Orientation.Vertical)       # as low as the dock goes
    _settle()
    assert w.sim_panel.plot.height() < 200
    assert not _overlapping_ticks(w.sim_panel.plot)      # the stacked plot's axes leave crowded labels out
