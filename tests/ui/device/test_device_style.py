"""The device panel's shared widgets: a combo box too narrow for its choice elides it and says
it whole in the tooltip."""
from PySide6.QtCore import QEvent, QPoint
from PySide6.QtGui import QHelpEvent
from PySide6.QtWidgets import QToolTip

from zuml_studio.ui.device.device_style import ElidedCombo


def test_a_narrow_combo_elides_its_choice_and_tells_it_whole(qtbot, monkeypatch):
    combo = ElidedCombo()
    qtbot.addWidget(combo)
    combo.addItem("Junsi iCharger (106B/206B/208B/306B/3010B)")
    combo.setToolTip("The charger's protocol")
    combo.setFixedWidth(120)
    combo.show()
    assert combo.elided()
    shown = []
    monkeypatch.setattr(QToolTip, "showText", lambda pos, text, *a: shown.append(text))
    combo.event(QHelpEvent(QEvent.Type.ToolTip, QPoint(5, 5), combo.mapToGlobal(QPoint(5, 5))))
    assert shown == ["Junsi iCharger (106B/206B/208B/306B/3010B)\n\nThe charger's protocol"]
    combo.setFixedWidth(600)
    assert not combo.elided()
    assert combo.grab().width() == 600          # paints without error
