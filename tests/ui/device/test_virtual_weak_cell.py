"""The device panel's virtual battery with a weak cell: VirtualCharger built with unequal cells,
so the live view gets cell voltages that differ; a weak cell that does not fit is refused in words."""
import pytest

from device_helpers import connect
from zuml_studio.virtual.virtual_charger import DeviceSetupError
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


def test_the_spec_takes_which_cell_and_a_spread_as_zuml_simulate_does():
    from zuml_studio.sim.simulate import BatterySetup, pack_cells
    spec = VirtualSpec("LiPo:2200:4", weak_cell_pct=15, weak_cell=2, cell_spread=(3.0, 10.0, 2.0), seed=7)
    setup = BatterySetup(weak_cell_pct=15, weak_cell=2, cell_spread=(3.0, 10.0, 2.0), seed=7)
    assert spec.cells() == pack_cells(setup, 2200, 4, 0.0)
    assert VirtualSpec("LiPo:2200:4", cell_spread=(3.0, 10.0, 2.0), seed=8).cells() != spec.cells()


def test_the_panel_offers_the_simulators_cell_fields_and_builds_the_charger_with_them(make_panel, qtbot):
    from zuml_studio.sim.simulate import BatterySetup, pack_cells
    panel = make_panel()
    bar = panel.bar
    assert bar.cells_button.text() == "equal"
    bar.v_chem.setCurrentIndex(bar.v_chem.findData("LiPo"))
    bar.v_mah.setValue(2200)
    bar.v_cells.setValue(4)
    assert not bar.v_seed.isEnabled()                # no spread: no draw to seed
    bar.v_weak.setValue(20)
    bar.v_weak_cell.setValue(2)
    bar.v_spread.setText("3,10,2")
    bar.v_seed.setValue(7)
    assert bar.v_seed.isEnabled()
    assert bar.cells_button.text().startswith("−20 % #2")       # cut to its room, whole in the tooltip
    assert bar.cells_button.toolTip().startswith("−20 % #2, ±3,10,2 (seed 7)\n")
    connect(qtbot, panel)
    wanted = pack_cells(BatterySetup(weak_cell_pct=20, weak_cell=2, cell_spread=(3.0, 10.0, 2.0), seed=7), 2200, 4,
                        0.0)
    assert panel.connection.virtual_device.pack.specs == wanted
    assert min(wanted, key=lambda c: c.capacity_mah) is wanted[1]
    assert not bar.cells_button.isEnabled() and not bar.v_spread.isEnabled()


def test_cells_typed_wrong_are_refused_in_words_before_connecting(make_panel, qtbot):
    panel = make_panel()
    bar = panel.bar
    bar.v_chem.setCurrentIndex(bar.v_chem.findData("LiPo"))
    bar.v_cells.setValue(4)
    bar.v_spread.setText("3,ten")
    assert not panel.connect_to("virtual")
    assert "cell spread '3,ten': write CAP,R,SOC" in panel.message_text()
    assert panel.connection.state == "disconnected"
    bar.v_spread.setText("")
    bar.v_weak.setValue(15)
    bar.v_weak_cell.setValue(6)
    with qtbot.waitSignal(panel.connectedChanged, timeout=30_000) as blocker:
        assert panel.connect_to("virtual")
    assert blocker.args == [False]
    assert "weak cell 6: the pack has cells 1 to 4" in panel.message_text()
