"""The iMAX B6 board's calibration and protections (firmware/boards/imaxb6/calib.c, protect.c) built for the
PC and driven through ctypes: the decisions the ADC interrupt takes, reading by reading."""
import ctypes
import subprocess
import tomllib

import pytest

from host_core import FIRMWARE, ROOT
from tools import HOST, needs

pytestmark = needs(HOST)

(VOUT, VOUT_MINUS, IDIS, ISMPS, VIN, VB0, VB1, VB2, VB3, VB4, VB5, VB6, TEXTERN) = range(13)
BLOCK = 54
AKK = {"Undef": 0, "Pb": 1, "NiCd": 2, "NiMh": 3, "LiPo": 4, "LiIon": 5, "LiS": 6, "LiFe": 7, "New": 8}


@pytest.fixture(scope="module")
def lib():
    done = subprocess.run(["make", "-s", "-C", str(FIRMWARE), "build/host/libzuml_b6_logic.so"],
                          capture_output=True, text=True)
    assert done.returncode == 0, done.stdout + done.stderr
    so = ctypes.CDLL(str(FIRMWARE / "build" / "host" / "libzuml_b6_logic.so"))
    so.cal_value.restype = ctypes.c_int32
    so.cal_value.argtypes = [ctypes.c_uint8, ctypes.c_uint16]
    so.cal_adc16.restype = ctypes.c_uint16
    so.cal_adc16.argtypes = [ctypes.c_uint8, ctypes.c_int32]
    so.protect_arm.restype = ctypes.c_char_p
    so.protect_arm.argtypes = [ctypes.c_uint8, ctypes.c_int16, ctypes.POINTER(ctypes.c_uint8), ctypes.c_char_p]
    so.protect_reading.argtypes = [ctypes.c_uint8, ctypes.c_int16]
    so.protect_text.restype = ctypes.c_char_p
    so.protect_cell_max_mv.restype = ctypes.c_uint16
    return so


def sealed(pairs, version=1):
    block = bytearray([version])
    for zero, full in pairs:
        block += zero.to_bytes(2, "little") + full.to_bytes(2, "little")
    check = 0
    for b in block:
        check ^= b
    return bytes(block + bytes([check]))


def nominal(lib):
    lib.cal_use(bytes(BLOCK))                       # not a calibration: the nominal one is used
    block = ctypes.create_string_buffer(BLOCK)
    lib.cal_block(block)
    return block.raw


def test_the_nominal_calibration_is_cheali_s_default_points(lib):
    block = nominal(lib)
    assert lib.cal_block_valid(block) == 1 and block[0] == 1
    # targets/imaxB6-original/defaultCalibration.cpp: Vout {55102, 25141 mV}, Ismps {775, 50} {11080, 1000 mA},
    # Idischarge {2017, 50} {11971, 300 mA}, Vb1 {55048, 4187 mV}, Textern {5884, 22.80 C}
    assert abs(lib.cal_value(VOUT, 55102) - 25141) <= 1
    assert abs(lib.cal_value(ISMPS, 775) - 50) <= 1 and abs(lib.cal_value(ISMPS, 11080) - 1000) <= 1
    assert abs(lib.cal_value(IDIS, 2017) - 50) <= 1 and abs(lib.cal_value(IDIS, 11971) - 300) <= 1
    assert abs(lib.cal_value(VB1, 55048) - 4187) <= 1 and abs(lib.cal_value(TEXTERN, 5884) - 2280) <= 1
    for k, value in ((VOUT, 12600), (ISMPS, 2000), (VB3, 4200), (VIN, 11000)):
        assert abs(lib.cal_value(k, lib.cal_adc16(k, value)) - value) <= 1


def test_a_calibration_block_is_used_only_whole(lib):
    pairs = [(0, 30000), (0, 30826), (26, 1646), (233, 6042), (0, 19154), (0, 5022), (0, 4985), (0, 9761),
             (0, 4899), (0, 5016), (0, 4993), (0, 4924), (0, 25395)]      # nominal, Vout+ 0.3 % off
    good = sealed(pairs)
    assert lib.cal_use(good) == 1 and lib.cal_value(VOUT, 32768) == 15000
    torn = bytearray(good)
    torn[5] ^= 0x40                                 # a byte a power cut left half written
    for bad in (bytes(torn), sealed(pairs, version=2), sealed(pairs[:12] + [(0, 0)]),
                b"\xff" * BLOCK):
        assert lib.cal_block_valid(bad) == 0
        assert lib.cal_use(bad) == 0                # falls back to the nominal calibration
        assert abs(lib.cal_value(VOUT, 55102) - 25141) <= 1


def test_the_ceiling_per_cell_is_the_spec_s_absolute_maximum_for_every_chemistry(lib):
    for name, code in AKK.items():
        path = ROOT / "resources" / "chemistries" / f"{name}.toml"
        if path.exists():
            max_v = tomllib.loads(path.read_text())["limits"]["max_v"]
            assert lib.protect_cell_max_mv(code) == round(max_v * 1000), name
    # the firmware's decisions where the spec gives none (docs/firmware.md)
    assert [lib.protect_cell_max_mv(AKK[n]) for n in ("LiS", "Undef", "New")] == [2800, 4350, 4350]


def feed(lib, readings, times=1):
    trip = 0
    for _ in range(times):
        for k, value in readings.items():
            trip = lib.protect_reading(k, value) or trip
    return trip


def pack(lib, cells_mv, vout=None, vin=12000, vminus=0, probe=2500):
    """A pack on the output and its balance lead: taps 1, 2 to ground, cells 3..6 alone."""
    taps = {VB0: 0, VB1: 0, VB2: 0, VB3: 0, VB4: 0, VB5: 0, VB6: 0}
    if cells_mv:
        taps[VB1] = cells_mv[0]
    if len(cells_mv) > 1:
        taps[VB2] = cells_mv[0] + cells_mv[1]
    for k, mv in enumerate(cells_mv[2:]):
        taps[VB3 + k] = mv
    return {VOUT: sum(cells_mv) if vout is None else vout, VOUT_MINUS: vminus, VIN: vin, TEXTERN: probe,
            ISMPS: 0, IDIS: 0, **taps}


def arm(lib, akk, cells, sentence=None):
    """protect_arm's answer (its text, its trip); the sentence the PC would get into `sentence` when given."""
    trip = ctypes.c_uint8()
    why = lib.protect_arm(AKK[akk], cells, ctypes.byref(trip), sentence)
    return (why.decode() if why else None), trip.value


def text(lib, trip):
    return lib.protect_text(trip).decode()


@pytest.mark.parametrize("readings, cells, why", [
    (dict(cells_mv=[3800] * 3, vout=0, vminus=3000), 3, "battery reversed"),
    (dict(cells_mv=[], vout=100), 3, "no battery"),
    (dict(cells_mv=[3800] * 3, vin=10500), 3, "input below 11V"),
    (dict(cells_mv=[3800] * 3), 4, "balance lead 3 cells"),
    (dict(cells_mv=[3800, 3800, 4320]), 3, "cell 3 over max"),
    (dict(cells_mv=[], vout=13500), 3, "pack over max"),
])
def test_a_start_the_inputs_forbid_is_refused_with_its_reason(lib, readings, cells, why):
    lib.protect_disarm()
    feed(lib, pack(lib, **readings))
    assert arm(lib, "LiPo", cells)[0] == why


def test_a_limit_trips_after_four_readings_in_a_row_not_on_one(lib):
    lib.protect_disarm()
    ok = pack(lib, [3900] * 3)
    feed(lib, ok)
    assert arm(lib, "LiPo", 3) == (None, 0)
    assert feed(lib, {ISMPS: 5300}) == 0 and feed(lib, {ISMPS: 2000}) == 0     # one noisy reading
    for n in range(3):
        assert feed(lib, {ISMPS: 5300}) == 0
    assert text(lib, feed(lib, {ISMPS: 5300})) == "over current"
    assert text(lib, feed(lib, ok)) == "over current"                          # the first trip stays


@pytest.mark.parametrize("akk, cells, reading, times, why", [
    ("LiPo", 3, dict(cells_mv=[4000, 4000, 4350]), 4, "cell 3 over max"),       # the fault's 4.35 V tap
    ("LiFe", 3, dict(cells_mv=[3400, 3660, 3400]), 4, "cell 2 over max"),
    ("NiMh", 8, dict(cells_mv=[], vout=8 * 1810), 4, "pack over max"),
    ("Pb", 6, dict(cells_mv=[], vout=6 * 2510), 4, "pack over max"),
    ("LiPo", 3, dict(cells_mv=[3900] * 3, vout=0), 16, "battery disconnected"),
    ("LiPo", 3, dict(cells_mv=[3900] * 3, vout=13000), 16, "battery disconnected"),  # main lead off: V rises
    ("LiPo", 3, dict(cells_mv=[3900, 3900, 0]), 4, "balance lead 2 cells"),
    ("LiPo", 3, dict(cells_mv=[3900] * 3, vout=0, vminus=11000), 4, "battery reversed"),
    ("LiPo", 3, dict(cells_mv=[3900] * 3, vin=10000), 4, "input below 11V"),
    ("LiPo", 3, dict(cells_mv=[3900] * 3, probe=6100), 4, "probe over 60C"),
    ("LiPo", 3, dict(cells_mv=[3900] * 3, probe=0), 4, "probe open"),
])
def test_each_limit_ends_the_run_with_its_reason(lib, akk, cells, reading, times, why):
    lib.protect_disarm()
    li_start = [3300 if akk == "LiFe" else 3900] * 3
    start = pack(lib, li_start) if akk.startswith("Li") else pack(lib, [], vout=cells * 1200)
    feed(lib, start)
    assert arm(lib, akk, cells) == (None, 0)
    assert text(lib, feed(lib, pack(lib, **reading), times)) == why


def test_below_the_limits_nothing_trips_and_disarming_clears_a_trip(lib):
    lib.protect_disarm()
    feed(lib, pack(lib, [4150, 4190, 4200]))
    assert arm(lib, "LiPo", 3) == (None, 0)
    assert feed(lib, {**pack(lib, [4150, 4190, 4290]), ISMPS: 5000, IDIS: 0, TEXTERN: 5900}, 20) == 0
    feed(lib, {ISMPS: 6000}, 4)
    lib.protect_disarm()
    assert feed(lib, pack(lib, [3900] * 3), 4) == 0


def test_without_a_probe_at_the_start_its_input_is_not_judged(lib):
    lib.protect_disarm()
    feed(lib, pack(lib, [3900] * 3, probe=0))
    assert arm(lib, "LiPo", 3) == (None, 0)
    assert feed(lib, pack(lib, [3900] * 3, probe=0), 10) == 0


def armed(lib, akk="LiPo", cells_mv=(3900, 3900, 3900), **start):
    """Limits armed for a pack of `cells_mv` on the output and its balance lead."""
    lib.protect_disarm()
    feed(lib, pack(lib, list(cells_mv), **start))
    assert arm(lib, akk, len(cells_mv)) == (None, 0)


FULL = {VB1: 4300, VB2: 8600, VB3: 4300}        # a 3S LiPo lead with every cell at its ceiling


# Each limit exactly at its threshold holds, one unit (1 mV, 1 mA, 0.01 degC) past it trips after its readings
# in a row, and one reading fewer does not: a boundary moved by one, a threshold scaled or a debounce changed is
# seen (tools/mutate_firmware.py's comparison and constant mutants).
@pytest.mark.parametrize("at, past, times, why", [
    # the currents as the ADC reads them: two charge readings between two discharge ones (adc.c)
    ({ISMPS: 5250, IDIS: 0}, {ISMPS: 5251, IDIS: 0}, 4, "over current"),
    ({ISMPS: 0, IDIS: 1050}, {ISMPS: 0, IDIS: 1051}, 4, "over current"),   # a discharge over-current
    ({VIN: 11000}, {VIN: 10999}, 4, "input below 11V"),
    ({VOUT_MINUS: 500}, {VOUT_MINUS: 501}, 4, "battery reversed"),
    ({TEXTERN: 6000}, {TEXTERN: 6001}, 4, "probe over 60C"),
    ({TEXTERN: 100}, {TEXTERN: 99}, 4, "probe open"),
    ({**FULL, VOUT: 3 * 4350}, {**FULL, VOUT: 3 * 4350 + 1}, 4, "pack over max"),
    ({VB3: 4300}, {VB3: 4301}, 4, "cell 3 over max"),                      # a cell exactly at the ceiling
    ({VB1: 4300, VB2: 8200}, {VB1: 4301, VB2: 8201}, 4, "cell 1 over max"),
    ({VB2: 3900 + 4300}, {VB2: 3900 + 4301}, 4, "cell 2 over max"),
    ({VOUT: 11700 + 1000}, {VOUT: 11700 + 1001}, 3, "battery disconnected"),    # Vout above the taps' sum
    ({VOUT: 11700 - 1000}, {VOUT: 11700 - 1001}, 3, "battery disconnected"),    # the taps above Vout
    # a quarter of the 3S LiPo's 13.05 V ceiling (LOST_FRACTION), the taps agreeing with it
    ({VOUT: 3262, VB1: 1087, VB2: 2174, VB3: 1088}, {VOUT: 3261, VB1: 1087, VB2: 2174, VB3: 1088}, 3,
     "battery disconnected"),
])
def test_a_limit_holds_at_its_threshold_and_trips_one_unit_past_it(lib, at, past, times, why):
    armed(lib)
    assert feed(lib, at, 40) == 0
    assert feed(lib, past, times - 1) == 0
    assert text(lib, feed(lib, past)) == why


@pytest.mark.parametrize("reading, why", [(12000, "probe over 60C"), (12001, "probe open")])
def test_a_probe_reading_above_120_c_is_an_open_probe_not_a_hot_pack(lib, reading, why):
    armed(lib)
    assert text(lib, feed(lib, {TEXTERN: reading}, 4)) == why


@pytest.mark.parametrize("k", range(6))
def test_every_cell_of_a_6s_pack_is_checked_under_its_own_name(lib, k):
    armed(lib, cells_mv=[3900] * 6)
    cells = [3900] * 6
    cells[k] = 4301
    assert text(lib, feed(lib, pack(lib, cells, vout=6 * 3900), 4)) == f"cell {k + 1} over max"


def test_the_lead_check_holds_without_a_lead_and_names_a_lead_that_comes_off(lib):
    armed(lib, "NiMh", [], vout=8 * 1200)
    assert feed(lib, pack(lib, [], vout=8 * 1200), 40) == 0                # no lead, no cells: nothing to compare
    armed(lib, cells_mv=[3900] * 4)
    assert text(lib, feed(lib, pack(lib, [3900] * 3), 4)) == "balance lead 3 cells"


def test_the_lead_s_cell_count_is_judged_once_a_scan_of_its_taps(lib):
    # at the scan's last tap (Vb6), when every tap is fresh: a count judged at each tap would see a lead half
    # read, and four taps of one scan would pass for four scans in a row
    armed(lib, cells_mv=[3900] * 4)
    two = pack(lib, [3900, 3900])                                         # a 2S pack where a 4S one was
    assert list(two)[-1] == VB6                                           # the ADC's order: Vb6 ends a scan
    assert feed(lib, two, 3) == 0
    assert text(lib, feed(lib, two)) == "balance lead 2 cells"


@pytest.mark.parametrize("start, cells, why", [
    (dict(cells_mv=[3900] * 3), 4, "balance lead 3 cells"),                 # SERIES above the balance count
    (dict(cells_mv=[3900] * 3), 2, "balance lead 3 cells"),                 # ... and below it
    (dict(cells_mv=[3900, 3900, 4301]), 3, "cell 3 over max"),
    (dict(cells_mv=[], vout=3 * 4350 + 1), 3, "pack over max"),
    (dict(cells_mv=[3900] * 3, vin=10999), 3, "input below 11V"),
    (dict(cells_mv=[], vout=499), 3, "no battery"),
    (dict(cells_mv=[3900] * 3, vminus=501), 3, "battery reversed"),
])
def test_a_start_one_unit_past_a_limit_is_refused(lib, start, cells, why):
    lib.protect_disarm()
    feed(lib, pack(lib, **start))
    assert arm(lib, "LiPo", cells)[0] == why


@pytest.mark.parametrize("start", [
    dict(cells_mv=[3900, 3900, 4300]), dict(cells_mv=[], vout=3 * 4350), dict(cells_mv=[3900] * 3, vin=11000),
    dict(cells_mv=[], vout=500), dict(cells_mv=[3900] * 3, vminus=500),
])
def test_a_start_exactly_at_a_limit_is_allowed(lib, start):
    lib.protect_disarm()
    feed(lib, pack(lib, **start))
    assert arm(lib, "LiPo", 3) == (None, 0)


def sink_steps(lib, loss_mw, steps):
    """The heat-sink estimate after `steps` 100 ms steps at `loss_mw`; the step a trip came at (None without)."""
    lib.protect_sink_step.argtypes = [ctypes.c_int32]
    trip = ctypes.c_uint8.in_dll(lib, "protect_trip")
    for n in range(steps):
        lib.protect_sink_step(loss_mw)
        if trip.value:
            return n + 1
    return None


STAGE_OFF, STAGE_CHARGE, STAGE_DISCHARGE = range(3)          # stage.h


def loss_mw(lib, mode, v_mv, i_ma):
    lib.protect_loss_mw.restype = ctypes.c_int32
    lib.protect_loss_mw.argtypes = [ctypes.c_uint8, ctypes.c_int16, ctypes.c_int16]
    return lib.protect_loss_mw(mode, v_mv, i_ma)


def test_the_stage_loses_a_tenth_of_a_charge_all_of_a_discharge_and_nothing_off(lib):
    # 12.6 V x 5 A = 63 W: the converter's 10 % of a charge, all of it in the discharge load
    assert loss_mw(lib, STAGE_CHARGE, 12600, 5000) == 6300
    assert loss_mw(lib, STAGE_DISCHARGE, 12600, 5000) == 63000
    assert loss_mw(lib, STAGE_OFF, 12600, 5000) == 0


def test_the_heat_sink_estimate_trips_from_the_stages_own_losses(lib):
    # The stock B6 has no heat-sink sensor (cheali: Tintern {0,0}): this estimate is the protection, and a sink
    # heated from outside is not seen (docs/firmware.md, Heat sink).
    sink = ctypes.c_int32.in_dll(lib, "protect_sink_sum")                  # the estimate x 600 steps
    armed(lib)
    sink.value = 2500 * 600
    # the B6's largest losses within its clamps, a 50 W charge (10 V x 5 A) or a 5 W discharge (5 V x 1 A):
    # 25 + 2 x 5 = 35 degC, no trip
    for mode, v_mv, i_ma in ((STAGE_CHARGE, 10000, 5000), (STAGE_DISCHARGE, 5000, 1000)):
        assert sink_steps(lib, loss_mw(lib, mode, v_mv, i_ma), 6000) is None and sink.value // 600 == 3500
    # a discharge dissipating 40 W (20 V x 2 A, were the 5 W clamp to fail): from 35 towards 105 degC with 60 s
    # of time constant, over 80 degC after 60 ln(70/25) = 62 s
    n = sink_steps(lib, loss_mw(lib, STAGE_DISCHARGE, 20000, 2000), 1200)
    assert n is not None and 590 <= n <= 650, n
    assert text(lib, ctypes.c_uint8.in_dll(lib, "protect_trip").value) == "heat sink over 80C"
    sink.value = 8100 * 600                    # cools back to the room's 25 degC with no losses
    lib.protect_disarm()
    assert sink_steps(lib, loss_mw(lib, STAGE_OFF, 20000, 2000), 6000) is None and sink.value // 600 == 2500


def starved(lib, run, i_ma, set_ma=4000, boosting=0, v_mv=12600, vin_mv=12000, times=1):
    """protect_starved's answer to `times` readings of `i_ma` at the top duty (its trip's text, "" for none)."""
    lib.protect_starved.argtypes = [ctypes.POINTER(ctypes.c_uint16), ctypes.c_int16, ctypes.c_int16, ctypes.c_uint8,
                                    ctypes.c_int16, ctypes.c_int16]
    trip = 0
    for _ in range(times):
        trip = lib.protect_starved(ctypes.byref(run), i_ma, set_ma, boosting, v_mv, vin_mv)
    return text(lib, trip)


def test_the_top_duty_is_starved_under_a_quarter_of_its_current_not_at_it(lib):
    run = ctypes.c_uint16(0)
    assert starved(lib, run, 999) == "" and run.value == 1          # 4 A set: under 1 A is starved
    assert starved(lib, run, 1000) == "" and run.value == 0         # exactly a quarter: the row starts again
    assert starved(lib, run, 999, times=399) == "" and run.value == 399
    assert starved(lib, run, 1000) == "" and run.value == 0         # a reading at a quarter after 399 holds it
    assert starved(lib, run, 999, times=400) == "battery disconnected"


def test_a_starved_duty_trips_on_its_400th_reading_in_a_row(lib):
    run = ctypes.c_uint16(0)
    assert starved(lib, run, 0, times=399) == "" and run.value == 399
    assert starved(lib, run, 0) == "battery disconnected" and run.value == 400


@pytest.mark.parametrize("boosting, v_mv, why", [
    (1, 23500, "battery disconnected"),            # 2 x 12 V - 0.5 V exactly: within the boost's reach
    (1, 23501, "pack above twice the input"),      # 1 mV above it
    (0, 23501, "battery disconnected"),            # the buck reaches no higher than its input: a lost pack
    (0, 27000, "battery disconnected"),
])
def test_a_starved_boost_names_a_pack_out_of_its_reach_only_above_twice_the_input(lib, boosting, v_mv, why):
    run = ctypes.c_uint16(399)
    assert starved(lib, run, 0, boosting=boosting, v_mv=v_mv, vin_mv=12000) == why


def loop_slots(lib, loop_ran, times):
    """protect_loop_slot's answer to `times` ADC slots; the slot it first returned 1 at (None without)."""
    lib.protect_loop_slot.argtypes = [ctypes.c_uint8]
    for n in range(times):
        if lib.protect_loop_slot(loop_ran):
            return n + 1
    return None


def test_the_main_loop_hangs_after_160_adc_slots_without_it_not_159(lib):
    armed(lib)
    trip = ctypes.c_uint8.in_dll(lib, "protect_trip")
    assert loop_slots(lib, 1, 1) is None                 # the loop ran: the count starts from 0
    assert loop_slots(lib, 0, 159) is None and trip.value == 0
    assert loop_slots(lib, 1, 1) is None                 # a slot with the loop starts it again
    assert loop_slots(lib, 0, 159) is None and trip.value == 0
    assert loop_slots(lib, 0, 1) == 1 and text(lib, trip.value) == "main loop hang"
    assert loop_slots(lib, 0, 1) == 1                    # hung it stays: the stage is held off each slot
    assert loop_slots(lib, 1, 1) is None
    lib.protect_disarm()


def test_an_unknown_chemistry_gets_the_highest_ceiling_and_only_li_types_are_li(lib):
    assert [lib.protect_cell_max_mv(k) for k in (8, 9, 255)] == [4350, 4350, 4350]
    assert [lib.protect_is_li(k) for k in range(10)] == [0, 0, 0, 0, 1, 1, 1, 1, 0, 0]


@pytest.mark.parametrize("tap_mv, cells", [(1000, 2), (1001, 3)])
def test_a_tap_carries_a_cell_above_1_v(lib, tap_mv, cells):
    lib.protect_disarm()
    feed(lib, pack(lib, [3900, 3900, tap_mv], vout=7800 + tap_mv))
    assert lib.protect_balance_cells() == cells


def test_all_six_taps_count_and_a_li_start_without_series_takes_the_lead_s_count(lib):
    lib.protect_disarm()
    feed(lib, pack(lib, [3900] * 6))
    assert lib.protect_balance_cells() == 6
    assert arm(lib, "LiPo", 0) == (None, 0)
    assert text(lib, feed(lib, pack(lib, [3900] * 5 + [4301], vout=6 * 3900), 4)) == "cell 6 over max"


@pytest.mark.parametrize("fault, why", [
    ({IDIS: 1200}, "over current"), ({VIN: 10000}, "input below 11V"), ({TEXTERN: 6500}, "probe over 60C"),
    ({VB3: 4400}, "battery disconnected"),
])
def test_a_trip_while_the_pack_reads_lost_keeps_its_own_name_unless_the_loss_explains_it(lib, fault, why):
    armed(lib)
    feed(lib, fault, 2)                     # the fault's row starts first: the lost pack trips after 3 readings
    assert text(lib, feed(lib, {**pack(lib, [3900] * 3, vout=0), **fault}, 2)) == why


@pytest.mark.parametrize("vminus, why, times", [(500, "battery disconnected", 3), (501, "battery reversed", 4)])
def test_vout_minus_at_0_5_v_is_a_lost_pack_and_above_it_a_reversed_one(lib, vminus, why, times):
    armed(lib)
    lost = pack(lib, [3900] * 3, vout=0, vminus=vminus)
    assert feed(lib, lost, times - 1) == 0
    assert text(lib, feed(lib, lost)) == why


def test_cells_1_and_2_are_checked_when_a_tap_below_them_moves(lib):
    armed(lib, cells_mv=[3900] * 3)
    feed(lib, {VB0: 300, VB1: 4600})                       # cell 1: 4.3 V on a lead whose minus reads 0.3 V
    assert text(lib, feed(lib, {VB0: 0}, 4)) == "cell 1 over max"
    armed(lib, cells_mv=[3900] * 3)
    feed(lib, {VB1: 4300, VB2: 8600})                      # cell 2: 4.3 V
    assert text(lib, feed(lib, {VB1: 4000}, 4)) == "cell 2 over max"


@pytest.mark.parametrize("probe, judged", [(199, False), (200, True), (12000, True), (12001, False)])
def test_a_probe_is_judged_when_it_read_2_to_120_c_at_the_start(lib, probe, judged):
    armed(lib, probe=probe)
    assert bool(feed(lib, {TEXTERN: 0}, 4)) == judged


@pytest.mark.parametrize("c100, loss_mw, trips", [(8000, 27500, False), (8001, 27505, True)])
def test_the_heat_sink_estimate_trips_above_80_c_not_at_it(lib, c100, loss_mw, trips):
    armed(lib)
    ctypes.c_int32.in_dll(lib, "protect_sink_sum").value = c100 * 600     # held there by these losses
    assert (sink_steps(lib, loss_mw, 10) is not None) == trips
    lib.protect_disarm()
    ctypes.c_int32.in_dll(lib, "protect_sink_sum").value = 2500 * 600


def test_a_reversed_pack_trips_on_its_current_first_and_is_named_by_a_vout_minus_reading_after_it(lib):
    armed(lib)
    lib.protect_settled.restype = ctypes.c_uint8
    assert text(lib, feed(lib, {ISMPS: 0, IDIS: 6000}, 4)) == "over current"     # the short, before Vout- is read
    assert not lib.protect_settled()
    feed(lib, {VOUT_MINUS: 11000})
    assert lib.protect_settled() and text(lib, ctypes.c_uint8.in_dll(lib, "protect_trip").value) == "battery reversed"
    armed(lib)
    feed(lib, {ISMPS: 0, IDIS: 6000}, 4)
    feed(lib, {VOUT_MINUS: 500}, 3)                                               # not reversed: its own name ...
    assert not lib.protect_settled()
    feed(lib, {VOUT_MINUS: 500})                                                  # ... once 4 readings said so
    assert lib.protect_settled() and text(lib, ctypes.c_uint8.in_dll(lib, "protect_trip").value) == "over current"


def test_a_tap_beyond_the_run_s_cells_is_a_lead_fault_not_a_cell_over_max(lib):
    armed(lib)
    assert text(lib, feed(lib, pack(lib, [3900, 3900, 3900, 4400], vout=3 * 3900), 4)) == "balance lead 4 cells"


def test_a_lost_pack_that_vout_minus_then_shows_reversed_is_named_reversed(lib):
    armed(lib)
    assert text(lib, feed(lib, {VOUT: 0}, 16)) == "battery disconnected"         # lost: off at once ...
    lib.protect_settled.restype = ctypes.c_uint8
    assert not lib.protect_settled()
    feed(lib, {VOUT_MINUS: 11000})                                                # ... then Vout- shows it reversed
    assert lib.protect_settled() and text(lib, ctypes.c_uint8.in_dll(lib, "protect_trip").value) == "battery reversed"


def test_a_start_sees_the_cells_as_the_lead_s_minus_tap_last_read_them(lib):
    lib.protect_disarm()
    feed(lib, {**pack(lib, [3900] * 3), VB0: 300, VB1: 4600})               # cell 1: 4.3 V
    feed(lib, {VB0: 0})                                                      # cell 1: 4.6 V
    assert arm(lib, "LiPo", 3)[0] == "cell 1 over max"


def test_a_trip_keeps_its_name_when_vout_minus_shows_no_reversed_pack(lib):
    armed(lib)
    lib.protect_settled.restype = ctypes.c_uint8
    assert text(lib, feed(lib, {VB3: 4400}, 4)) == "cell 3 over max" and not lib.protect_settled()
    feed(lib, {VOUT_MINUS: 0}, 4)
    assert lib.protect_settled() and text(lib, ctypes.c_uint8.in_dll(lib, "protect_trip").value) == "cell 3 over max"


def test_a_reading_rounds_to_the_nearest_unit_on_both_sides_of_zero(lib):
    nominal(lib)                                    # Vout: zero 0, 29 902 mV full scale; I dis: zero 26
    assert [lib.cal_value(VOUT, d) for d in (1, 10, 12)] == [0, 5, 5]          # 0.46, 4.56, 5.48 mV
    assert [lib.cal_value(IDIS, 26 - d) for d in (19, 20)] == [0, -1]          # -0.48, -0.50 mA


def test_a_trip_number_past_the_table_reads_as_no_trip(lib):
    # TRIPS (31) and above name no trip: the text is no trip's own row, never the row past the table's end
    assert lib.protect_text(30).decode() == "pack above twice the input"
    row = ctypes.CFUNCTYPE(ctypes.c_void_p, ctypes.c_uint8)(("protect_text", lib))
    assert row(31) == row(255) == row(0)


def test_a_lone_nickel_cell_is_lost_below_half_a_volt(lib):
    # a 1S NiMH pack's quarter of its ceiling (437 mV) is below the 500 mV of "no battery": that threshold decides
    armed(lib, "NiMh", (1300,))
    assert feed(lib, {VOUT: 500}, 40) == 0
    assert feed(lib, {VOUT: 499}, 2) == 0
    assert text(lib, feed(lib, {VOUT: 499})) == "battery disconnected"
