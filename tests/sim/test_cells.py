"""A pack of unequal cells and the charger's balancer: a 4S LiPo pack with one cell 15 % weaker,
charged CC-CV on the iMAX B6 model; the spread reproducible; identical cells the one-state pack."""
import io

import numpy as np
import pytest

from simhelp import record_of
from zuml_studio.sim.battery import Pack
from zuml_studio.sim.cell_pack import CellPack, CellSpec, spread_cells
from zuml_studio.domain.chemistry import load_chemistry
from zuml_studio.sim.interpreter import StartError, StartParams
from zuml_studio.sim.simulate import BatterySetup, prepare, simulate

CELLS = [f"cell{k}_v" for k in range(1, 5)]


def _weak_run(**setup):
    return simulate(record_of("LiPo"), StartParams("charge", 1, 2000, 2.0, None, 4), BatterySetup(**setup))


def test_a_weak_cell_is_held_at_the_b6_ceiling_and_the_charge_ends_by_the_macro_with_the_pack_balanced():
    r = _weak_run(weak_cell_pct=15.0)
    cc, cv = r.phases
    a = r.log.arrays()
    volts = np.column_stack([a[c] for c in CELLS])
    assert volts.max() <= 4.2 + 0.0005                      # held at the ceiling, to the solve's tolerance
    assert cc.reason == "IF(V>4.1S) STOP_FAZE"
    assert cv.reason == "IF(I<0.1A) STOP_FAZE" and not cv.by_default
    in_cv = a["phase"] == cv.run
    held = in_cv & (volts[:, 3] > 4.2 - 0.0005)
    current, mask = a["current_a"][in_cv], a["balance_mask"][in_cv]
    assert held.sum() > 300 and current.max() <= 2.0                          # never above the phase's own
    # the B6's windows (15 s bleeding, 4 s off): the held current rises only as a window starts
    assert np.all((np.diff(current) <= 1e-9) | (np.diff(mask) != 0))
    assert a["current_a"][in_cv][0] <= a["current_a"][~in_cv][-1]             # no jump at the CV's start
    # the CV's own current ends it as a window closes (the weak cell's bleed off, the hold takes 0.3 A off
    # the current): the weak cell at its ceiling, the others 24 mV under it (the firmware's windows do so)
    assert max(cv.cells_end) == cv.cells_end[3] and min(cv.cells_end) > 4.17
    assert np.any(mask & 0b1000)                                               # the weak cell bleeds during CV
    duration = cv.end_s - cv.start_s
    assert cv.bled_s[:3] == (0.0, 0.0, 0.0) and 0.7 * duration <= cv.bled_s[3] <= duration * 15 / 19 + 15
    assert "balancer: cell 4 19 min" in cv.notes
    # the pack's sum is what the charger measured
    assert np.allclose(volts.sum(axis=1), a["voltage_v"], atol=1e-4)


def test_without_a_weak_cell_the_macro_ends_the_charge():
    r = _weak_run()
    assert [p.reason for p in r.phases] == ["IF(V>4.1S) STOP_FAZE", "IF(I<0.1A) STOP_FAZE"]
    assert r.log.arrays()["balance_mask"].max() == 0


def test_the_spread_is_drawn_again_with_the_same_seed_and_differs_with_another():
    one = spread_cells(2000, 6, (5.0, 10.0, 2.0), seed=7, soc=0.3)
    assert one == spread_cells(2000, 6, (5.0, 10.0, 2.0), seed=7, soc=0.3)
    assert one != spread_cells(2000, 6, (5.0, 10.0, 2.0), seed=8, soc=0.3)
    assert all(1900 <= c.capacity_mah <= 2100 and 0.9 <= c.r_scale <= 1.1 and 0.28 <= c.soc <= 0.32 for c in one)
    a = _weak_run(cell_spread=(3.0, 10.0, 2.0), seed=5).log.arrays()["cell2_v"]
    b = _weak_run(cell_spread=(3.0, 10.0, 2.0), seed=5).log.arrays()["cell2_v"]
    assert np.array_equal(a, b)


def test_identical_cells_in_the_cell_pack_follow_the_one_state_pack():
    chem = load_chemistry("LiPo")
    one, cells = Pack(chem, 2000, 4, 0.3), CellPack(chem, 2000, [CellSpec(2000.0)] * 4, 0.3)
    for k in range(2000):
        target = one.open_circuit_voltage() + (0.1 if k % 5 else -0.1)
        i = one.current_for_voltage(target, 1.0)
        assert cells.current_for_voltage(target, 1.0) == pytest.approx(i, abs=1e-9)
        assert cells.step(i, 1.0) == pytest.approx(one.step(i, 1.0), abs=1e-9)


def test_the_cv_solve_holds_unequal_cells_to_the_microvolt():
    chem = load_chemistry("LiPo")
    pack = CellPack(chem, 2000, spread_cells(2000, 12, (5.0, 20.0, 5.0), seed=3, soc=0.5), 0.5)
    target = pack.open_circuit_voltage() + 0.5
    for _ in range(500):
        pack.step(pack.current_for_voltage(target, 1.0), 1.0)
        assert pack.voltage == pytest.approx(target, abs=1e-6)


def test_the_csv_carries_each_cell_and_the_balance_mask():
    out = io.StringIO()
    _weak_run(weak_cell_pct=15.0).log.write_csv(out)
    header = out.getvalue().splitlines()[0].split(",")
    assert header[-5:] == CELLS + ["balance_mask"]


@pytest.mark.parametrize("setup, message", [
    (BatterySetup(weak_cell_pct=120.0), "weak cell"),
    (BatterySetup(cell_spread=(60.0, 0.0, 0.0)), "cell spread"),
])
def test_bad_cells_are_refused_in_one_line(setup, message):
    with pytest.raises(StartError, match=message):
        simulate(record_of("LiPo"), StartParams("charge", 1, 2000, 2.0, None, 4), setup)


def test_the_b6_balancer_bleeds_through_its_resistor_and_keeps_bleeding_down_to_the_lowest_cell():
    from zuml_studio.sim.charger_model import load_charger
    bal = load_charger("imax_b6").balancer
    assert bal.bleed(4.2) == pytest.approx(0.300) and bal.bleed(3.6) == pytest.approx(3.6 / 14.0)
    assert bal.mask([4.000, 4.005, 4.009]) == 0b100                  # more than 8 mV above the lowest
    assert bal.mask([4.000, 4.005, 4.004], bleeding=0b100) == 0b100  # once bleeding: while above the lowest
    assert bal.mask([4.000, 4.005, 4.000], bleeding=0b100) == 0
    assert bal.ceiling_reason("LiPo", [4.1, 4.1996], 0.1, 1.0) == "balancer: cell 2 reached 4.20V (ceiling)"
    assert bal.ceiling_reason("LiPo", [4.1, 4.1994], 0.1, 1.0) is None
    assert bal.ceiling_reason("NiMh", [9.0], 0.1, 1.0) is None


def test_the_b6_balancer_bleeds_in_windows_as_its_firmware_does():
    # firmware/boards/imaxb6/balance.c and board.c's balance(): 4 s with the loads off, then up to 3 cells, the
    # highest first, for at most 15 s; a cell leaves once presumed down to the lowest that does not bleed
    from zuml_studio.sim.charger_model import BalanceWindow, load_charger
    bal = load_charger("imax_b6").balancer
    w, lipo = BalanceWindow(), "LiPo"
    cells = [4.000, 4.020, 4.030, 4.000, 4.040, 4.050]
    assert [bal.window(w, cells, 1.0, False, lipo) for _ in range(4)] == [0, 0, 0, 0b110100]   # cells 6, 5, 3
    bled = [4.000, 4.020, 4.021, 4.000, 4.031, 4.041]          # each bleed takes 9 mV off its reading
    assert bal.window(w, bled, 1.0, False, lipo) == 0b110100 and w.drop[2] == pytest.approx(0.009)
    assert bal.window(w, [4.000, 4.020, 3.991, 4.000, 4.031, 4.041], 1.0, False, lipo) == 0b110000  # cell 3 is down
    for _ in range(12):
        assert bal.window(w, bled, 1.0, False, lipo) == 0b110000
    assert bal.window(w, bled, 1.0, False, lipo) == 0 and w.bled == 0b110000    # 15 s: the window ends
    assert [bal.window(w, [4.000, 4.000, 4.000, 4.000, 4.005, 4.000], 1.0, False, lipo) for _ in range(4)] == \
        [0, 0, 0, 0b010000]                                      # 5 mV: only a cell that bled in the last window
    w = BalanceWindow()
    low = [3.700, 3.740, 3.700]                                  # under 3.75 V: no window, unless CV holds
    assert [bal.window(w, low, 1.0, False, lipo) for _ in range(5)] == [0] * 5
    assert [bal.window(w, low, 1.0, True, lipo) for _ in range(4)] == [0, 0, 0, 0b010]


@pytest.mark.parametrize("table, said", [
    ({"bleed_r_ohm": 26.0, "bleed_a": 1.0}, "give bleed_r_ohm or bleed_a"),
    ({"bleed_a": 0.0}, "give bleed_r_ohm or bleed_a"),
    ({"bleed_a": 1.0, "during": "always"}, "during must be"),
    ({"bleed_a": 1.0, "ceiling_v": {"LiPo": 42.0}}, "each ceiling_v must be 0..10 V"),
])
def test_a_bad_balancer_table_is_refused_in_one_line(table, said):
    from zuml_studio.sim.charger_model import _balancer
    base = {"during": "charge", "spread_v": 0.008, "ceiling_v": {"LiPo": 4.2}}
    with pytest.raises(ValueError, match=said):
        _balancer({**base, **table})


def test_the_weak_cell_can_be_any_cell_and_must_be_in_the_pack():
    r = _weak_run(weak_cell_pct=15.0, weak_cell=2)
    cells = r.phases[-1].cells_end
    assert max(cells) == cells[1] and np.argmax(np.array(cells)) == 1
    with pytest.raises(StartError, match="weak cell 5: the pack has cells 1 to 4"):
        _weak_run(weak_cell_pct=15.0, weak_cell=5)


def test_the_balancer_acts_alike_however_the_run_is_advanced():
    # its hysteresis (a bleeding cell goes on while above the lowest) is the phase's, not one run of ticks'
    setup = BatterySetup(cell_spread=(3.0, 10.0, 2.0), seed=3)
    params = StartParams("charge", 1, 2000, 2.0, None, 6, True)
    whole, stepped = (prepare(record_of("LiPo"), params, setup).interpreter for _ in range(2))
    whole.run()
    while stepped.advance(997):
        pass
    assert stepped.phases == whole.phases
    assert (stepped.log.arrays()["balance_mask"] == whole.log.arrays()["balance_mask"]).all()
    assert whole.log.arrays()["balance_mask"].any()


def test_the_b6_balancer_ends_a_held_charge_only_when_its_current_has_fallen_to_a_tenth():
    from zuml_studio.sim.charger_model import load_charger
    bal = load_charger("imax_b6").balancer
    assert bal.ceiling_reason("LiPo", [4.1, 4.2], 0.1, 1.0) is not None        # at a tenth: cheali's minIc
    assert bal.ceiling_reason("LiPo", [4.1, 4.2], 0.1001, 1.0) is None
    assert bal.ceiling_reason("LiPo", [4.1, 4.2], 0.0, -1.0) is None          # no current asked (a pause)
    assert bal.ceiling_reason("LiPo", [4.1, 4.2], 0.08, 0.0, [0.16, 0.0]) is not None   # CV: the bleeds take all
    assert bal.ceiling_reason("LiPo", [4.1, 4.2], 0.0801, 0.0, [0.16, 0.0]) is None
    assert bal.ceiling_reason("LiPo", [4.1, 4.2], 0.18, 1.0, [0.16, 0.0]) is not None   # 0.16 A bled over 2 cells
    assert bal.ceiling_reason("LiPo", [4.1, 4.2], 0.1801, 1.0, [0.0, 0.16]) is None


CC_TO_CEILING = """MACRO Past
  AKK_TYPE={chem}
  CHARGE_SECTION
    FAZE
    CONSTANT_I=1C
    IF(V>{over}S) STOP_FAZE()
    END_FAZE
    FAZE
    CONSTANT_I=1C
    CONSTANT_V={cv}S
    IF(I<0.05C) STOP_FAZE()
    END_FAZE
  END_SECTION
END_MACRO
"""


@pytest.mark.parametrize("charger", ["imax_b6", "icharger_406duo"])
@pytest.mark.parametrize("chem, over, cv", [("LiPo", "4.25", "4.2"), ("LiFe", "3.65", "3.6"), ("LiIon", "4.24", "4.2")])
@pytest.mark.parametrize("spread", [dict(weak_cell_pct=15.0), dict(cell_spread=(10.0, 30.0, 10.0), seed=3),
                                    dict(weak_cell_pct=30.0, weak_cell=1)])
def test_no_cell_passes_its_ceiling_at_any_tick_and_no_phase_starts_above_its_own_current(charger, chem, over, cv,
                                                                                         spread):
    # a CC that asks for more than the ceiling (the balancer's held end ends it), then a CV at the ceiling
    from helpers import compiled
    from zuml_studio.sim.charger_model import load_charger
    record = compiled(CC_TO_CEILING.format(chem=chem, over=over, cv=cv))
    r = simulate(record, StartParams("charge", 1, 2200, None, None, 4), BatterySetup(charger=charger, **spread))
    ceiling = load_charger(charger).balancer.ceiling_v[chem]
    a = r.log.arrays()
    volts = np.column_stack([a[c] for c in CELLS])
    assert volts.max() <= ceiling + 0.005
    cc, cv_phase = r.phases
    assert cc.reason.startswith("balancer: cell")                       # held, then ended at a tenth of 1C
    in_cv = a["phase"] == cv_phase.run
    assert a["current_a"][in_cv].max() <= 2.2 + 1e-6                    # its own limit, 1C (a 1.2 A bleed may
                                                                        # let it start above the CC's end)
