"""The simulated iMAX B6 itself (firmware/harness/b6_*), checked with a probe image written from cheali's pin map
(tests/firmware/b6_probe.c) rather than with our firmware: what reaches each ADC channel and multiplexer address,
the buck stage and its trace, the LCD and the buttons, every fault, a hang and the watchdog, the calibration block.
Expected values come from cheali's default calibration (the full scales in docs/firmware.md), not from the
harness's table, and hold within the components' tolerances."""
import struct
import subprocess

import pytest

from b6_harness import B6, B6_SIM, build, read_trace

# the value at AREF of each probe request (V, degC): cheali's imaxB6-original defaultCalibration.cpp
FULL_SCALE = {"a0": 29.902, "a1": 30.826, "a4": 19.154, "m0": 5.022, "m1": 4.985, "m2": 9.761, "m3": 4.899,
              "m4": 5.016, "m5": 4.993, "m6": 4.924, "m7": 253.95}
ISMPS_FULL_A = 6.042
TOLERANCE = 0.03           # 1 % dividers, 1 % reference, the probe's 2 %, the ADC's LSB


@pytest.fixture(scope="module")
def probe(tmp_path_factory):
    build("simavr-imaxb6")
    elf = tmp_path_factory.mktemp("probe") / "probe.elf"
    done = subprocess.run(["avr-gcc", "-std=c99", "-Wall", "-Werror", "-mmcu=atmega32", "-DF_CPU=16000000UL", "-Os",
                           "-o", str(elf), str(B6_SIM.parents[3] / "tests" / "firmware" / "b6_probe.c")],
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    return elf


@pytest.fixture
def b6(probe):
    started = []

    def start(*args):
        sim = B6(probe, "--speed", "0", *args)
        started.append(sim)
        assert sim.port.startswith("/dev/"), sim.port
        return sim

    yield start
    for sim in started:
        sim.stop()


def reading(sim, request):
    """A probe reading as 10-bit counts (the mean of its 64 conversions)."""
    name, value = sim.ask(request).split("=")
    assert name == request
    return int(value) / 64


def counts(request, value):
    return value / FULL_SCALE[request] * 1023


def test_the_adc_channels_and_the_multiplexer_carry_the_b6s_inputs(b6, tmp_path):
    sim = b6("--cells", "4", "--soc", "0.5", "--seed", "11", "--trace", tmp_path / "t.csv")
    got = {request: reading(sim, request) for request in FULL_SCALE}
    ismps = reading(sim, "a3")
    sim.stop()
    pack = read_trace(tmp_path / "t.csv")[-1].voltage_v
    cell = pack / 4
    expected = {"a0": pack, "a1": 0, "a4": 12.0, "m0": 0, "m1": cell, "m2": 2 * cell, "m3": cell, "m4": cell,
                "m5": 0, "m6": 0, "m7": 25.0}
    for request, value in expected.items():
        assert got[request] == pytest.approx(counts(request, value), rel=TOLERANCE, abs=2), request
    assert ismps < 8                 # the current amplifier's offset alone: no current flows


def test_the_buck_stage_charges_through_its_inductor_and_the_trace_is_the_models_truth(b6, tmp_path):
    sim = b6("--cells", "3", "--soc", "0.5", "--trace", tmp_path / "t.csv")
    idle = reading(sim, "a3")
    assert sim.ask("b500") == "ok"
    charging = reading(sim, "a3")
    assert sim.ask("x\n") == "ok"
    after = reading(sim, "a3")
    sim.stop()
    rows = read_trace(tmp_path / "t.csv")
    assert [r.t_ms for r in rows] == list(range(rows[0].t_ms, rows[0].t_ms + len(rows)))   # every simulated ms
    on = [r for r in rows if r.output_enabled]
    assert on and rows[0].output_enabled == 0 and rows[-1].output_enabled == 0
    # fast PWM mode 14, TOP 512: OCR 500 is on for 501 of 513 clocks
    assert on[-1].buck_duty == pytest.approx(501 / 513, abs=1e-4) and on[-1].boost_duty == 0
    current = on[-1].current_a
    assert 0.3 < current < 5 and on[-1].voltage_v > rows[0].voltage_v
    assert charging - idle == pytest.approx(current / ISMPS_FULL_A * 1023, rel=0.05)
    assert after == pytest.approx(idle, abs=2) and rows[-1].current_a == 0


def test_the_lcd_shows_what_the_image_writes_and_the_buttons_pull_their_lines_low(b6):
    sim = b6("--lcd", "--press", "start@0.5", "--press", "inc@1.0:0.5", "--press", "stop@2")
    k, _ = sim.wait_line("LCD|PROBE|KEYS    S")
    k, _ = sim.wait_line("LCD|PROBE|KEYS   i", k)
    k, _ = sim.wait_line(lambda line: line == "LCD|PROBE|KEYS", k)
    sim.wait_line("LCD|PROBE|KEYS s", k)


@pytest.mark.parametrize("fault, asked, value", [
    ("cell-high", "m3", 4.35),         # the third (last) cell's tap reads 4.35 V
    ("sensor-open", "m7", 0.0),        # an unplugged probe reads 0 V
    ("input-low", "a4", 10.5),         # the supply sags below 11 V
    ("input-sag", "a4", 11.3),         # ... or only under half a charged 6S pack, over the 11 V trip
])
def test_a_fault_changes_what_the_board_reads(b6, fault, asked, value):
    sim = b6("--cells", "3", "--soc", "0.5", "--fault", f"{fault}@0.2")
    sim.wait_line(f"FAULT|{fault}|0.200")
    assert reading(sim, asked) == pytest.approx(counts(asked, value), rel=TOLERANCE, abs=2)


def test_a_reversed_pack_behind_the_open_output_switch_lifts_vout_minus(b6, tmp_path):
    sim = b6("--cells", "3", "--soc", "0.5", "--fault", "reverse@0.2", "--trace", tmp_path / "t.csv")
    sim.wait_line("FAULT|reverse|0.200")
    assert reading(sim, "a0") < 2 and reading(sim, "a1") == pytest.approx(counts("a1", 3 * 3.83), rel=TOLERANCE)
    sim.stop()
    assert all(r.voltage_v < -10 and r.current_a == 0 for r in read_trace(tmp_path / "t.csv") if r.t_ms > 200)


def test_a_reversed_pack_on_the_output_is_a_short_through_the_diode(b6, tmp_path):
    sim = b6("--cells", "3", "--soc", "0.5", "--fault", "reverse@0.2", "--press", "start@0.4", "--press", "stop@0.6",
             "--lcd", "--trace", tmp_path / "t.csv")
    sim.wait_line("LCD|PROBE|KEYS s")
    sim.stop()
    rows = read_trace(tmp_path / "t.csv")
    assert min(r.current_a for r in rows if r.t_ms > 450) < -5


def test_a_disconnected_battery_leaves_the_stage_on_an_open_output(b6, tmp_path):
    sim = b6("--cells", "3", "--soc", "0.5", "--press", "start@0.2", "--fault", "disconnect@1", "--trace",
             tmp_path / "t.csv")
    sim.wait_line("FAULT|disconnect|1.000")
    open_v = reading(sim, "a0")
    sim.stop()
    rows = read_trace(tmp_path / "t.csv")
    assert next(r for r in rows if r.t_ms == 999).current_a > 0.3
    assert all(r.current_a == 0 for r in rows if r.t_ms > 1000)
    # no battery to hold it: the output capacitor rises to what the buck makes of 12 V
    assert rows[-1].voltage_v == pytest.approx(12.0 * 501 / 513, rel=0.03)
    assert open_v == pytest.approx(counts("a0", rows[-1].voltage_v), rel=TOLERANCE)


def test_sink_hot_is_reported_but_the_b6_has_no_heat_sink_sensor_to_show_it(b6):
    sim = b6("--fault", "sink-hot@0.1")
    sim.wait_line("FAULT|sink-hot|0.100")
    # every ADC channel and mux address is taken by another input (cheali's map): none carries a heat sink
    assert reading(sim, "m7") == pytest.approx(counts("m7", 25.0), rel=TOLERANCE)


def test_a_hang_stops_the_main_loop_and_the_images_watchdog_resets_it(b6, tmp_path):
    sim = b6("--press", "start@0.2", "--fault", "hang@0.5", "--lcd", "--trace", tmp_path / "t.csv")
    k, _ = sim.wait_line("FAULT|hang|")
    k, reset = sim.wait_line("RESET|watchdog|", k)
    sim.wait_line("LCD|PROBE WDT", k)
    sim.stop()
    hang_ms = 500
    reset_ms = float(reset.split("|")[2]) * 1000
    assert hang_ms < reset_ms <= hang_ms + 35                   # the probe's 30 ms watchdog, its last feed before
    rows = read_trace(tmp_path / "t.csv")
    assert next(r for r in rows if r.t_ms == hang_ms).output_enabled == 1
    # the stage keeps its last duty while the loop is stuck; the image's first instructions switch it off
    assert all(r.output_enabled == 0 for r in rows if r.t_ms > reset_ms + 1)


def calibration_block(path):
    block = path.read_bytes()[970:1024]
    check = 0
    for byte in block[:53]:
        check ^= byte
    return block[0], [struct.unpack_from("<HH", block, 1 + 4 * k) for k in range(13)], check == block[53]


def test_the_eeprom_starts_with_the_block_the_calibration_procedure_finds(b6, tmp_path):
    sim = b6("--cells", "3", "--soc", "0.5", "--seed", "5", "--eeprom", tmp_path / "ee.bin",
             "--trace", tmp_path / "t.csv")
    vout = reading(sim, "a0") * 64
    sim.stop()
    version, pairs, checked = calibration_block(tmp_path / "ee.bin")
    assert version == 1 and checked
    zero, full = pairs[0]
    assert zero == 0 and full == pytest.approx(29902, rel=0.025)
    # what the procedure does not reach keeps the nominal values: Vout-, Vb0, the taps above 3 cells, T extern
    assert [pairs[k] for k in (1, 5, 9, 10, 11, 12)] == [(0, 30826), (0, 5022), (0, 5016), (0, 4993), (0, 4924),
                                                         (0, 25395)]
    assert 116 <= pairs[3][0] <= 350                             # I smps: its amplifier's true offset
    # through the block, the probe's average reads the model's true voltage
    assert (vout - zero) * full / 65536 == pytest.approx(read_trace(tmp_path / "t.csv")[-1].voltage_v * 1000, abs=10)


def test_a_calibration_in_the_eeprom_file_is_kept_and_uncalibrated_erases_it(b6, tmp_path):
    path = tmp_path / "ee.bin"
    b6("--seed", "5", "--eeprom", path).stop()
    first = calibration_block(path)
    b6("--seed", "6", "--eeprom", path).stop()
    assert calibration_block(path) == first
    b6("--uncalibrated", "--eeprom", path).stop()
    assert path.read_bytes()[970:1024] == b"\xff" * 54


@pytest.mark.parametrize("args, message", [
    (["--fault", "melt@1"], "--fault is KIND@SECONDS"),
    (["--fault", "hang"], "--fault is KIND@SECONDS"),
    (["--press", "start@soon"], "--press is BUTTON@SECONDS[:HOLD]"),
    (["--press", "reset@1"], "--press is BUTTON@SECONDS[:HOLD]"),
    (["--cells", "7"], "--cells is 1..6"),
    (["--speed", "-1"], "--speed is 0"),
    (["--seed", "1.5"], "--seed is a whole number"),
    (["--bogus"], "unknown option"),
    (["--rx", "a5f@1"], "--rx is HEX@SECONDS"),                 # not whole bytes
    (["--rx", "zz@1"], "--rx is HEX@SECONDS"),
    (["--rx", "a5"], "--rx is HEX@SECONDS"),
    (["--rx", "00" * 49 + "@1"], "--rx is HEX@SECONDS"),       # past simavr's receive queue
    (["--rx", "a5@1", "--no-rx"], "--rx needs the receive wire"),
])
def test_bad_options_are_one_line_and_exit_2(probe, args, message):
    done = subprocess.run([str(B6_SIM), str(probe), *args], capture_output=True, text=True, timeout=30)
    assert done.returncode == 2 and done.stdout == ""
    assert len(done.stderr.strip().splitlines()) == 1 and message in done.stderr


def test_timer0_in_ctc_matches_once_a_millisecond(b6):
    # the firmware's millisecond clock is Timer0 in CTC (OCR0 249, /64): simavr 1.6 gives the ATmega32's Timer0 no
    # WGM bits, so it ignored CTC and matched every 256 counts (1.024 s for 1000 matches, the firmware's clock
    # 2.3 % slow); the harness gives Timer0 its WGM bits and modes as the datasheet (and simavr after 1.6) does
    sim = b6("--cells", "3")
    assert sim.ask("t0") == "ok"
    k, on = sim.wait_line("BALANCER|")
    _k, off = sim.wait_line("BALANCER|", k + 1)
    assert on.endswith("|1") and off.endswith("|0"), (on, off)
    lasted_s = float(off.split("|")[1]) - float(on.split("|")[1])
    assert lasted_s == pytest.approx(1.000, abs=0.0002), lasted_s          # 1000 x 250 x 64 cycles, +- a step
