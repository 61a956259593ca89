"""Time on the simulated B6: the firmware's millisecond clock (Timer0 in CTC, docs/firmware.md) agrees with the
simulated time, and PC requests reach the B6 at simulated times the test chooses (`--rx`), so a run's start has
a known phase against the firmware's 1 s measuring window whatever the host's speed."""
import pytest

from b6_harness import rx_at, start_at
from helpers import compiled
from zuml_studio.lang import eeprom

RATE_TOLERANCE = 0.002              # 0.2 %: time limits and the charge counted per 1 s tick depend on it
STORE_SIZE = 404                    # IDENTIFY's eeprom_size on the B6 (docs/firmware.md, Calibration)
CC_CV = """MACRO Held
  AKK_TYPE=LiPo
  CHARGE_SECTION
    FAZE
    CONSTANT_I=5A
    CONSTANT_V=4.2S
    IF(tf>60) STOP_FAZE()
    END_FAZE
  END_SECTION
END_MACRO
"""



def test_the_firmware_s_uptime_keeps_the_simulated_time(b6_on):
    # two STATUS requests 10 simulated seconds apart: the uptime between their answers is 10 s within 0.2 %
    # (simavr 1.6 ignored Timer0's CTC: 9.77 s, 2.3 % slow), and each uptime is the simulated time less the
    # boot's few ms
    sim = b6_on(b"", "--cells", "3", *rx_at(2.0, "STATUS", 1), *rx_at(12.0, "STATUS", 2))
    got = sim.answers(2)
    early, late = got[1]["uptime_ms"] / 1000, got[2]["uptime_ms"] / 1000
    assert late - early == pytest.approx(10.0, rel=RATE_TOLERANCE), (early, late)
    assert 1.9 <= early <= 2.0, early


def test_no_isr_or_locked_section_holds_the_interrupts_off_for_half_a_millisecond(b6_on):
    # a Timer0 match waits while the interrupts are off and is lost only past 1 ms: the longest stretch (the
    # harness's INTERRUPTS line) through a 5 A CC-CV charge with its ticks' latches, the PC asking STATUS every
    # 0.5 s and the balancer's first bleed. Measured 272 us (the ADC interrupt's reading); the latch that divided
    # all 11 averages under one lock held them off 515 us
    status = [arg for k in range(10) for arg in rx_at(2 + k * 0.5, "STATUS", 20 + k)]
    sim = b6_on(eeprom.pack([compiled(CC_CV)], STORE_SIZE), "--cells", "3", "--soc", "0.9", "--cell-spread", "60",
                *start_at(1.3, 3), *status)
    assert sim.answers(11)[7] == {"slot": 0, "name": "Held"}
    sim.wait_line(lambda line: line.startswith("BALANCER|") and not line.endswith("|0"))
    sim.stop()
    _k, off = sim.wait_line("INTERRUPTS|off|")
    assert float(off.split("|")[2]) < 500, off
