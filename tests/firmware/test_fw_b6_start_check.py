"""Issue 31, sections 1 and 3, in the B6's protections built for the PC (protect.c through ctypes): the balance lead
as evidence for every chemistry, the cell count counted from the rest voltage, the pack the boost cannot reach, the
reason of a trip refined once the output is off, and the run's time and capacity limits. Each comparison is held
on both sides of its limit and each limit constant by its value, so a mutant of either fails here."""
import ctypes
import threading

import pytest

from helpers import compiled
from test_fw_b6_protect import AKK, IDIS, ISMPS, VIN, VOUT, VOUT_MINUS, arm, feed, lib, pack, text  # noqa: F401 - lib: a fixture

TRIP_DISCONNECTED = 11


@pytest.fixture
def b6(lib):  # noqa: F811 - the fixture imported above
    lib.protect_cells_at_rest.restype = ctypes.c_int16
    lib.protect_cells_at_rest.argtypes = [ctypes.c_uint8, ctypes.c_int16]
    lib.protect_time_limit_min.restype = ctypes.c_uint16
    lib.protect_time_limit_min.argtypes = [ctypes.c_char_p]
    lib.protect_capacity_limit_uah.restype = ctypes.c_uint32
    lib.protect_capacity_limit_uah.argtypes = [ctypes.c_int32]
    lib.protect_run_limits.restype = ctypes.c_uint8
    lib.protect_run_limits.argtypes = [ctypes.c_uint32, ctypes.c_uint16, ctypes.c_uint32, ctypes.c_uint32]
    lib.protect_disarm()
    return lib


def refusal(lib, akk, cells, **readings):  # noqa: F811 - the fixture imported above, passed in
    """START on these readings: (the display's text, the PC's sentence or the text when there is none)."""
    lib.protect_disarm()
    feed(lib, pack(lib, **readings))
    sentence = ctypes.create_string_buffer(100)
    why, _ = arm(lib, akk, cells, sentence)
    return why, sentence.value.decode() or why


@pytest.mark.parametrize("akk", ["NiMh", "NiCd", "Pb"])
def test_a_balance_lead_showing_lithium_cells_refuses_a_nickel_or_lead_macro_with_a_sentence(b6, akk):
    why, sentence = refusal(b6, akk, 0, cells_mv=[4120, 4140, 4130])
    assert why == "lithium pack"
    assert sentence == f"the balance lead shows 3 cells up to 4.14 V: a lithium pack; this macro is for {akk}"
    assert refusal(b6, akk, 9, cells_mv=[4120, 4140, 4130])[0] == "lithium pack"    # a count given: the same


def test_lithium_is_a_cell_above_2_50_v_pbs_maximum_below_it_the_cell_is_over_the_macros_maximum(b6):
    assert refusal(b6, "NiMh", 0, cells_mv=[1300, 2501])[0] == "lithium pack"
    assert refusal(b6, "NiMh", 0, cells_mv=[1300, 2500]) == (
        "cell 2 over max", "the balance lead shows 2 cells up to 2.50 V: over NiMh's 1.75 V a cell")
    # a lithium macro on cells above its own maximum: over it, not "lithium"
    assert refusal(b6, "LiFe", 0, cells_mv=[4140] * 3) == (
        "cell 1 over max", "the balance lead shows 3 cells up to 4.14 V: over LiFe's 3.65 V a cell")
    # the sentence for each cell of the lead, the sixth too
    assert refusal(b6, "LiFe", 0, cells_mv=[3300] * 5 + [3700]) == (
        "cell 6 over max", "the balance lead shows 6 cells up to 3.70 V: over LiFe's 3.65 V a cell")


@pytest.mark.parametrize("akk, ceiling_mv", [("NiMh", 1750), ("NiCd", 1750), ("Pb", 2450), ("LiFe", 3650),
                                             ("LiPo", 4300), ("LiIon", 4200)])
def test_a_cell_on_the_lead_at_its_ceiling_starts_and_runs_and_one_mv_above_it_trips(b6, akk, ceiling_mv):
    low = ceiling_mv - 300
    assert refusal(b6, akk, 0, cells_mv=[low, ceiling_mv + 1, low])[0] == "cell 2 over max"
    assert refusal(b6, akk, 0, cells_mv=[low, ceiling_mv, low]) == (None, None)   # armed, 3 cells from the lead
    assert feed(b6, pack(b6, [low, ceiling_mv, low]), 8) == 0
    assert feed(b6, pack(b6, [low, low, ceiling_mv + 1]), 3) == 0                  # 3 readings: noise
    assert text(b6, feed(b6, pack(b6, [low, low, ceiling_mv + 1]))) == "cell 3 over max"


def test_every_chemistry_checks_the_lead_s_count_and_a_lead_pulled_mid_run(b6):
    assert refusal(b6, "NiMh", 4, cells_mv=[1300] * 3)[0] == "balance lead 3 cells"
    assert refusal(b6, "NiMh", 3, cells_mv=[1300] * 3) == (None, None)
    assert text(b6, feed(b6, pack(b6, [1300, 1300]), 4)) == "balance lead 2 cells"


@pytest.mark.parametrize("akk, mv, cells", [
    ("NiCd", 12600, 9), ("NiCd", 1000, 1), ("NiCd", 1500, 1), ("NiCd", 999, 0), ("NiCd", 1501, 0),
    ("NiMh", 12600, 9), ("NiMh", 1000, 1), ("NiMh", 1500, 1), ("NiMh", 22500, 15),
    ("NiMh", 999, 0), ("NiMh", 1501, 0), ("NiMh", 1999, 0), ("NiMh", 2000, 2), ("NiMh", 22501, 0),
    ("Pb", 12600, 6), ("Pb", 1800, 1), ("Pb", 2300, 1), ("Pb", 1799, 0), ("Pb", 2301, 0), ("Pb", 23000, 10),
    ("Pb", 23001, 0),
    ("LiPo", 12600, 3), ("LiPo", 3000, 1), ("LiPo", 4300, 1), ("LiPo", 2999, 0), ("LiPo", 4301, 0),
    ("LiPo", 25800, 6), ("LiPo", 25801, 0),
    ("LiIon", 2500, 1), ("LiIon", 4200, 1), ("LiIon", 2499, 0), ("LiIon", 4201, 0),
    ("LiFe", 2500, 1), ("LiFe", 3650, 1), ("LiFe", 2499, 0), ("LiFe", 3651, 0), ("LiFe", 25550, 7),
    ("LiS", 1700, 1), ("LiS", 2750, 1), ("LiS", 1699, 0), ("LiS", 2751, 0),
    ("Undef", 12600, 0), ("New", 12600, 0),
])
def test_the_cell_count_at_rest_is_the_fewest_cells_whose_window_holds_the_voltage(b6, akk, mv, cells):
    assert b6.protect_cells_at_rest(AKK[akk], mv) == cells


def test_without_a_count_the_pack_ceiling_follows_the_count_at_rest_never_27_v(b6):
    assert refusal(b6, "NiMh", 0, cells_mv=[], vout=12600) == (None, None)           # 9 cells: 16.20 V
    assert feed(b6, pack(b6, [], vout=16200), 8) == 0
    assert text(b6, feed(b6, pack(b6, [], vout=16201), 4)) == "pack over max"


def test_a_voltage_that_fits_no_whole_number_of_cells_refuses_to_start(b6):
    assert refusal(b6, "NiMh", 0, cells_mv=[], vout=1700) == (
        "no cell count", "no cell count: 1.70 V fits no whole number of NiMh cells (1.00..1.50 V each at rest)")
    assert refusal(b6, "Undef", 0, cells_mv=[], vout=12600) == (
        "no cell count", "no cell count: Undef cells cannot be counted from the voltage")
    assert refusal(b6, "NiMh", 2, cells_mv=[], vout=1700) == (None, None)             # a count given: it starts


def test_a_pack_over_the_ceiling_of_its_cells_says_both_voltages(b6):
    assert refusal(b6, "NiMh", 3, cells_mv=[], vout=5401) == (
        "pack over max", "the pack reads 5.40 V: over 5.40 V, the ceiling of 3 NiMh cells")
    assert refusal(b6, "NiMh", 3, cells_mv=[], vout=5400) == (None, None)


def test_a_pack_above_twice_the_input_less_0_5_v_is_out_of_the_stage_s_reach(b6):
    cells = [4100] * 5 + [3601]                       # 24.101 V on the lead, 12 V in
    assert refusal(b6, "LiPo", 6, cells_mv=cells, vout=23501, vin=12000) == (
        "pack above twice the input", "the stage cannot reach the pack's 23.50 V from 12.00 V in: at most twice the "
                                      "input")
    assert refusal(b6, "LiPo", 6, cells_mv=cells, vout=23500, vin=12000)[0] is None


def test_a_lost_pack_is_off_after_3_readings_and_its_reason_waits_4_vout_minus_readings_to_be_final(b6):
    assert refusal(b6, "LiPo", 3, cells_mv=[3900] * 3) == (None, None)
    assert feed(b6, {VOUT: 0}, 2) == 0
    assert feed(b6, {VOUT: 0}) == TRIP_DISCONNECTED   # the ADC interrupt switches the stage off on this
    for _ in range(3):
        assert not b6.protect_settled()
        feed(b6, {VOUT_MINUS: 0})
    assert not b6.protect_settled()
    feed(b6, {VOUT_MINUS: 0})
    assert b6.protect_settled() and text(b6, feed(b6, {VOUT_MINUS: 11000})) == "battery disconnected"


def test_a_pack_below_a_quarter_of_its_ceiling_is_lost_after_3_readings(b6):
    assert refusal(b6, "LiPo", 3, cells_mv=[], vout=11700) == (None, None)          # no lead: 13.05 V ceiling
    assert feed(b6, {VOUT: 13050 // 4}, 8) == 0
    assert feed(b6, {VOUT: 13050 // 4 - 1}, 2) == 0
    assert text(b6, feed(b6, {VOUT: 13050 // 4 - 1})) == "battery disconnected"


def test_a_reversed_pack_behind_the_open_switch_names_the_first_trip(b6):
    assert refusal(b6, "LiPo", 3, cells_mv=[3900] * 3) == (None, None)
    assert feed(b6, {ISMPS: 6000}, 4) != 0            # the short: over current first
    feed(b6, {VOUT_MINUS: 0}, 3)
    assert text(b6, feed(b6, {VOUT_MINUS: 501})) == "battery reversed" and b6.protect_settled()
    assert refusal(b6, "LiPo", 3, cells_mv=[3900] * 3) == (None, None)
    feed(b6, {VOUT: 0, VOUT_MINUS: 500}, 8)           # 0.5 V on Vout- is not reversed
    assert text(b6, feed(b6, {VOUT_MINUS: 500})) == "battery disconnected"


def test_a_reversed_pack_counted_before_its_trip_names_it_even_when_gone_after_it(b6):
    # a limit that trips while Vout- has already shown the pack reversed names it "battery reversed" at once:
    # the readings behind the open switch only refine, and a pack pulled off as it trips shows nothing there
    assert refusal(b6, "LiPo", 3, cells_mv=[3900] * 3) == (None, None)
    feed(b6, {VOUT_MINUS: 11000})                     # one reversed reading: counted, not yet a trip
    assert feed(b6, {ISMPS: 6000}, 3) == 0            # the short's current
    assert text(b6, feed(b6, {ISMPS: 6000})) == "battery reversed"     # over current's 4th reading names it
    feed(b6, {VOUT_MINUS: 0}, 4)                      # the pack off the leads: nothing to refine it with
    assert b6.protect_settled() and text(b6, feed(b6, {VOUT_MINUS: 0})) == "battery reversed"


def record(intro="", *tfs):
    phases = "".join("    FAZE\n      CONSTANT_I=1A\n" + (f"      IF(tf>{tf}) STOP_FAZE\n" if tf else "") +
                     "    END_FAZE\n" for tf in tfs or (None,))
    return compiled(f"MACRO T\n  AKK_TYPE=LiPo {intro}\n  CHARGE_SECTION\n{phases}  END_SECTION\nEND_MACRO\n")


@pytest.mark.parametrize("intro, tfs, minutes", [
    ("", (), 720), ("", ("1h",), 720), ("", ("11h",), 720), ("", ("396001",), 721), ("", ("6h", "5h"), 720),
    ("", ("10h", "8h"), 1140), ("", ("827400",), 1439), ("", ("23h",), 1440), ("", ("23h", "23h"), 1440),
    ("", ("4294967295", "4294967295"), 1440),
    ("IF(tm>11h) STOP_MACRO", (), 720), ("IF(tm>20h) STOP_MACRO", ("2h",), 1260),
    ("IF(tm>13h) STOP_MACRO", ("20h",), 840), ("IF(tm>100h) STOP_MACRO", (), 1440),
])
def test_the_time_limit_is_the_macros_own_bound_and_an_hour_between_12_and_24_h(b6, intro, tfs, minutes):
    # the run's IF(tm>x), else the sum of the phases' IF(tf>x)
    assert b6.protect_time_limit_min(record(intro, *tfs)) == minutes


def test_the_time_limit_reads_the_record_and_nothing_after_it(b6):
    # a record whose check byte (its last) reads as IF(tf>x), with 0xFF bytes lying after the record: neither
    # the check byte nor what follows is an instruction (read as one, the limit would be 24 h)
    rec = next(r for r in (record("", str(tf)) for tf in range(36000, 37000)) if r[r[0] - 1] in (87, 88))
    assert b6.protect_time_limit_min(rec + b"\xff" * 4) == b6.protect_time_limit_min(rec) == 720


def test_the_time_limit_stops_at_a_byte_that_is_no_instruction(b6):
    # a record the core has not validated (zc_op_size 0): the scan ends there instead of standing on it for
    # ever. The call runs beside the test so that a scan that never ends fails it instead of hanging the suite.
    rec = bytearray(record("IF(tm>20h) STOP_MACRO"))
    first = rec[1]
    assert b6.zc_op_size(0xEE) == 0
    rec[first] = 0xEE                                 # no opcode: the IF(tm>20h) after it is never read
    answer = []
    scan = threading.Thread(target=lambda: answer.append(b6.protect_time_limit_min(bytes(rec))), daemon=True)
    scan.start()
    scan.join(60)
    assert answer == [720]


@pytest.mark.parametrize("akk", [9, 12, 17, 18, 255])
def test_a_chemistry_code_past_the_table_has_no_cells_at_rest(b6, akk):
    # the host build traps on an index past the table of rest windows
    assert b6.protect_cells_at_rest(akk, 3800) == 0


def test_pb_float_s_16_h_absorption_and_6_h_float_fit_its_time_limit(b6):
    assert b6.protect_time_limit_min(compiled("Pb-float")) == 23 * 60


@pytest.mark.parametrize("mah, uah", [(0, 10_000_000), (-1, 10_000_000), (2000, 4_000_000), (24_999, 49_998_000),
                                      (25_000, 50_000_000), (25_001, 50_000_000), (65_535, 50_000_000)])
def test_the_capacity_limit_is_twice_the_capacity_and_never_past_50_ah(b6, mah, uah):
    assert b6.protect_capacity_limit_uah(mah) == uah


@pytest.mark.parametrize("minutes", [720, 1440])
def test_a_run_goes_on_at_its_time_limit_and_trips_a_millisecond_past_it(b6, minutes):
    # the main loop's check (board.c slow_limits); 12 h and more of simulated time is no test on the simulated B6
    limit_ms = minutes * 60_000
    assert b6.protect_run_limits(limit_ms, minutes, 0, 1) == 0
    assert text(b6, b6.protect_run_limits(limit_ms + 1, minutes, 0, 1)) == "time limit"
    assert text(b6, b6.protect_run_limits(limit_ms + 1, minutes, 5, 1)) == "time limit"     # the time's first


@pytest.mark.parametrize("uah", [1, 4_000_000, 50_000_000])
def test_a_run_goes_on_at_its_capacity_limit_and_trips_a_microamp_hour_past_it(b6, uah):
    assert b6.protect_run_limits(0, 720, uah, uah) == 0
    assert text(b6, b6.protect_run_limits(0, 720, uah + 1, uah)) == "capacity limit"
