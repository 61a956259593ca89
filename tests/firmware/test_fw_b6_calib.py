"""The iMAX B6's calibration window and duty bound (firmware/boards/imaxb6/calib.c, duty.c) built for the PC:
a block is used only when every input reads the board's maximum and 0 within what its parts allow (voltages
3 %, currents 8 %, the probe 5 % of the maximum; a quarter of that at 0), and the charge duty never exceeds
the one that puts the pack's ceiling plus 1.5 V on the output. Each boundary is met exactly, one unit inside
and one outside, so a changed comparison or constant fails here."""
import ctypes

import pytest

from test_fw_b6_protect import IDIS, ISMPS, TEXTERN, VB1, VB2, VOUT, sealed
from test_fw_b6_protect import lib as logic  # noqa: F401 - the host build, a fixture

NOMINAL = [(0, 29902), (0, 30826), (26, 1646), (233, 6042), (0, 19154), (0, 5022), (0, 4985), (0, 9761),
           (0, 4899), (0, 5016), (0, 4993), (0, 4924), (0, 25395)]
# (the board's maximum in mV, mA or 0.01 degC, per cent the parts allow) per input, calib.c's window
WINDOW = [(27000, 3), (27000, 3), (1000, 8), (5000, 8), (18000, 3), (4350, 3), (4350, 3), (8700, 3),
          (4350, 3), (4350, 3), (4350, 3), (4350, 3), (10000, 5)]
OK, BAD_FORM, OUT_OF_WINDOW = 0, 1, 2


@pytest.fixture(scope="module")
def lib(logic):  # noqa: F811 - the fixture imported above
    logic.duty_top.restype = ctypes.c_uint16
    logic.duty_top.argtypes = [ctypes.c_int32, ctypes.c_int32]
    logic.cal_block_check.restype = ctypes.c_uint8
    return logic


class Miss(ctypes.Structure):
    _fields_ = [("input", ctypes.c_uint8), ("point", ctypes.c_int32), ("reads", ctypes.c_int32),
                ("allowed", ctypes.c_int32)]


def check(lib, pairs) -> tuple[int, Miss]:
    miss = Miss()
    return lib.cal_block_check(sealed(pairs), ctypes.byref(miss)), miss


def value(zero: int, full: int, adc16: int) -> int:
    """calib.c's value_of: rounded half away from zero."""
    v = (abs(adc16 - zero) * full + 32768) >> 16
    return v if adc16 >= zero else -v


def at_point(k: int) -> int:
    """The ADC16 where the nominal calibration reads input k's maximum."""
    zero, full = NOMINAL[k]
    return zero + (WINDOW[k][0] * 65536 + full // 2) // full


def with_pair(k: int, pair) -> list:
    return NOMINAL[:k] + [pair] + NOMINAL[k + 1:]


def test_the_nominal_calibration_is_inside_every_window(lib):
    assert check(lib, NOMINAL)[0] == OK and lib.cal_block_valid(sealed(NOMINAL)) == 1


@pytest.mark.parametrize("k", range(13))
@pytest.mark.parametrize("side", [1, -1])
def test_each_input_s_full_scale_is_refused_one_unit_past_its_window(lib, k, side):
    point, pct = WINDOW[k]
    allowed = point * pct // 100
    zero, nominal_full = NOMINAL[k]
    edge = point + side * allowed                     # reads exactly this: still allowed
    fulls = range(nominal_full, 2 * nominal_full) if side > 0 else range(nominal_full, 0, -1)
    inside = next(f for f in fulls if side * (value(zero, f, at_point(k)) - edge) >= 0)
    assert value(zero, inside, at_point(k)) == edge
    assert check(lib, with_pair(k, (zero, inside)))[0] == OK
    outside = inside + side
    while value(zero, outside, at_point(k)) == edge:
        outside += side
    verdict, miss = check(lib, with_pair(k, (zero, outside)))
    assert verdict == OUT_OF_WINDOW
    assert (miss.input, miss.point, miss.reads, miss.allowed) == (k, point, edge + side, allowed)


@pytest.mark.parametrize("k", range(13))
def test_a_refusal_names_the_reading_at_the_adc_code_nearest_the_point(lib, k):
    # a full scale of 65535 makes one ADC code worth a unit or more, so the code the nominal calibration reads
    # the point at (rounded to the nearest, not up) shows in the reading named
    zero = NOMINAL[k][0]
    verdict, miss = check(lib, with_pair(k, (zero, 65535)))
    assert verdict == OUT_OF_WINDOW and miss.input == k
    assert miss.reads == value(zero, 65535, at_point(k))


@pytest.mark.parametrize("k", range(13))
def test_each_input_s_zero_is_refused_one_unit_past_a_quarter_of_its_window(lib, k):
    point, pct = WINDOW[k]
    zero, full = NOMINAL[k]
    edge = point * pct // 400                         # |reading at 0| * 400 > point * pct: refused
    inside = next(z for z in range(zero, zero + 65536) if value(z, full, zero) <= -edge)
    assert value(inside, full, zero) == -edge
    assert check(lib, with_pair(k, (inside, full)))[0] == OK
    outside = inside
    while value(outside, full, zero) == -edge:
        outside += 1
    verdict, miss = check(lib, with_pair(k, (outside, full)))
    assert verdict == OUT_OF_WINDOW
    assert (miss.input, miss.point, miss.reads, miss.allowed) == (k, 0, -edge - 1, edge)


@pytest.mark.parametrize("k, scale, reads", [
    (ISMPS, 1 / 3, 1667), (ISMPS, 0.001, 5), (ISMPS, 3, 15000), (IDIS, 1 / 3, 333),
    (VOUT, 0.8, 21600), (VOUT, 1.2, 32400), (VB1, 0.8, 3480), (VB2, 1.2, 10440), (TEXTERN, 0.5, 5000),
])
def test_a_lying_calibration_is_refused_and_the_nominal_one_used(lib, k, scale, reads):
    """Issue 31's blocks: the current sensor reading 1/3, ~0 and 3x the truth, the voltages 80 % and 120 %."""
    zero, full = NOMINAL[k]
    block = with_pair(k, (zero, max(1, round(full * scale))))
    verdict, miss = check(lib, block)
    assert verdict == OUT_OF_WINDOW and miss.input == k and miss.point == WINDOW[k][0]
    assert abs(miss.reads - reads) <= 2
    assert lib.cal_use(sealed(block)) == 0
    assert abs(lib.cal_value(VOUT, 55102) - 25141) <= 1          # the nominal calibration is in use


def test_the_first_input_out_of_its_window_is_the_one_named(lib):
    pairs = with_pair(VOUT, (0, 20000))
    pairs[ISMPS] = (233, 2000)
    assert check(lib, pairs)[1].input == VOUT
    pairs[VOUT] = NOMINAL[VOUT]
    assert check(lib, pairs)[1].input == ISMPS


def test_a_block_that_is_no_block_is_bad_form_before_any_window(lib):
    pairs = with_pair(VOUT, (0, 20000))
    assert lib.cal_block_check(sealed(pairs, version=2), ctypes.byref(Miss())) == BAD_FORM
    assert check(lib, with_pair(ISMPS, (233, 0)))[0] == BAD_FORM
    torn = bytearray(sealed(NOMINAL))
    torn[9] ^= 1
    assert lib.cal_block_check(bytes(torn), ctypes.byref(Miss())) == BAD_FORM


def test_readings_through_any_pair_do_not_overflow(lib):
    lib.cal_use(sealed(NOMINAL))
    assert lib.cal_value(VOUT, 65535) == value(0, 29902, 65535)
    assert lib.cal_value(ISMPS, 0) == value(233, 6042, 0) < 0
    assert lib.cal_value(IDIS, 26) == 0


BUCK_FULL, BOOST_MAX, MARGIN_MV = 32768, 16384, 1500


@pytest.mark.parametrize("vin, ceiling", [(12000, 4350), (12000, 8700), (12000, 10450), (18000, 13050),
                                          (12000, 12600 - 1500), (12000, 13050), (11000, 17400), (15000, 17400)])
def test_the_duty_bound_puts_the_ceiling_plus_the_margin_on_the_output(lib, vin, ceiling):
    top = lib.duty_top(vin, ceiling)
    target = ceiling + MARGIN_MV
    if target <= vin:
        assert top == target * BUCK_FULL // vin
        out = vin * top / BUCK_FULL
    else:
        assert top == BUCK_FULL + BUCK_FULL - vin * BUCK_FULL // target
        out = vin / (1 - (top - BUCK_FULL) / BUCK_FULL)
    assert abs(out - target) <= target / 1000


def test_the_duty_bound_is_capped_at_half_boost_and_closed_without_an_input(lib):
    assert lib.duty_top(12000, 27000) == BUCK_FULL + BOOST_MAX            # 2 x 12 V < 28.5 V: the 50 % cap
    below_cap = lib.duty_top(12000, 24000 - MARGIN_MV)                   # 24 V from 12 V: exactly 50 %
    assert below_cap == BUCK_FULL + BOOST_MAX
    assert lib.duty_top(12000, 24000 - MARGIN_MV - 20) < BUCK_FULL + BOOST_MAX

    assert lib.duty_top(999, 4350) == 0
    assert lib.duty_top(1000, 4350) == BUCK_FULL + BOOST_MAX              # 1 V in: boost, capped
    assert lib.duty_top(12000, -5000) == MARGIN_MV * BUCK_FULL // 12000   # no ceiling: the margin alone
    assert lib.duty_top(12000, 12000 - MARGIN_MV) == BUCK_FULL


@pytest.mark.parametrize("pack", [3000, 11400, 25200])
def test_the_pack_and_its_cells_agree_within_two_per_cent_and_50_mv(lib, pack):
    lib.cal_pack_agrees.argtypes = [ctypes.c_int32, ctypes.c_int32]
    lib.cal_pack_agrees.restype = ctypes.c_uint8
    edge = (pack * 2 + 5000) // 100
    assert lib.cal_pack_agrees(pack, pack) == 1
    assert lib.cal_pack_agrees(pack, pack - edge) == 1 and lib.cal_pack_agrees(pack, pack + edge) == 1
    assert lib.cal_pack_agrees(pack, pack - edge - 1) == 0 and lib.cal_pack_agrees(pack, pack + edge + 1) == 0


def adc16(zero: int, full: int, value: int) -> int:
    """calib.c's cal_adc16: the nearest ADC16 code to `value` (0 for a negative one), at most 65535."""
    return min(zero + (max(value, 0) * 65536 + full // 2) // full, 65535)


def test_a_value_turns_into_its_nearest_adc16_code_and_one_past_the_scale_into_65535(lib):
    # cal_adc16 turns the battery's current into the code the averages count in boost (adc.c): its
    # rounding is half a code, not a whole one nor a quarter, and a value past the input's scale is the
    # top code, never one wrapped to 16 bits (29902 mV per 65536: 40 V is code 87 666, kept as 65535)
    lib.cal_use(sealed(NOMINAL))
    for k in (VOUT, ISMPS, IDIS):
        zero, full = NOMINAL[k]
        for v in list(range(0, 40)) + [1000, 4999, 5000, 12600, 20000]:
            assert lib.cal_adc16(k, v) == adc16(zero, full, v), (k, v)
    edge = (65535 - NOMINAL[ISMPS][0]) * NOMINAL[ISMPS][1] // 65536          # the highest value below the top
    assert lib.cal_adc16(ISMPS, edge) < 65535 and lib.cal_adc16(ISMPS, edge + 2) == 65535
    assert lib.cal_adc16(VOUT, 40000) == 65535
    assert lib.cal_adc16(ISMPS, -5) == NOMINAL[ISMPS][0]
