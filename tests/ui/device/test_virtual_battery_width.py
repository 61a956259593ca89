"""A saved battery with a long name does not widen the device panel (issue 26): the virtual chemistry box asks
for the width of its chemistries in the language shown and elides the battery's name, so the panel stays within
its dock at 1366x768 in English and in Russian, and the window does not grow."""
import pytest

from zuml_studio import i18n
from zuml_studio.sim.batteries import save_battery
from zuml_studio.domain.chemistry import load_chemistry
from zuml_studio.sim.fit import Battery

LONG_NAME = "Turnigy nano-tech 4S 2200 mAh 45-90C cells, bought 2023 (fitted from the bench log)"[:80]


@pytest.fixture
def long_battery(monkeypatch, tmp_path):
    monkeypatch.setenv("ZUML_STUDIO_CONFIG_DIR", str(tmp_path / "config"))
    save_battery(LONG_NAME, Battery(load_chemistry("LiPo"), 2200.0, 4))
    return f"battery:{LONG_NAME}"


@pytest.fixture(params=["en", "ru"])
def language(request):
    i18n.install(request.param)
    yield request.param
    i18n.install("en")


@pytest.mark.parametrize("mode", ["write", "charge"])
def test_a_long_battery_name_keeps_the_panel_in_its_dock_at_1366x768(make_window, qtbot, long_battery, language,
                                                                      mode, tmp_path):
    w = make_window(config=tmp_path / "config")
    w.resize(1366, 768)
    qtbot.waitUntil(lambda: w.size().width() == 1366)
    w.modes.switch(mode)
    panel = w.device_panel
    w.device_dock.show()
    w.device_dock.raise_()
    box = panel.v_chem
    assert box.findData(long_battery) > 0
    box.setCurrentIndex(box.findData(long_battery))
    qtbot.waitUntil(lambda: panel.isVisible() and panel.width() > 0)
    assert panel.minimumSizeHint().width() <= w.device_dock.width()
    assert panel.width() <= w.device_dock.width() and w.size().width() == 1366
    assert box.elided()                              # the name is cut on the face, whole in its tooltip
    chemistries = max(box.fontMetrics().horizontalAdvance(box.itemText(i)) for i in range(box.count() - 1))
    assert box.width() < box.fontMetrics().horizontalAdvance(box.currentText())
    assert box.width() >= chemistries                # "from the macro" and the chemistries whole
