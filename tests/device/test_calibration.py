"""The calibration block and the procedure's arithmetic (docs/firmware.md, *Calibration*)."""
import pytest

from zuml_studio.device.calibration import (BLOCK_SIZE, INPUTS, Block, CalibrationError, current_points,
                                            voltage_point)

NOMINAL = Block(((0, 29902), (0, 30826), (26, 1646), (233, 6042), (0, 19154), (0, 5022), (0, 4985), (0, 9761),
                 (0, 4899), (0, 5016), (0, 4993), (0, 4924), (0, 25395)))


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
    with pytest.raises(CalibrationError, match="outside what the charger stores"):
        NOMINAL.replaced(3, *current_points((500.0, 1000), (1000.0, 1100)))
