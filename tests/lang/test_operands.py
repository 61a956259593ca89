"""Stored currents and voltages resolved to amperes and volts (simulator, passport lockout) and
to C-rates and volts per cell (lint): one rule for INPUT, relative and absolute values."""
from zuml_studio.lang.operands import CURRENT, INPUT_U16, VOLTAGE, absolute_value, relative_value


def test_absolute_values():
    assert absolute_value(CURRENT.parse("2A"), 9.0, 5.0) == 2.0
    assert absolute_value(CURRENT.parse("0.5C"), None, 4.0) == 2.0          # 0.5 x 4 Ah
    assert absolute_value(VOLTAGE.parse("4.2S"), None, 3) == 4.2 * 3
    assert absolute_value(INPUT_U16, 1.5, None) == 1.5
    assert absolute_value(INPUT_U16, None, 4.0) is None                   # not entered
    assert absolute_value(CURRENT.parse("1C"), 2.0, None) is None         # capacity unknown


def test_relative_values():
    assert relative_value(CURRENT.parse("1C"), None) == 1.0
    assert relative_value(CURRENT.parse("4A"), 2.0) == 2.0                # 4 A on 2 Ah
    assert relative_value(VOLTAGE.parse("12.6V"), 3) == 4.2
    assert relative_value(VOLTAGE.parse("12.6V"), None) is None
    assert relative_value(INPUT_U16, 3) is None
