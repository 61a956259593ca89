"""The simulated iMAX B6 (`zuml firmware-sim --board imaxb6`) for tests that talk to it over its pty, and
its model's truth from the --trace file."""
import subprocess
import sys
from pathlib import Path

from tools import SIMAVR, skip_unless

FIRMWARE = Path(__file__).resolve().parents[1] / "firmware"
B6_BAUD = 57600


def build_b6() -> None:
    """`make` the B6 image and its simulator, or skip saying which tools are missing."""
    skip_unless(SIMAVR)                     # the simulator links simavr and libelf
    done = subprocess.run(["make", "-s", "-C", str(FIRMWARE), "imaxb6", "simavr-imaxb6"], capture_output=True,
                          text=True)
    assert done.returncode == 0, done.stdout + done.stderr


class SimulatedB6:
    """A simulated B6 started with ``args``; ``port`` its pty; ``truth(column)`` the model's true value of a
    trace column (current_a, voltage_v) over the last simulated second written."""

    def __init__(self, trace: Path, *args: str):
        self.trace = trace
        self.proc = subprocess.Popen([sys.executable, "-m", "zuml_studio.cli.main", "firmware-sim", "--board",
                                      "imaxb6", "--trace", str(trace), *args],
                                     stdout=subprocess.PIPE, stderr=subprocess.DEVNULL, text=True)
        self.port = self.proc.stdout.readline().strip()

    def truth(self, column: str) -> float:
        lines = self.trace.read_text().splitlines()
        index = lines[0].split(",").index(column)
        rows = [line.split(",") for line in lines[-1001:-1]
                if line.count(",") == lines[0].count(",") and line[0].isdigit()]
        return sum(float(row[index]) for row in rows) / len(rows)

    def stop(self) -> None:
        self.proc.terminate()
        self.proc.wait()


def uncalibrated_b6(tmp_path: Path):
    """A fixture body: an uncalibrated simulated B6 with a 3S pack at half charge, stopped afterwards."""
    build_b6()
    b6 = SimulatedB6(tmp_path / "trace.csv", "--uncalibrated", "--seed", "7", "--soc", "0.5")
    yield b6
    b6.stop()
