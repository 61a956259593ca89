"""zuml calibrate: its one-line errors (the whole procedure on the simulated B6:
tests/firmware/test_fw_b6_calibrate.py)."""


def test_readings_out_of_range_are_refused_before_connecting(zuml):
    code, out, err = zuml("calibrate", "--port", "/dev/null/none", "--pack-v", "99")
    assert code == 2 and err == "zuml: error: --pack-v: 99 V is outside 0..60 V\n"
    code, out, err = zuml("calibrate", "--port", "/dev/null/none", "--cells-v", "3.9,x")
    assert code == 2 and err == "zuml: error: --cells-v: 'x' is not a number of volts\n"
    code, out, err = zuml("calibrate", "--port", "/dev/null/none", "--cells-v", "4,4,4,4,4,4,4")
    assert code == 2 and "at most 6 cells" in err
    code, out, err = zuml("calibrate", "--port", "/dev/null/none", "--cells-v", "3.9,,3.9")
    assert code == 2 and err == "zuml: error: --cells-v: item 2 is empty: give every cell from cell 1 on\n"


def test_cells_none_keeps_them_as_the_help_says(zuml, make_charger):
    _device, port = make_charger()
    for keep in ("none", ""):
        code, out, err = zuml("calibrate", "--port", port, "--pack-v", "12", "--supply-v", "0", "--cells-v", keep)
        assert code == 1 and "CAL_READ: not a request this charger serves" in err   # got as far as the charger


def test_a_charger_without_the_b6_calibration_says_so(zuml, make_charger):
    _device, port = make_charger()
    code, out, err = zuml("calibrate", "--port", port, "--pack-v", "12", "--supply-v", "0", "--cells-v", "")
    assert code == 1 and err.splitlines() == ["zuml: error: the charger refused: CAL_READ: not a request this "
                                              "charger serves"]
