"""The checks of test_truncation.py find what they look for: a button clipped to a strip under a
two-line message, and a plot squeezed until its tick labels run into each other."""
from PySide6.QtCore import Qt
from PySide6.QtWidgets import QLabel, QPushButton, QVBoxLayout, QWidget

from helpers import MACROS
from test_truncation import _cut_controls, _overlapping_ticks, _settle


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


def test_tick_labels_of_a_squeezed_plot_are_found_overlapping(make_window):
    w = make_window(str(MACROS / "NiMh.zuml"))
    w.resize(1366, 768)
    w.sim_panel.simulate()
    w.sim_panel.wait(60_000)
    _settle()
    assert not _overlapping_ticks(w.sim_panel.plot)
    w.resizeDocks([w.sim_dock], [100], Qt.Orientation.Vertical)       # as low as the dock goes
    _settle()
    assert _overlapping_ticks(w.sim_panel.plot)
