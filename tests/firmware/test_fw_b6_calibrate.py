"""`zuml calibrate` on the simulated iMAX B6, started uncalibrated: the user's meter is the model's truth
(the --trace file's true current and voltage), read at the moment the command asks for it; afterwards
the charger measures V within 10 mV and I within 2 % of that truth."""
import re
import shutil
import subprocess
import sys

import pytest

from zuml_studio.cli.main import main
from zuml_studio.device.calibration import CHARGE, ISMPS, OFF, VOUT, Calibrator
from zuml_studio.device.client import ChargerClient

from host_core import FIRMWARE, INSTALL_HINT

B6_BAUD = 57600


@pytest.fixture(scope="module")
def b6_build():
    missing = [tool for tool in ("make", "gcc", "avr-gcc") if shutil.which(tool) is None]
    if missing:
        pytest.skip(f"{', '.join(missing)} not found ({INSTALL_HINT})")
    done = subprocess.run(["make", "-s", "-C", str(FIRMWARE), "imaxb6", "simavr-imaxb6"], capture_output=True,
                          text=True)
    assert done.returncode == 0, done.stdout + done.stderr


@pytest.fixture
def uncalibrated_b6(b6_build, tmp_path):
    """(port, truth): a simulated B6 with no calibration, and truth(column) the model's true value of a
    trace column ('current_a', 'voltage_v') averaged over its last simulated second written."""
    trace = tmp_path / "trace.csv"
    proc = subprocess.Popen([sys.executable, "-m", "zuml_studio.cli.main", "firmware-sim", "--board", "imaxb6",
                             "--uncalibrated", "--seed", "7", "--soc", "0.5", "--speed", "0", "--trace", str(trace)],
                            stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
    port = proc.stdout.readline().strip()

    def truth(column: str) -> float:
        lines = trace.read_text().splitlines()
        index = lines[0].split(",").index(column)
        rows = [line.split(",") for line in lines[-1001:-1] if line.count(",") == 5 and line[0].isdigit()]
        return sum(float(row[index]) for row in rows) / len(rows)

    yield port, truth
    proc.terminate()
    proc.wait()


def test_zuml_calibrate_makes_the_simulated_b6_read_its_truth(uncalibrated_b6, monkeypatch, capsys):
    port, truth = uncalibrated_b6
    asked = []

    def meter(prompt: str) -> str:
        asked.append(prompt)
        if "ammeter" in prompt:
            return f"{abs(truth('current_a')) * 1000:.1f}"
        if "pack" in prompt:
            return f"{truth('voltage_v'):.4f}"
        return ""                           # the supply and the cells: not measured, kept

    monkeypatch.setattr("builtins.input", meter)
    assert main(["calibrate", "--port", port, "--baud", str(B6_BAUD), "--supply-v", "0", "--cells-v", ""]) == 0
    out = capsys.readouterr().out
    assert "Calibrated and stored" in out
    assert len(asked) == 5 and sum("ammeter" in prompt for prompt in asked) == 4
    assert re.search(r"Vout\+ +\d+ +zero +0 +full +\d+", out)

    with ChargerClient(port, B6_BAUD) as client:
        calibrator = Calibrator(client)
        assert calibrator.read()[0]                           # the EEPROM's block now
        volts = calibrator.after_next_second()[VOUT].value / 1000
        assert abs(volts - truth("voltage_v")) <= 0.010
        calibrator.output(CHARGE, 500)
        try:
            amps = calibrator.settled(ISMPS).value / 1000
            true_amps = truth("current_a")
        finally:
            calibrator.output(OFF)
    assert abs(amps - true_amps) <= 0.02 * true_amps
