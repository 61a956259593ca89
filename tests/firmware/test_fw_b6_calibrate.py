"""`zuml calibrate` on the simulated iMAX B6, started uncalibrated: the user's meter is the model's truth
(the --trace file's true current and voltage), read at the moment the command asks for it; afterwards
the charger measures V within 10 mV and I within 2 % of that truth."""
import re

import pytest

from b6_sim import B6_BAUD, uncalibrated_b6
from zuml_studio.cli.main import main
from zuml_studio.device.zuml.calibration import CHARGE, ISMPS, OFF, VOUT, Calibrator
from zuml_studio.device.zuml.client import ChargerClient

b6 = pytest.fixture(uncalibrated_b6)


def test_zuml_calibrate_makes_the_simulated_b6_read_its_truth(b6, monkeypatch, capsys):
    asked = []

    def meter(prompt: str) -> str:
        asked.append(prompt)
        if "ammeter" in prompt:
            return f"{abs(b6.truth('current_a')) * 1000:.1f}"
        if "pack" in prompt:
            return f"{b6.truth('voltage_v'):.4f}"
        return ""                           # the supply and the cells: not measured, kept

    monkeypatch.setattr("builtins.input", meter)
    # --timeout: a simulated B6 on a loaded machine can fall seconds behind; a real one answers at once
    assert main(["calibrate", "--port", b6.port, "--baud", str(B6_BAUD), "--timeout", "5", "--supply-v", "0",
                 "--cells-v", ""]) == 0
    out = capsys.readouterr().out
    assert "Calibrated and stored" in out
    assert len(asked) == 5 and sum("ammeter" in prompt for prompt in asked) == 4
    assert re.search(r"Vout\+ +\d+ +zero +0 +full +\d+", out)

    with ChargerClient(b6.port, B6_BAUD) as client:
        calibrator = Calibrator(client)
        assert calibrator.read()[0]                           # the EEPROM's block now
        volts = calibrator.after_next_second()[VOUT].value / 1000
        assert abs(volts - b6.truth("voltage_v")) <= 0.010
        calibrator.output(CHARGE, 500)
        try:
            amps = calibrator.settled(ISMPS).value / 1000
            true_amps = b6.truth("current_a")
        finally:
            calibrator.output(OFF)
    assert abs(amps - true_amps) <= 0.02 * true_amps


def test_zuml_calibrate_refuses_a_pack_typed_ten_times_low_and_writes_nothing(b6, capsys):
    """hostile-3/calibrate_typo.sh: 1.17 V typed for the 3S pack at ~11.4 V was stored as "Calibrated"."""
    assert main(["calibrate", "--port", b6.port, "--baud", str(B6_BAUD), "--timeout", "5", "--pack-v", "1.17",
                 "--supply-v", "0", "--cells-v", "none"]) == 1
    err = capsys.readouterr().err
    assert re.fullmatch(r"zuml: error: the pack: 1\.17 V entered, but the charger reads 1\d\.\d\d V at its output "
                        r"\(more than 6 % apart\): check the meter's reading\n", err), err
    with ChargerClient(b6.port, B6_BAUD) as client:
        assert not Calibrator(client).read()[0]                # still not calibrated
