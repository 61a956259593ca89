"""The calibration block and the procedure's arithmetic (docs/firmware.md, *Calibration*)."""
import pytest

from fake_b6_calibration import NOMINAL, FakeB6, patch_calibrator, readings
from zuml_studio.device.zuml.calibration import (BLOCK_SIZE, CHARGE, DISCHARGE, INPUTS, OFF, Block, CalibrationError,
                                            Calibrator, check_current, check_voltages, current_points, parse_cells,
                                            voltage_point)


def test_a_block_is_version_pairs_and_an_xor_check_byte():
    data = NOMINAL.encode()
    assert len(data) == BLOCK_SIZE == 54 and data[0] == 1 and data[1:5] == bytes((0, 0, 0xCE, 0x74))
    x = 0
    for byte in data:
        x ^= byte
    assert x == 0 and Block.decode(data) == NOMINAL


@pytest.mark.parametrize("damage", [lambda d: b"\x02" + d[1:], lambda d: d[:-1] + bytes((d[-1] ^ 1,)),
                                    lambda d: d[:-1]])
def test_a_damaged_block_is_refused(damage):
    with pytest.raises(CalibrationError):
        Block.decode(damage(NOMINAL.encode()))


def test_voltage_from_one_point_reads_the_meter_back():
    zero, full = voltage_point(11490.0, 25156)
    block = NOMINAL.replaced(INPUTS.index("Vout+"), zero, full)
    assert zero == 0 and abs(block.value(0, 25156) - 11490.0) < 0.5


def test_current_from_two_points_reads_both_back():
    zero, full = current_points((88.1, 2000), (982.8, 11000))
    block = NOMINAL.replaced(INPUTS.index("I smps"), zero, full)
    assert abs(block.value(3, 2000) - 88.1) < 0.2 and abs(block.value(3, 11000) - 982.8) < 0.2


def test_an_offset_just_below_zero_is_stored_as_zero_a_larger_one_or_a_falling_pair_is_an_error():
    assert current_points((50.0, 1970), (300.0, 11930))[0] == 0           # zero would be -22 counts
    with pytest.raises(CalibrationError, match="do not rise"):
        current_points((300.0, 11930), (50.0, 1970))
    with pytest.raises(CalibrationError, match=r"^I smps: the readings give a calibration the charger cannot store "
                                               r"\(check the meter's readings\)$"):
        NOMINAL.replaced(3, *current_points((500.0, 1000), (1000.0, 1100)))


@pytest.mark.parametrize("text", ["", "  ", "none", "None"])
def test_no_cells_means_keep(text):
    assert parse_cells(text) is None


def test_cells_are_volts_in_order_with_commas_or_semicolons():
    assert parse_cells("3.91,3.92, 3.90") == [3910.0, 3920.0, 3900.0]
    assert parse_cells("3,91;3,92") == [3910.0, 3920.0]


@pytest.mark.parametrize("text, reason", [
    ("3.9,,3.9", "item 2 is empty: give every cell from cell 1 on"),
    (",3.9", "item 1 is empty: give every cell from cell 1 on"),
    ("3.9,3.9,", "item 3 is empty: give every cell from cell 1 on"),
    ("3.9,x", "'x' is not a number of volts"),
    ("3.9,0", "cell 2: 0 V is outside 0..5 V"),
    ("5.01", "cell 1: 5.01 V is outside 0..5 V"),
    ("4,4,4,4,4,4,4", "the B6's balance port has at most 6 cells"),
])
def test_a_cell_list_that_would_shift_or_lie_is_refused(text, reason):
    with pytest.raises(CalibrationError) as caught:
        parse_cells(text)
    assert str(caught.value) == reason


def test_five_volts_and_six_cells_are_still_cells():
    assert parse_cells("5") == [5000.0] and len(parse_cells("4,4,4,4,4,4")) == 6


def refusal(*args) -> str:
    with pytest.raises(CalibrationError) as caught:
        check_voltages(*args)
    return str(caught.value)


def test_a_pack_typed_ten_times_low_is_refused_in_volts():
    """The issue's typo: 1.17 V entered for a pack the charger and its taps read at 11.4 V."""
    assert refusal(readings(), 1170, None, None) == ("the pack: 1.17 V entered, but the charger reads 11.40 V at "
                                                     "its output (more than 6 % apart): check the meter's reading")


def test_the_meter_and_the_charger_may_be_six_per_cent_apart_no_more():
    no_lead = readings(cells=())
    check_voltages(no_lead, 11400 * 1.0599, None, None)
    check_voltages(no_lead, 11400 * 0.9401, None, None)
    assert "more than 6 % apart" in refusal(no_lead, 11400 * 1.0640, None, None)
    assert "more than 6 % apart" in refusal(no_lead, 11400 * 0.9399, None, None)


def test_the_pack_must_be_its_cells_sum_within_three_per_cent():
    check_voltages(readings(), 11400 * 1.0299, None, None)
    assert refusal(readings(), 11400 * 1.0310, None, None) == ("the pack: 11.75 V entered, but its cells add up to "
                                                               "11.40 V: check the meter's reading")
    # the typed cells are the sum when given
    assert "cells add up to 12.00 V" in refusal(readings(), 11400, None, [4000, 4000, 4000])
    check_voltages(readings(), 11400, None, [3850, 3780, 3770])


def test_typed_cells_must_be_the_balance_port_s_and_each_near_its_reading():
    assert refusal(readings(), 7600, None, [3800, 3800]) == "the cells: 2 entered, but the balance port shows 3"
    assert refusal(readings(), 11400, None, [3800, 3400, 4200]) == (
        "cell 2: 3.40 V entered, but the charger reads 3.80 V (more than 6 % apart): check the meter's reading")


def test_the_supply_is_checked_against_the_input_reading():
    check_voltages(readings(), 11400, 12500, None)
    assert refusal(readings(), 11400, 1200, None) == ("the supply: 1.20 V entered, but the charger reads 12.00 V at "
                                                      "its input (more than 6 % apart): check the meter's reading")


def test_an_ammeter_reading_is_checked_against_the_charger_s_in_amps():
    check_current(CHARGE, 136, 100)                   # 16 % + 20 mA
    check_current(CHARGE, 64, 100)
    with pytest.raises(CalibrationError) as caught:
        check_current(CHARGE, 136.5, 100)
    assert str(caught.value) == ("the ammeter: 0.137 A entered, but the charger reads 0.100 A charging (more than "
                                 "16 % apart): check the meter's reading")
    with pytest.raises(CalibrationError, match="discharging"):
        check_current(DISCHARGE, 63.5, 100)
    with pytest.raises(CalibrationError):
        check_current(CHARGE, 333, 1000)               # a third of the truth typed


class TypedMeter:
    def __init__(self, pack_mv=11400.0, cells=None, currents=()):
        self.pack, self.cells, self.currents = pack_mv, cells, list(currents)

    def pack_mv(self):
        return self.pack

    def supply_mv(self):
        return None

    def cells_mv(self):
        return self.cells

    def current_ma(self, mode, asked_ma):
        return self.currents.pop(0)


def calibrator(monkeypatch):
    patch_calibrator(monkeypatch)
    client = FakeB6()
    return Calibrator(client), client


def test_a_typo_stops_the_calibration_before_any_output_or_write(monkeypatch):
    c, client = calibrator(monkeypatch)
    with pytest.raises(CalibrationError, match="1.17 V entered"):
        c.run(TypedMeter(pack_mv=1170))
    assert [name for name, _payload in client.asked] == ["CAL_READ"]


def test_an_ammeter_typo_switches_the_output_off_and_writes_nothing(monkeypatch):
    c, client = calibrator(monkeypatch)
    with pytest.raises(CalibrationError, match="0.010 A entered"):
        c.run(TypedMeter(currents=[10]))
    names = [name for name, _payload in client.asked]
    assert "CAL_WRITE" not in names and client.asked[-1] == ("CAL_OUTPUT", bytes((OFF, 0, 0)))
