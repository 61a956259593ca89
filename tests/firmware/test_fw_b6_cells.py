"""Issue 31, sections 1 and 3, on the simulated iMAX B6 (the imaxb6 image; the model's truth from --trace): the
balance lead is evidence for every chemistry, no run starts without a cell count the firmware trusts, a START
during a run is BUSY, a reversed pack mid-charge is off within 10 ms, a pack the boost cannot reach says so."""
import pytest

from b6_harness import read_trace
from helpers import compiled
from zuml_studio.protocol import messages as m
from zuml_studio.device.zuml.client import ChargerClient
from zuml_studio.device.errors import DeviceError
from zuml_studio.lang import eeprom

STORE_SIZE = 404                    # IDENTIFY's eeprom_size on the B6
LIPO_MAX_V = 4.35
SLOTS = ("LiPo", "NiMh", "LiFe", "Pb", "NiCd")      # slot 1, the panel's first, is LiPo


def macro(akk: str) -> bytes:
    """A charge at 1 A with no cell count anywhere (no SERIES, no S values): only its chemistry."""
    return compiled(f"MACRO {akk}1A\n  AKK_TYPE={akk}\n  CHARGE_SECTION\n    FAZE\n      CONSTANT_I=1A\n"
                    "      IF(tf>1h) STOP_FAZE\n    END_FAZE\n  END_SECTION\nEND_MACRO\n")


@pytest.fixture
def b6(b6_on):
    """start(*args): the image on the simulated B6, one macro per chemistry of SLOTS in its slots."""
    store = eeprom.pack([macro(akk) for akk in SLOTS], STORE_SIZE)
    return lambda *args: b6_on(store, *args)


@pytest.mark.parametrize("akk", ["NiMh", "LiFe", "Pb", "NiCd"])
def test_a_3s_lipo_at_4_14_v_a_cell_refuses_a_macro_of_another_chemistry_without_a_cell_count(b6, akk):
    sim = b6("--cells", "3", "--soc", "0.95")
    sim.wait_line("LCD|1 ")                               # the panel is up: the readings are in
    with ChargerClient(sim.port, timeout=10) as client:
        with pytest.raises(DeviceError) as refused:
            client.start(SLOTS.index(akk), "charge")      # no cell count, no capacity
        assert refused.value.code == m.ErrorCode.PROTECTION
        text = str(refused.value)
        assert client.status().state == "idle"
    if akk == "LiFe":                                     # lithium too, but above its 3.70 V
        assert "the balance lead shows 3 cells up to 4.1" in text and ": over LiFe's 3.65 V a cell" in text, text
        lcd = "cell "
    else:
        assert "the balance lead shows 3 cells up to 4.1" in text, text
        assert text.endswith(f" V: a lithium pack; this macro is for {akk}"), text
        lcd = "lithium pack"
    sim.wait_line(lambda line: line.startswith("LCD|") and line.split("|")[2].startswith(lcd))
    sim.stop()
    rows = read_trace(sim.trace)
    assert rows and not any(r.output_enabled for r in rows)
    assert max(r.cell_max_v for r in rows) <= LIPO_MAX_V + 0.050


def test_a_start_during_a_run_is_busy_and_the_run_goes_on_with_its_counters(b6):
    sim = b6("--cells", "3", "--soc", "0.5")
    sim.wait_line("LCD|1 ")
    with ChargerClient(sim.port, timeout=10) as client:
        assert client.start(SLOTS.index("LiPo"), "charge", series=3) == "LiPo1A"
        k, _ = sim.wait_line("LCD|C1 ")
        sim.wait_line(lambda line: line.startswith("LCD|C1 ") and " 0m" in line and "  1mAh" in line, k)
        before = client.status()
        with pytest.raises(DeviceError) as refused:
            client.start(SLOTS.index("LiPo"), "charge", series=3, capacity_mah=100)
        assert refused.value.code == m.ErrorCode.BUSY
        after = client.status()
        assert after.state == "running" and after.run_s >= before.run_s and after.events == before.events


def test_a_pack_reversed_mid_charge_is_off_within_10_ms_and_named_afterwards(b6):
    sim = b6("--cells", "3", "--soc", "0.5", "--press", "start@0.3:0.7", "--fault", "reverse@1.5")
    k, _ = sim.wait_line("FAULT|reverse|")
    k, off = sim.wait_line("OUTPUT|off|", k)
    assert float(off.split("|")[2]) - 1.5 <= 0.010
    sim.wait_line("LCD|end LiPo1A|battery reversed", k)
    with ChargerClient(sim.port, timeout=10) as client:
        assert client.status().end_reason == "protection: battery reversed"
    sim.stop()
    rows = read_trace(sim.trace)
    assert sum(1 for r in rows if abs(r.current_a) > 5.5) <= 10          # ms of the short through the pack


def test_a_6s_pack_above_twice_the_input_is_refused_with_both_voltages(b6):
    sim = b6("--cells", "6", "--soc", "0.9")                              # 24.5 V from a 12 V supply
    sim.wait_line("LCD|1 ")
    with ChargerClient(sim.port, timeout=10) as client:
        with pytest.raises(DeviceError) as refused:
            client.start(SLOTS.index("LiPo"), "charge", series=6)
    assert refused.value.code == m.ErrorCode.PROTECTION
    assert str(refused.value).startswith("the stage cannot reach the pack's 24.")
    assert str(refused.value).endswith(" V in: at most twice the input")
    sim.wait_line(lambda line: line.startswith("LCD|") and "twice" in line)


def test_a_6s_pack_charged_past_twice_the_input_ends_saying_so_not_disconnected(b6):
    # a small 6S pack from just within the boost's reach: its voltage rises past 2 x Vin and the current starves
    sim = b6("--cells", "6", "--soc", "0.6", "--capacity", "15")
    sim.wait_line("LCD|1 ")
    with ChargerClient(sim.port, timeout=10) as client:
        assert client.start(SLOTS.index("LiPo"), "charge", series=6) == "LiPo1A"
        k, _ = sim.wait_line("LCD|end LiPo1A|")
        assert client.status().end_reason == "protection: pack above twice the input"
    sim.stop()
    assert max(r.cell_max_v for r in read_trace(sim.trace)) <= LIPO_MAX_V + 0.050


def test_a_run_ends_at_twice_its_capacity_as_the_pack_s_true_charge_says(b6):
    sim = b6("--cells", "3", "--soc", "0.5")
    sim.wait_line("LCD|1 ")
    with ChargerClient(sim.port, timeout=10) as client:
        assert client.start(SLOTS.index("LiPo"), "charge", series=3, capacity_mah=2) == "LiPo1A"
        sim.wait_line("LCD|end LiPo1A|capacity limit")
        assert client.status().end_reason == "protection: capacity limit"
    sim.stop()
    mah = sum(r.current_a for r in read_trace(sim.trace)) / 3600        # 1 ms rows: A ms -> mAh
    assert 4.0 <= mah <= 4.0 * 1.05 + 0.1                               # 2 x 2 mAh; the slow check is 100 ms
