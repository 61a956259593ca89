"""Issue 31's lying calibrations on the simulated iMAX B6: blocks whose current sensor reads 1/3, about 0 and 3x
the truth, and whose voltages all read 80 % and 120 %, are refused by CAL_WRITE with the point in volts or amps,
and a charger that finds one in its EEPROM at boot runs as "not calibrated" (no START, the output never on:
the model's true current in the trace). A calibration inside the window runs a 5 A charge under 5.5 A true."""
import re

import pytest

from b6_harness import read_trace, start_at, switched_on
from fake_b6_calibration import NOMINAL
from helpers import compiled, until
from zuml_studio.device.zuml.calibration import INPUTS, ISMPS, VIN, VOUT, VOUT_MINUS, Block, Calibrator
from zuml_studio.device.zuml.client import ChargerClient
from zuml_studio.device.errors import DeviceError
from zuml_studio.lang import eeprom

FIVE_AMPS = """MACRO Five
  AKK_TYPE=LiPo
  CHARGE_SECTION
    FAZE
    CONSTANT_I=5A
    IF(V>4.1S) STOP_FAZE()
    END_FAZE
  END_SECTION
END_MACRO
"""
STORE_SIZE = 404
CAL_AT = 970
UNCALIBRATED = 16
VOLTAGES = [VOUT, VOUT_MINUS, VIN] + [INPUTS.index(f"Vb{k}") for k in range(7)]


def lying(block: Block, kind: str) -> Block:
    """The block with the current sensor reading 1/3, ~0 or 3x the truth, or every voltage 80 % or 120 %."""
    pairs = list(block.pairs)
    scale, inputs = {"I/3": (1 / 3, [ISMPS]), "I~0": (0.002, [ISMPS]), "3I": (3, [ISMPS]),
                     "V80%": (0.8, VOLTAGES), "V120%": (1.2, VOLTAGES)}[kind]
    for k in inputs:
        zero, full = pairs[k]
        pairs[k] = (zero, max(1, min(65535, round(full * scale))))
    return Block(tuple(pairs))


# what CAL_WRITE names: the first input out of its window, at the board's maximum (27 V out, 5 A charge)
REFUSAL = {"I/3": r"I charge reads 5\.00A as 1\.[5-8]\dA: more than 0\.40A off",
           "I~0": r"I charge reads 5\.00A as 0\.0\dA: more than 0\.40A off",
           "3I": r"I charge reads 5\.00A as 1[4-6]\.\d\dA: more than 0\.40A off",
           "V80%": r"Vout\+ reads 27\.00V as 2[12]\.\d\dV: more than 0\.81V off",
           "V120%": r"Vout\+ reads 27\.00V as 3[23]\.\d\dV: more than 0\.81V off"}


@pytest.fixture
def b6(b6_on):
    """start(calibration=None, *args): the image on the simulated B6, Five in slot 0, the block given (else the
    model's own) in its EEPROM."""
    def start(calibration: Block | None = None, *args):
        data = bytearray(eeprom.pack([compiled(FIVE_AMPS)], STORE_SIZE).ljust(1024, b"\xff"))
        if calibration is not None:
            data[CAL_AT:] = calibration.encode()
        return b6_on(bytes(data), *args)
    return start


def test_cal_write_refuses_each_lying_block_naming_its_point_and_keeps_the_calibration(b6):
    sim = b6(None, "--cells", "2", "--soc", "0.5")
    with ChargerClient(sim.port, timeout=10) as client:
        calibrator = Calibrator(client)
        calibrated, good = calibrator.read()
        assert calibrated
        for kind, text in REFUSAL.items():
            with pytest.raises(DeviceError) as caught:
                client.request("CAL_WRITE", lying(good, kind).encode(), response_len=55, extra_s=1.0)
            assert re.fullmatch(text, caught.value.message), (kind, caught.value.message)
        assert calibrator.read() == (True, good)


@pytest.mark.parametrize("kind", list(REFUSAL))
def test_a_lying_block_found_at_boot_leaves_the_charger_not_calibrated_and_the_output_off(b6, kind):
    sim = b6(lying(NOMINAL, kind), "--cells", "2", "--soc", "0.5", "--press", "start@0.3:0.7")
    k, _ = sim.wait_line(lambda line: line.startswith("LCD|") and "not calibrated" in line)
    with ChargerClient(sim.port, timeout=10) as client:
        assert Calibrator(client).read() == (False, NOMINAL)
        with pytest.raises(DeviceError) as caught:
            client.start(0, current_a=5, series=2)
        assert caught.value.code == UNCALIBRATED
        assert until(lambda: client.status().uptime_s > 1.5, timeout_s=600)   # the panel's START held 0.3..1.0 s
    sim.stop()
    rows = read_trace(sim.trace)
    assert rows and not any(r.output_enabled for r in rows) and max(abs(r.current_a) for r in rows) < 0.01


def test_a_five_amp_charge_on_a_calibration_inside_its_window_stays_under_5_5_a_true(b6):
    """The current sensor reads 7 % under the nominal calibration (inside the 8 % window): the regulator's 5 A
    is at most 5 A / 0.92 of the truth."""
    pairs = list(NOMINAL.pairs)
    zero, full = pairs[ISMPS]
    pairs[ISMPS] = (zero, round(full * 0.93))
    sim = b6(Block(tuple(pairs)), "--cells", "2", "--soc", "0.3")
    with ChargerClient(sim.port, timeout=10) as client:
        assert Calibrator(client).read()[0]
        client.start(0, series=2)
        k, _ = sim.wait_line("OUTPUT|on|")
        started = client.status().uptime_s
        assert until(lambda: client.status().uptime_s > started + 3, timeout_s=600)
        client.stop()
    sim.wait_line("OUTPUT|off|", k)
    sim.stop()
    rows = [r for r in read_trace(sim.trace) if r.output_enabled]
    assert max(r.current_a for r in rows) > 4.0            # it did charge at about 5 A
    over = [r.t_ms for r in rows if r.current_a > 5.5]
    longest, run = 0, 0
    for a, b in zip(over, over[1:]):
        run = run + 1 if b == a + 1 else 0
        longest = max(longest, run)
    assert longest < 10, f"{len(over)} ms above 5.5 A, {longest + 1} in a row"


def test_the_charge_duty_stays_under_the_pack_ceiling_s_bound_when_no_current_flows(b6):
    """The main leads come off during a 5 A charge of a 2S pack: the current reads 0 and the regulator opens
    the stage; its duty stops where the output would be 2 x 4.35 V + 1.5 V from the 12 V input (duty.c), never
    the 50 % boost, until the protections end the run."""
    # the START at a simulated time of its own: sent from here, a loaded host could deliver it after the fault
    sim = b6(None, "--cells", "2", "--soc", "0.3", *start_at(1.0, cells=2), "--fault", "disconnect@2.5")
    k, _ = sim.wait_line(switched_on)
    k, _ = sim.wait_line("FAULT|disconnect|", k)
    k, off = sim.wait_line("OUTPUT|off|", k)
    sim.stop()
    rows = [r for r in read_trace(sim.trace) if 2500 <= r.t_ms <= float(off.split("|")[2]) * 1000]
    bound = (2 * 4.35 + 1.5) / 12.0                       # the input: 12 V +- 1 %, read within 3 %
    assert max(r.boost_duty for r in rows) == 0
    assert 0.9 * bound < max(r.buck_duty for r in rows) <= bound * 1.05


def toward_nominal(block: Block, k: int, share: float) -> Block:
    """The block with input k's scale moved `share` towards (and past) its nominal one: inside the window."""
    pairs = list(block.pairs)
    zero, full = pairs[k]
    pairs[k] = (zero, round(full * (1 - share if full > NOMINAL.pairs[k][1] else 1 + share)))
    return Block(tuple(pairs))


def test_a_start_is_refused_when_the_pack_and_its_balance_lead_read_apart(b6):
    """Vout+ calibrated 2.8 % off the taps (inside its window; a typo of the pack's voltage): the pack and the
    sum of its cells, one voltage with the output off, read more than 2 % + 50 mV apart."""
    sim = b6(None, "--cells", "3", "--soc", "0.5", "--speed", "1", "--press", "start@8:0.7")
    with ChargerClient(sim.port, timeout=10) as client:
        calibrator = Calibrator(client)
        good = calibrator.read()[1]
        calibrator.write(toward_nominal(good, VOUT, 0.028))
        assert client.status().uptime_s < 7.5               # before the panel's START
        with pytest.raises(DeviceError) as caught:
            client.start(0, series=3)
        assert caught.value.message == "pack and balance lead read over 2% apart: calibrate or check the leads"
        sim.wait_line(lambda line: line.startswith("LCD|") and "pack and balance" in line)   # the panel's START
        calibrator.write(toward_nominal(good, VOUT, 0.01))
        client.start(0, series=3)
        client.stop()
