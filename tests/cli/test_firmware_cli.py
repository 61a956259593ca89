"""`zuml firmware-sim`: the C firmware behind a pty, driven by the device commands as a charger is."""
import argparse
import os
import subprocess
import sys

import pytest

from tools import HOST, SIMAVR, needs
from helpers import MACROS
from zuml_studio.cli.firmware_command import b6_arguments

pytestmark = pytest.mark.skipif(os.name != "posix", reason="ptys need POSIX")


BOARDS = [
    pytest.param("host", marks=needs(HOST)),
    pytest.param("atmega32", marks=needs(SIMAVR)),
]


@pytest.fixture(params=BOARDS)
def firmware_port(request, tmp_path):
    proc = subprocess.Popen([sys.executable, "-m", "zuml_studio.cli.main", "firmware-sim", "--board", request.param,
                             "--eeprom", str(tmp_path / "ee.bin")], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True)
    port = proc.stdout.readline().strip()
    assert port.startswith("/dev/"), proc.stderr.read() if proc.poll() is not None else port
    yield port
    proc.terminate()
    assert proc.wait(timeout=10) == 0


def test_flash_slots_run_monitor_stop_backup_against_the_firmware(firmware_port, zuml, tmp_path):
    port = firmware_port
    assert zuml("flash", "--port", port, str(MACROS / "LiPo.zuml"))[0] == 0
    assert zuml("flash", "--port", port, str(MACROS / "NiMh-dV.zuml"))[0] == 0
    code, out, err = zuml("slots", "--port", port)
    assert code == 0 and "LiPo" in out and "NiMh-dV" in out, err
    code, out, err = zuml("run", "--port", port, "--slot", "0", "--capacity", "2000", "--current", "1",
                          "--series", "3")
    assert code == 0, err
    code, out, err = zuml("monitor", "--port", port, "--samples", "3", "--seconds", "50", "--rate", "10")
    assert code == 0 and "charge" in out, err
    code, out, err = zuml("stop", "--port", port)
    assert code == 0, err
    code, out, err = zuml("backup", "--port", port, "-o", str(tmp_path / "image.bin"))
    assert code == 0 and (tmp_path / "image.bin").stat().st_size == 431
    code, out, err = zuml("restore", "--port", port, str(tmp_path / "image.bin"))
    assert code == 0, err


def test_a_start_the_firmware_refuses_is_one_line(firmware_port, zuml):
    assert zuml("flash", "--port", firmware_port, str(MACROS / "LiPo.zuml"))[0] == 0
    code, out, err = zuml("run", "--port", firmware_port, "--slot", "0", "--capacity", "2000", "--series", "3")
    assert code != 0 and "give the current" in err and len(err.strip().splitlines()) == 1


@pytest.mark.parametrize("args, message", [
    (["--board", "atmega32", "--lcd"], "--lcd is for --board imaxb6"),
    (["--board", "host", "--fault", "hang@1"], "--fault is for --board imaxb6"),
    (["--board", "atmega32", "--no-rx"], "--no-rx is for --board imaxb6"),
    (["--board", "host", "--no-balance-lead"], "--no-balance-lead is for --board imaxb6"),
    (["--board", "imaxb6", "--fault", "melt@1"], "--fault melt@1: expected NAME@SECONDS, NAME one of disconnect"),
    (["--board", "imaxb6", "--fault", "hang@1:2"], "--fault hang@1:2: expected NAME@SECONDS,"),
    (["--board", "imaxb6", "--press", "start@1:x"], "--press start@1:x: expected NAME@SECONDS[:HOLD]"),
    (["--board", "imaxb6", "--cells", "7"], "--cells is 1..6 on the iMAX B6"),
    (["--board", "imaxb6", "--speed", "-1"], "--speed is 0"),
    (["--board", "imaxb6", "--cell-spread", "2000"], "--cell-spread is 0..1000 mV"),
])
def test_the_simulated_b6s_options_are_checked_before_anything_is_built(zuml, args, message):
    code, out, err = zuml("firmware-sim", *args)
    assert code != 0 and out == "" and message in err and len(err.strip().splitlines()) == 1


def test_no_balance_lead_reaches_the_simulated_b6():
    args = argparse.Namespace(board="imaxb6", cells=3, cell_spread=None, weak_cell=None, seed=None, fault=None,
                              press=None, trace=None, speed=None, uncalibrated=False, lcd=False, no_rx=False,
                              no_balance_lead=True)
    assert b6_arguments(args) == ["--no-balance-lead"]


@needs(SIMAVR)
def test_the_simulated_b6_takes_its_options_through_the_cli(tmp_path):
    """--uncalibrated, --lcd and --eeprom through `zuml firmware-sim --board imaxb6`: the panel says why it will
    not charge, and the file holds no calibration."""
    proc = subprocess.Popen([sys.executable, "-m", "zuml_studio.cli.main", "firmware-sim", "--board", "imaxb6",
                             "--speed", "0", "--lcd", "--uncalibrated", "--seed", "3", "--eeprom",
                             str(tmp_path / "ee.bin")], stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        assert proc.stdout.readline().startswith("/dev/")
        for line in proc.stderr:                     # the device runs until stopped: the line ends the wait
            if line.startswith("LCD|") and "not calibrated" in line:
                break
        else:
            raise AssertionError("the simulator ended without showing 'not calibrated'")
    finally:
        proc.terminate()
        proc.wait(timeout=30)
    assert (tmp_path / "ee.bin").read_bytes()[970:1024] == b"\xff" * 54


@needs(SIMAVR)
def test_no_rx_through_the_cli_is_a_b6_heard_on_its_tx_alone(tmp_path):
    """`zuml firmware-sim --board imaxb6 --no-rx` reaches the simulator: it says it has no receive wire (what
    that means for the firmware: tests/firmware/test_fw_b6_txonly.py)."""
    proc = subprocess.Popen([sys.executable, "-m", "zuml_studio.cli.main", "firmware-sim", "--board", "imaxb6",
                             "--speed", "0", "--lcd", "--no-rx"], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                            text=True)
    try:
        assert proc.stdout.readline().startswith("/dev/")
        said = []
        for line in proc.stderr:
            said.append(line)
            if line.startswith("LCD|") and "ready Vin" in line:
                break
        else:
            raise AssertionError("the simulator ended before its idle screen")
    finally:
        proc.terminate()
        proc.wait(timeout=30)
    assert any("TX only (no receive wire)" in line for line in said)
