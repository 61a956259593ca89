"""The device panel's virtual battery with a weak cell: VirtualCharger built with unequal cells,
so the live view gets cell voltages that differ; a weak cell that does not fit is refused in words."""
import pytest

from device_helpers import connect
from zuml_studio.device.virtual_charger import DeviceSetupError
from zuml_studio.ui.device.connection import VirtualSpec


def test_the_spec_builds_the_cells_with_the_top_one_weaker():
    cells = VirtualSpec("LiPo:2200:4", weak_cell_pct=15).cells()
    assert [round(c.capacity_mah) for c in cells] == [2200, 2200, 2200, 1870]
    assert VirtualSpec("LiPo:2200:4").cells() is None


def test_a_weak_cell_that_does_not_fit_is_refused_in_words():
    with pytest.raises(DeviceSetupError, match="weak cell: 100 is no percentage of capacity to take off"):
        VirtualSpec("LiPo:2200:4", weak_cell_pct=100).cells()


def test_the_virtual_charger_is_built_with_the_weak_cell(make_panel, qtbot):
    panel = make_panel()
    bar = panel.bar
    bar.v_chem.setCurrentIndex(bar.v_chem.findData("LiPo"))
    bar.v_mah.setValue(2200)
    bar.v_cells.setValue(4)
    bar.v_weak.setValue(15)
    connect(qtbot, panel)
    pack = panel.connection.virtual_device.pack
    assert [round(c.capacity_mah) for c in pack.specs] == [2200, 2200, 2200, 1870]
    assert not bar.v_weak.isEnabled()           # chosen before connecting, like the rest of the battery
