"""`zuml replay` onto a pty, read back by `zuml monitor --driver auto`: the charger is
recognised and every record of the recording reaches the CSV."""
import csv
import os
import signal
import subprocess
import sys

import pytest

from tests_cli_util import run_zuml
from zuml_studio.streams.drivers import DRIVERS

DATA = os.path.join(os.path.dirname(__file__), "..", "data", "realdata")
pytestmark = pytest.mark.skipif(os.name != "posix", reason="zuml replay needs a pty")


def _replay(path, *extra):
    proc = subprocess.Popen([sys.executable, "-m", "zuml_studio.cli.main", "replay", path, *extra],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    port = proc.stdout.readline().strip()
    return proc, port


def _stop(proc):
    proc.send_signal(signal.SIGINT)
    try:
        return proc.communicate(timeout=10)
    finally:
        proc.kill()


@pytest.mark.parametrize("name, records, driver, cells", [
    ("cheali_captured_lines_from_issues.txt", 13, "cheali", 6),
    ("icharger306B_RB_1000_lines_head60.txt", 60, "icharger", 6),
])
def test_replay_into_monitor_loses_nothing(tmp_path, name, records, driver, cells):
    src = os.path.join(DATA, name)
    if "head60" in name:                       # the first 60 lines of the 300 kept: 120 s of recording, 1.2 s at x100
        src = tmp_path / name
        lines = open(os.path.join(DATA, "icharger306B_RB_1000_lines_head300.txt"), "rb").read().splitlines(True)
        src.write_bytes(b"".join(lines[:60]))
    proc, port = _replay(str(src), "--speed", "100")
    try:
        assert port.startswith("/dev/"), proc.stderr.read()
        out_csv = tmp_path / "out.csv"
        code, out, err = run_zuml("monitor", "--port", port, "--driver", "auto", "--samples", str(records),
                                  "--seconds", "50", "--csv", str(out_csv))
        # The replay says so once its last record is out (the monitor may have it first).
        told = [proc.stderr.readline() for _ in range(2)]
    finally:
        _stop(proc)
    assert code == 0, err
    assert f"recognised {DRIVERS[driver].title} at " in err, err
    assert "end of the recording" in told[1], told
    with out_csv.open() as fh:
        rows = list(csv.DictReader(fh))
    assert len(rows) == records and len(out.splitlines()) == records
    assert list(rows[0])[-cells:] == [f"cell{k}_v" for k in range(1, cells + 1)]
    assert f"{driver}: {records} sample{'' if records == 1 else 's'}" in err


def test_replay_refuses_what_it_cannot_read(tmp_path):
    bad = tmp_path / "notes.txt"
    bad.write_text("just some text\n")
    code, out, err = run_zuml("replay", str(bad))
    assert code != 0 and "no recording recognised" in err and "tried cheali" in err and "Traceback" not in err


def test_monitor_names_what_it_tried_on_a_port_of_junk(tmp_path):
    """A pty that sends only junk: a message naming the drivers and bauds, no traceback."""
    import threading
    import tty
    master, slave = os.openpty()
    tty.setraw(slave)
    stop = threading.Event()

    def junk():
        while not stop.is_set():
            try:
                os.write(master, bytes(range(256)))
            except OSError:
                break
            stop.wait(0.01)

    t = threading.Thread(target=junk, daemon=True)
    t.start()
    try:
        code, out, err = run_zuml("monitor", "--port", os.ttyname(slave), "--driver", "auto", "--seconds", "60")
    finally:
        stop.set()
        t.join()
        os.close(master)
        os.close(slave)
    assert code == 1 and "nothing recognisable" in err and "tried cheali, icharger, imaxb6, ultramat" in err
    assert "57600, 128000, 9600" in err and "Traceback" not in err


def test_a_hid_report_dump_replays_to_its_driver(tmp_path):
    """HID report dumps play onto a pty too; `--driver NAME` reads them (auto is for serial chargers)."""
    sys.path.insert(0, os.path.join(os.path.dirname(__file__), "..", "device"))
    from realdata_samples import ICHARGER_HID_REPORT
    dump = tmp_path / "icharger-hid.txt"
    dump.write_text("# three log reports\n" + "".join(f"RX {ICHARGER_HID_REPORT[:44].hex(' ')}\n" for _ in range(3)))
    proc, port = _replay(str(dump), "--speed", "100")
    try:
        code, out, err = run_zuml("monitor", "--port", port, "--driver", "icharger-hid", "--samples", "3",
                                  "--seconds", "50")
    finally:
        _stop(proc)
    assert code == 0 and "icharger-hid: 3 samples, 0 bad records" in err, err
    assert out.count("15.403 V") == 3 and "[discharge]" in out
