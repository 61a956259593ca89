"""The set points board.c's hal_output passes on to the stage, measured on the simulated B6 by the model's TRUE
values (--trace), where nothing else holds the output: a nickel charge on a pack without its balance lead (no
balancer's hold caps the current at the macro's own) and a discharge down to its floor. Each test kills a mutant
tools/mutate_firmware.py makes of hal_output's unit conversions (issue 31, section 6; docs/firmware.md, *Mutation
testing*). Runs are started from the PC; the tests wait for the harness's lines and the trace, never for a time."""
import pytest

from b6_harness import LINE_WAIT_S, read_trace, started, switched_on, trace_rows
from helpers import until


def _macro(chemistry: str, section: str, current: str, volts: str = "") -> str:
    hold = f"\n    CONSTANT_V={volts}" if volts else ""
    return (f"MACRO Own\n  AKK_TYPE={chemistry}\n  {section}_SECTION\n    FAZE\n    CONSTANT_I={current}{hold}\n"
            f"    IF(tf>60) STOP_FAZE()\n    END_FAZE\n  END_SECTION\nEND_MACRO\n")


def _window(sim, from_ms: float, to_ms: float):
    """The trace's rows from..to ms after the output went on (the run stopped after them)."""
    k, on = sim.wait_line(switched_on)
    on_ms = float(on.split("|")[2]) * 1000
    assert until(lambda: any(r.t_ms >= on_ms + to_ms for r in trace_rows(sim)), LINE_WAIT_S)
    assert not any(line.startswith("OUTPUT|off|") for line in sim.lines[k:]), sim.lines[k:]   # no trip
    sim.stop()
    return [r for r in read_trace(sim.trace) if on_ms + from_ms <= r.t_ms < on_ms + to_ms]


@pytest.mark.parametrize("volts", ["", "1.6S"])           # a current alone; CC-CV, the pack far below its CV
def test_a_nickel_charge_without_a_balance_lead_gets_its_own_current(b6, volts):
    # 2 LiPo cells at rest (7.66 V) are, to a NiMH macro told 6 cells, 1.28 V a cell; with no lead there is no
    # balancer's hold, whose cap (the macro's own current) hides a set point passed on twice as large
    sim = b6(_macro("NiMH", "CHARGE", "1A", volts), "--cells", "2", "--soc", "0.5", "--no-balance-lead")
    started(sim, "charge", 6)
    rows = _window(sim, 500, 1500)
    mean_a = sum(r.current_a for r in rows) / len(rows)
    assert 0.8 <= mean_a <= 1.05, mean_a




def test_a_discharge_down_to_its_floor_is_held_there(b6):
    # 1S at rest 3.83 V, 1 A down to 3.80 V: the floor binds at once and the discharge creeps up to hold it (0.54 A
    # at 3.803 V, 3..4 s after the start, measured); a floor passed on half as high discharges at the full 1 A and
    # pulls the cell to 3.78 V in the same seconds
    sim = b6(_macro("LiPo", "DISCHARGE", "1A", "3.8S"), "--cells", "1", "--soc", "0.5")
    started(sim, "discharge", 1)
    rows = _window(sim, 3000, 4000)
    mean_v, mean_a = (sum(x) / len(rows) for x in zip(*((r.voltage_v, -r.current_a) for r in rows)))
    assert 3.795 <= mean_v <= 3.815 and 0.2 <= mean_a <= 0.75, (mean_v, mean_a)



def test_a_charge_from_off_starts_at_the_duty_that_puts_its_current_on_at_once(b6):
    # stage_set presets the buck at 95 % of Vout/Vin (cheali SMPS_PID::init), so the first 100 ms after the output
    # goes on already carry the set point: 0.79 A in the first 50 ms, 1.0 A after (2S, 1 A, measured); a duty
    # preset at half of that, or not at all, carries nothing for 50 ms and 0.58 A in the next 50
    sim = b6(_macro("LiPo", "CHARGE", "1A"), "--cells", "2", "--soc", "0.5")
    started(sim, "charge", 2)
    rows = _window(sim, 0, 100)
    mean_a = sum(r.current_a for r in rows) / len(rows)
    assert 0.7 <= mean_a <= 1.05, mean_a


def test_a_charge_whose_voltage_is_below_the_pack_s_holds_the_stage_shut(b6):
    # 1S at 4.1 V told CC-CV to 3.9 V: the voltage's error drives the duty down past zero, where it must stay at
    # zero (step's floor); a duty that wrapped below zero would read as the stage's top and push amps into the cell
    sim = b6(_macro("LiPo", "CHARGE", "1A", "3.9S"), "--cells", "1", "--soc", "0.9")
    started(sim, "charge", 1)
    rows = _window(sim, 500, 1500)
    assert max(r.current_a for r in rows) <= 0.05, max(r.current_a for r in rows)
    assert max(r.buck_duty for r in rows) == 0 and max(r.boost_duty for r in rows) == 0
