"""The imaxb6 image on the simulated iMAX B6 (issue 23's acceptance): every fault switches the output off within
100 ms and ends the run with its reason as an event; a macro started with the buttons alone runs to its end; a 3S
LiPo pack whose cells start 60 mV apart ends its CV with the cells within 10 mV. Runs are started from the front
panel (--press), so everything happens at a simulated time the test chose, and the test waits for the harness's
lines (LCD, OUTPUT, FAULT), never for a time."""
import pytest

from b6_harness import B6, build, read_trace
from helpers import compiled
from host_core import FIRMWARE
from zuml_studio.device.client import ChargerClient
from zuml_studio.lang import eeprom

BENCH = """MACRO Bench
  AKK_TYPE=LiPo
  CHARGE_SECTION
    FAZE
    CONSTANT_I=1A
    IF(V>4.1S) STOP_FAZE()
    END_FAZE
    FAZE
    CONSTANT_V=4.2S
    IF(I<0.1A) STOP_FAZE()
    END_FAZE
  END_SECTION
END_MACRO
"""
STORE_SIZE = 404                    # IDENTIFY's eeprom_size on the B6 (docs/firmware.md, Calibration)
FAULT_AT_S = 1.5
START = "start@0.3:0.7"             # START held 0.7 s (the panel wants 0.5 s)


@pytest.fixture(scope="module")
def image():
    build("imaxb6", "simavr-imaxb6")
    return FIRMWARE / "build" / "imaxb6" / "zuml.elf"


@pytest.fixture
def b6(image, tmp_path):
    """start(*args): the image on the simulated B6 with the Bench macro in slot 1 (EEPROM file per test)."""
    started = []
    store = eeprom.pack([compiled(BENCH)], STORE_SIZE)

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


def end_reason_and_finish(sim):
    """STATUS's end reason and the run's last event (None when the device holds none), once the run is over."""
    client = ChargerClient(sim.port, timeout=10)
    try:
        status = client.status()
        return status.end_reason, client.get_event(status.events - 1) if status.events else None
    finally:
        client.close()


@pytest.mark.parametrize("fault, text", [
    ("disconnect", "battery disconnected"),
    ("reverse", "battery reversed"),
    ("cell-high", "cell 3 over max"),
    ("sensor-open", "probe open"),
    ("input-low", "input below 11V"),
])
def test_a_fault_switches_the_output_off_within_100_ms_and_ends_the_run_with_its_reason(b6, fault, text):
    sim = b6("--cells", "3", "--soc", "0.5", "--press", START, "--fault", f"{fault}@{FAULT_AT_S}")
    k, _ = sim.wait_line("OUTPUT|on|")
    k, _ = sim.wait_line(f"FAULT|{fault}|", k)
    k, off = sim.wait_line("OUTPUT|off|", k)
    assert float(off.split("|")[2]) - FAULT_AT_S <= 0.100
    sim.wait_line("LCD|end Bench|", k)
    reason, finish = end_reason_and_finish(sim)
    assert reason == f"protection: {text}"
    assert finish is not None and finish.kind == "finish" and finish.detail == f"protection: {text}"
    sim.stop()
    rows = read_trace(sim.trace)
    assert all(not r.output_enabled and abs(r.current_a) < 0.01 for r in rows if r.t_ms >= FAULT_AT_S * 1000 + 100)


def test_a_hang_switches_the_output_off_within_100_ms_and_the_watchdog_reports_it(b6):
    sim = b6("--cells", "3", "--soc", "0.5", "--press", START, "--fault", f"hang@{FAULT_AT_S}")
    k, _ = sim.wait_line("OUTPUT|on|")
    k, hang = sim.wait_line("FAULT|hang|", k)
    k, off = sim.wait_line("OUTPUT|off|", k)
    assert float(off.split("|")[2]) - float(hang.split("|")[2]) <= 0.100
    k, _ = sim.wait_line("RESET|watchdog|", k)
    sim.wait_line(lambda line: line.startswith("LCD|") and "watchdog" in line, k)
    reason, finish = end_reason_and_finish(sim)
    assert reason == "protection: watchdog reset"
    assert finish is not None and finish.kind == "finish" and finish.detail == reason, "no event carries the reason"


def test_a_macro_started_with_the_buttons_alone_runs_to_its_end(b6):
    # a small pack near full: CC to 4.1 V per cell, then CV until the current falls below 0.1 A
    sim = b6("--cells", "3", "--soc", "0.9", "--capacity", "20", "--press", START)
    k, _ = sim.wait_line("LCD|C1 ")                       # the panel started phase 1 of the charge
    k, _ = sim.wait_line("LCD|C2 ", k)                    # ... and the macro moved to its CV phase
    k, end = sim.wait_line("LCD|end Bench|", k)
    reason, finish = end_reason_and_finish(sim)
    assert finish is not None and finish.kind == "finish" and not reason.startswith("protection"), (reason, end)
    sim.stop()
    rows = read_trace(sim.trace)
    on = [r for r in rows if r.output_enabled]
    # the phase ended on its current: the last half second's mean (the 9-bit boost duty dithers it around 0.1 A)
    last = on[-500:]
    assert sum(r.current_a for r in last) / len(last) < 0.1 + 0.01
    assert max(r.voltage_v for r in on) < 3 * 4.2 + 0.05


def test_a_3s_lipo_60_mv_apart_ends_its_cv_with_the_cells_within_10_mv(b6):
    sim = b6("--cells", "3", "--soc", "0.9", "--capacity", "20", "--cell-spread", "60", "--press", START)
    k, _ = sim.wait_line("LCD|C2 ")
    end, _ = sim.wait_line("LCD|end Bench|", k)
    sim.wait_line("BALANCER|", k)                         # the balancer bled during the CV phase
    off = [line for line in sim.lines[:end] if line.startswith("OUTPUT|off|")][-1]    # the CV phase's end
    cells = [float(v) for v in off.split("|")[3:]]
    assert len(cells) == 3 and max(cells) - min(cells) <= 0.010, cells
