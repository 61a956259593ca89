"""Time on the simulated B6: the firmware's millisecond clock (Timer0 in CTC, docs/firmware.md) agrees with the
simulated time, and PC requests reach the B6 at simulated times the test chooses (`--rx`), so a run's start has
a known phase against the firmware's 1 s measuring window whatever the host's speed."""
import pytest

from b6_harness import rx_at

RATE_TOLERANCE = 0.002              # 0.2 %: time limits and the charge counted per 1 s tick depend on it


def test_the_firmware_s_uptime_keeps_the_simulated_time(b6_on):
    # two STATUS requests 10 simulated seconds apart: the uptime between their answers is 10 s within 0.2 %
    # (simavr 1.6 ignored Timer0's CTC: 9.77 s, 2.3 % slow), and each uptime is the simulated time less the
    # boot's few ms
    sim = b6_on(b"", "--cells", "3", *rx_at(2.0, "STATUS", 1), *rx_at(12.0, "STATUS", 2))
    got = sim.answers(2)
    early, late = got[1]["uptime_ms"] / 1000, got[2]["uptime_ms"] / 1000
    assert late - early == pytest.approx(10.0, rel=RATE_TOLERANCE), (early, late)
    assert 1.9 <= early <= 2.0, early
