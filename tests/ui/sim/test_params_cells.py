"""The simulator panel's cells and charger: off by default; a weak cell, a spread and the charger
reach BatterySetup and the run (unequal cells in its log, the balancer's end); bad values are
refused in words."""
from pathlib import Path

import numpy as np

from zuml_studio.sim.simulate import BatterySetup

LIPO = (Path(__file__).resolve().parents[3] / "macros" / "LiPo.zuml").read_text(encoding="utf-8")
PACK = {"capacity_mah": 2200, "series": 4, "current_a": 2.2}


def test_the_cells_are_equal_and_the_charger_the_b6_by_default(panel):
    setup = panel.form.battery_setup()
    assert (setup.cell_spread, setup.weak_cell_pct, setup.weak_cell) == (None, 0.0, None)
    assert setup.charger == BatterySetup().charger == "imax_b6"
    assert panel.form.weak_pct.text() == "off" and not panel.form.seed.isEnabled()


def test_the_fields_reach_battery_setup(panel):
    panel.form.set_values(weak_cell_pct=15, weak_cell=2, cell_spread=(3, 10, 2), seed=7, charger="icharger_406duo")
    setup = panel.form.battery_setup()
    assert setup.weak_cell_pct == 15.0 and setup.weak_cell == 2
    assert setup.cell_spread == (3.0, 10.0, 2.0) and setup.seed == 7
    assert setup.charger == "icharger_406duo"
    assert panel.form.seed.isEnabled()


def test_a_weak_cell_runs_ahead_and_is_held_at_the_ceiling_while_the_balancer_catches_up(run, panel):
    result = run(LIPO, **PACK, weak_cell_pct=15)
    cols = result.log.arrays()
    last = [float(cols[f"cell{k}_v"][-1]) for k in range(1, 5)]
    # the weak top cell held; the B6's windows end the CV as one closes, the others still catching up
    assert int(np.argmax(last)) == 3 and last[3] - min(last) < 0.040
    assert max(float(np.max(cols[f"cell{k}_v"])) for k in range(1, 5)) <= 4.2 + 1e-3
    assert result.phases[-1].reason == "IF(I<0.1A) STOP_FAZE"
    assert "1870–2200 mAh" in panel.run_label.text() and "iMAX B6" in panel.run_label.text()


def test_the_weak_cell_chosen_is_the_one_that_runs_ahead(run):
    result = run(LIPO, **PACK, weak_cell_pct=15, weak_cell=1)
    cols = result.log.arrays()
    last = [float(cols[f"cell{k}_v"][-1]) for k in range(1, 5)]
    assert int(np.argmax(last)) == 0


def test_a_bad_spread_is_refused_in_words_and_nothing_runs(panel):
    from helpers import compiled
    panel.form.auto.setChecked(False)
    panel.set_record(compiled(LIPO), "LiPo")
    panel.form.set_values(cell_spread="3,x")
    panel.simulate()
    assert not panel.is_running()
    assert "cell spread '3,x': write CAP,R,SOC" in panel.message_text()
    panel.form.set_values(cell_spread="3,10,60")
    panel.simulate()
    assert "from 0 to 50" in panel.message_text()


def test_a_weak_cell_beyond_the_pack_is_refused_in_words(panel, qtbot):
    from helpers import compiled
    panel.form.auto.setChecked(False)
    panel.set_record(compiled(LIPO), "LiPo")
    panel.form.set_values(**PACK, weak_cell_pct=15, weak_cell=9)
    panel.simulate()
    qtbot.waitUntil(lambda: not panel.is_running(), timeout=60_000)
    assert "weak cell 9: the pack has cells 1 to 4" in panel.message_text()
