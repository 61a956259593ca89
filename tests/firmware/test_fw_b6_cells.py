"""Issue 31, sections 1 and 3, on the simulated iMAX B6 (the imaxb6 image; the model's truth from --trace): the
balance lead is evidence for every chemistry, no run starts without a cell count the firmware trusts, a START
during a run is BUSY, a reversed pack mid-charge is off within 10 ms, a pack the boost cannot reach says so."""
import pytest

from b6_harness import B6, build, read_trace
from helpers import compiled
from host_core import FIRMWARE
from zuml_studio.device import messages as m
from zuml_studio.device.client import ChargerClient
from zuml_studio.device.errors import DeviceError
from zuml_studio.lang import eeprom

STORE_SIZE = 404                    # IDENTIFY's eeprom_size on the B6
LIPO_MAX_V = 4.35
SLOTS = ("NiMh", "LiFe", "Pb", "NiCd", "LiPo")


def macro(akk: str) -> bytes:
    """A charge at 1 A with no cell count anywhere (no SERIES, no S values): only its chemistry."""
    return compiled(f"MACRO {akk}1A\n  AKK_TYPE={akk}\n  CHARGE_SECTION\n    FAZE\n      CONSTANT_I=1A\n"
                    "      IF(tf>1h) STOP_FAZE\n    END_FAZE\n  END_SECTION\nEND_MACRO\n")


@pytest.fixture(scope="module")
def image():
    build("imaxb6", "simavr-imaxb6")
    return FIRMWARE / "build" / "imaxb6" / "zuml.elf"


@pytest.fixture
def b6(image, tmp_path):
    """start(*args): the image on the simulated B6, one macro per chemistry of SLOTS in its slots."""
    started = []
    store = eeprom.pack([macro(akk) for akk in SLOTS], STORE_SIZE)

    def start(*args):
        path = tmp_path / f"ee{len(started)}.bin"
        path.write_bytes(store + b"\xff" * (1024 - len(store)))
        sim = B6(image, "--speed", "0", "--lcd", "--eeprom", path, "--trace", tmp_path / f"t{len(started)}.csv",
                 *args)
        sim.trace = tmp_path / f"t{len(started)}.csv"
        started.append(sim)
        return sim

    yield start
    for sim in started:
        sim.stop()


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
