"""The iMAX B6's balancer and its hold (firmware/boards/imaxb6/balance.c) built for the PC and driven through
ctypes: which cells bleed, the cap that holds the highest cell at its ceiling, the held charge's end. Each
constant and comparison has a case on each side of it (docs/firmware.md, Balancer)."""
import ctypes

import pytest

from test_fw_b6_protect import lib as logic  # noqa: F401 - the host build, made once
from tools import HOST, needs

pytestmark = needs(HOST)
AKK = {"Undef": 0, "Pb": 1, "NiCd": 2, "NiMh": 3, "LiPo": 4, "LiIon": 5, "LiS": 6, "LiFe": 7, "New": 8}


@pytest.fixture(scope="module")
def lib(logic):  # noqa: F811 - the fixture imported above
    so = logic
    so.balance_ceiling_mv.restype = ctypes.c_uint16
    so.balance_bleeders.restype = ctypes.c_uint8
    so.balance_bleeders.argtypes = [ctypes.POINTER(ctypes.c_int16)] + [ctypes.c_uint8] * 3
    so.balance_keep.restype = ctypes.c_uint8
    so.balance_keep.argtypes = [ctypes.POINTER(ctypes.c_int16), ctypes.c_uint8, ctypes.c_uint8,
                                ctypes.POINTER(ctypes.c_int16)]
    so.balance_cap.restype = ctypes.c_int16
    so.balance_cap.argtypes = [ctypes.c_int16, ctypes.c_int16, ctypes.c_int16, ctypes.c_int32]
    so.balance_held_end.restype = ctypes.c_uint8
    so.balance_held_end.argtypes = [ctypes.c_int32] * 4 + [ctypes.c_uint8, ctypes.c_int32]
    so.balance_bled_ua.restype = ctypes.c_int32
    so.balance_bled_ua.argtypes = [ctypes.POINTER(ctypes.c_int16), ctypes.c_uint8, ctypes.c_uint8]
    return so


def cells(*mv):
    return (ctypes.c_int16 * 6)(*mv)


def bleeders(lib, mv, bled_before=0, can=0x3F):
    return lib.balance_bleeders(cells(*mv), len(mv), bled_before, can)


def test_the_ceiling_is_the_charge_voltage_per_cell_of_the_simulator_s_b6(lib):
    from zuml_studio.sim.charger_model import load_charger
    table = load_charger("imax_b6").balancer.ceiling_v
    for name, code in AKK.items():
        expected = round(table[name] * 1000) if name in table else 0
        assert lib.balance_ceiling_mv(code) == expected, name
    assert lib.balance_ceiling_mv(9) == 0 and lib.balance_ceiling_mv(255) == 0


def test_a_cell_bleeds_from_8_mv_above_the_lowest_and_from_3_mv_when_it_bled_before(lib):
    assert bleeders(lib, [4000, 4008, 4000]) == 0                  # at 8 mV: not yet
    assert bleeders(lib, [4000, 4009, 4000]) == 0b010
    assert bleeders(lib, [4000, 4003, 4000], bled_before=0b010) == 0
    assert bleeders(lib, [4000, 4004, 4000], bled_before=0b010) == 0b010
    assert bleeders(lib, [4000, 4004, 4000], bled_before=0b100) == 0   # only the cell that bled
    assert bleeders(lib, [4009, 4000]) == 0b01                           # the first cell too
    assert bleeders(lib, [4000, 4000, 4000, 4000, 4000, 4020]) == 0b100000   # the last (6th) cell too


def test_at_most_3_cells_bleed_at_once_the_highest_first(lib):
    assert bleeders(lib, [4000, 4020, 4030, 4000, 4040, 4050]) == 0b110100   # cells 6, 5, 3 (not 2)
    assert bleeders(lib, [4000, 4020, 4030, 4000, 4040]) == 0b10110          # four above: the highest three
    assert bleeders(lib, [4000, 4020, 4030, 4000]) == 0b0110
    assert bleeders(lib, [4000, 4020, 4020, 4000, 4020, 4020]) == 0b010110   # a tie: the first cells


def test_cell_4_bleeds_as_the_others_do(lib):
    # PD0 is cell 4's load on a TX-only B6; board.c leaves it out only while PD0 is a receive wire
    assert bleeders(lib, [4000, 4000, 4000, 4050, 4000, 4000]) == 0b1000
    assert bleeders(lib, [4000, 4010, 4000, 4050, 4000, 4000]) == 0b1010


def test_while_pd0_receives_the_three_bleeders_are_chosen_among_the_other_cells(lib):
    # board.c passes all but cell 4 while PD0 is the receive line: the window still bleeds 3 cells
    no_4 = 0x3F & ~0b1000
    assert bleeders(lib, [4000, 4020, 4030, 4060, 4040, 4010], can=no_4) == 0b010110   # cells 5, 3, 2
    assert bleeders(lib, [4000, 4000, 4000, 4050, 4000, 4000], can=no_4) == 0
    assert bleeders(lib, [4000, 4020, 4030, 4060, 4040, 4010], can=0x3F) == 0b011100   # with cell 4: 4, 5, 3


def test_a_bleeding_cell_goes_on_while_its_presumed_voltage_is_above_the_lowest_cell_that_does_not_bleed(lib):
    def keep(mv, bleeding, drop=(0,) * 6):
        return lib.balance_keep(cells(*mv), len(mv), bleeding, cells(*drop))
    assert keep([4000, 4001, 4000], 0b010) == 0b010
    assert keep([4000, 4000, 4005], 0b010) == 0                  # at the lowest: it leaves
    assert keep([4010, 3990, 4000], 0b011) == 0b001              # a bled cell reading low is not the reference
    assert keep([4003, 4001, 4005], 0b011) == 0
    # its own bleed took 9 mV off its reading: it is presumed 9 mV higher (cheali's Voff - Von)
    assert keep([4000, 3992, 4000], 0b010, (0, 9, 0)) == 0b010
    assert keep([4000, 3991, 4000], 0b010, (0, 9, 0)) == 0
    assert keep([3995, 3996, 4000], 0b010, (9, 0, 0)) == 0b010   # only a bleeding cell's own drop counts


def test_the_hold_caps_the_current_by_5_ma_per_mv_from_where_it_was_or_from_the_current_above_the_ceiling(lib):
    cap = lib.balance_cap
    assert cap(1000, 10, 300, 2000) == 1050                     # below: grows from where it was
    assert cap(1000, 0, 300, 2000) == 1000
    assert cap(1000, -10, 300, 2000) == 250                     # above: falls from the current now
    assert cap(200, -10, 300, 2000) == 150                      # ... or from the cap when that is lower
    assert cap(1000, 100, 300, 1200) == 1200                    # never above the phase's own
    assert cap(100, -100, 50, 2000) == 0                        # never below zero


def test_a_held_charge_ends_at_its_ceiling_less_5_mv_and_a_tenth_of_its_current_kept_by_the_cells(lib):
    end = lib.balance_held_end
    assert end(4195000, 4200000, 100000, 0, 3, 1000000) == 1
    assert end(4194999, 4200000, 100000, 0, 3, 1000000) == 0       # below the ceiling
    assert end(4195000, 4200000, 100001, 0, 3, 1000000) == 0       # more than a tenth
    assert end(4195000, 4200000, 300000, 600000, 3, 1000000) == 1  # a tenth kept: 0.6 A bled over 3 cells
    assert end(4195000, 4200000, 300001, 600000, 3, 1000000) == 0
    assert end(4195000, 4200000, 100000, 0, 0, 1000000) == 0       # no cells
    assert end(4195000, 0, 0, 0, 3, 1000000) == 0                  # no ceiling (a chemistry without one)
    assert end(4195000, 4200000, 0, 0, 3, 0) == 1                  # a CV phase: once the cells keep nothing
    assert end(4195000, 4200000, 1, 0, 3, 0) == 0
    assert end(4195000, 4200000, 0, 0, 3, -1) == 0                 # no current asked


def test_a_load_bleeds_300_ma_at_4_2_v(lib):
    bled = lambda mv, bleeding: lib.balance_bled_ua(cells(*mv), len(mv), bleeding)
    assert bled([4200, 4200, 4200], 0b101) == 600000
    assert bled([4200, 4200, 4200], 0) == 0
    assert bled([4200, 3500, 4200, 4200, 4200, 4200], 0b100010) == 250000 + 300000   # the 6th cell counts


def test_cells_that_all_read_above_16_v_still_bleed_from_the_lowest_of_them(lib):
    # a tap on the wrong pin can make a "cell" read a whole pack (up to 27 V): the lowest is the reference
    # whatever the readings, not a start value below them
    assert bleeders(lib, [20000, 20020]) == 0b10
    assert bleeders(lib, [16400, 16400, 16409]) == 0b100
    assert lib.balance_keep(cells(20000, 19990), 2, 0b10, cells(0, 0)) == 0        # it reached the lowest


def test_only_the_pack_s_cells_are_read_not_the_taps_past_them(lib):
    # the board's six readings are one array: with a 2-cell pack, a third tap reading high is no cell of it
    assert lib.balance_bleeders(cells(4000, 4000, 4500, 4500, 4500, 4500), 2, 0, 0x3F) == 0
    assert lib.balance_bleeders(cells(4000, 4020, 4500, 4500, 4500, 4500), 2, 0b100, 0x3F) == 0b10
    # nor does balance_keep judge a tap past them, even with its bit in the mask (the count changed between calls)
    assert lib.balance_keep(cells(4000, 4010, 3990, 0, 0, 0), 2, 0b110, cells(0, 0, 0)) == 0b110
    assert lib.balance_bled_ua(cells(4200, 4200, 4200, 0, 0, 0), 2, 0b100) == 0
