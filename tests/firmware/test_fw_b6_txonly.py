"""The iMAX B6 with nothing wired to its receive pin (issue 32 §2): the firmware sends its telemetry, events and
display over TX unasked, `zuml monitor --driver zuml-tx` shows the run started from the buttons, and PD0 is cell
4's balancer; with a USB-serial adapter's TX on PD0 the request protocol is as before and cell 4 is not balanced,
which the LCD and IDENTIFY say. Every wait is for a line the simulator or the monitor prints, never for a time."""
import csv
import os
import subprocess
import sys
import threading
import tty

import pytest

from b6_harness import B6, LINE_WAIT_S
from helpers import HOT_LIION
from host_core import FIRMWARE
from test_fw_b6_acceptance import BENCH        # CC to 4.1 V per cell, then CV to 0.1 A
from tools import AVRDUDE, needs
from zuml_studio.protocol import messages as m
from zuml_studio.device.zuml.client import ChargerClient
from zuml_studio.protocol.frames import FrameParser, encode_frame

ROOT = FIRMWARE.parent


@pytest.fixture
def two_macros(tmp_path):
    """An EEPROM file holding Bench and LiPo.zuml, made by `zuml image` as a user would."""
    (tmp_path / "Bench.zuml").write_text(BENCH)
    out = tmp_path / "eeprom.bin"
    done = subprocess.run([sys.executable, "-m", "zuml_studio.cli.main", "image", "-o", str(out),
                           str(tmp_path / "Bench.zuml"), str(ROOT / "macros" / "LiPo.zuml")],
                          capture_output=True, text=True, cwd=ROOT)
    assert done.returncode == 0, done.stderr
    return out


class Monitor:
    """`zuml monitor` on the port, its stdout lines collected as they come."""

    def __init__(self, *args: str):
        self.proc = subprocess.Popen([sys.executable, "-m", "zuml_studio.cli.main", "monitor", *args],
                                     stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, cwd=ROOT)
        self.lines: list[str] = []
        self.changed = threading.Condition()
        threading.Thread(target=self._read, daemon=True).start()

    def _read(self) -> None:
        for line in self.proc.stdout:
            with self.changed:
                self.lines.append(line.rstrip("\n"))
                self.changed.notify_all()

    def wait_line(self, test) -> str:
        with self.changed:
            assert self.changed.wait_for(lambda: any(test(line) for line in self.lines) or self.proc.poll() is not None,
                                         timeout=LINE_WAIT_S), self.lines[-5:]
            found = [line for line in self.lines if test(line)]
            assert found, f"the monitor ended: {self.lines[-5:]} {self.proc.stderr.read()}"
            return found[0]


def test_a_run_started_from_the_buttons_is_watched_listen_only_to_its_end(image, two_macros, tmp_path):
    sim = B6(image, "--no-rx", "--eeprom", two_macros, "--soc", "0.9", "--capacity", "20", "--speed", "0", "--lcd")
    session = tmp_path / "session.csv"
    monitor = Monitor("--driver", "zuml-tx", "--port", sim.port, "--until-end", "--csv", str(session))
    try:
        # the display as the firmware writes it, heard on TX: slot 1 is the first macro of the image
        monitor.wait_line(lambda line: line.startswith("LCD |1 Bench"))
        sim.press("start", 0.7)                   # START held 0.7 s (the panel wants 0.5 s) starts slot 1
        sim.wait_line("PRESS|start|")
        assert monitor.proc.wait(timeout=LINE_WAIT_S) == 0, monitor.proc.stderr.read()
    finally:
        if monitor.proc.poll() is None:
            monitor.proc.terminate()
        sim.stop()
    lines = monitor.lines
    events = [line for line in lines if line.startswith("*")]
    assert [e.split()[2].rstrip(":") for e in events] == ["section", "phase_start", "phase_end", "phase_start",
                                                          "phase_end", "finish"], events
    assert events[2].endswith("IF(V>4.1S) STOP_FAZE") and events[4].endswith("IF(I<0.1A) STOP_FAZE")
    assert events[-1].endswith("finish: end of macro")
    # the curve: the charge's samples, both phases, a current flowing, the charge counted
    samples = [line.split() for line in lines if line.startswith("  ") and " charge " in line]
    assert {s[2] for s in samples} >= {"1/1", "2/1"}
    assert max(float(s[5]) for s in samples) > 0.5
    with open(session, newline="") as f:
        rows = list(csv.DictReader(f))
    assert any(r["event"] == "finish: end of macro" for r in rows)
    assert any(r["section"] == "charge" and float(r["mah_in"] or 0) > 0 for r in rows)


def test_without_the_receive_wire_a_request_gets_no_answer_and_the_stream_goes_on(image, two_macros):
    sim = B6(image, "--no-rx", "--eeprom", two_macros, "--speed", "0")
    try:
        fd = os.open(sim.port, os.O_RDWR | os.O_NOCTTY)
        tty.setraw(fd)
        parser = FrameParser(m.DEVICE_TYPES)
        os.write(fd, encode_frame(m.IDENTIFY, 1))
        lcd = []
        while len(lcd) < 4:                        # both lines twice: two rounds of the display after the request
            frames = parser.feed(os.read(fd, 256))
            assert all(f.type in (m.TELEMETRY, m.EVENT, m.LCD) for f in frames), frames
            lcd += [f for f in frames if f.type == m.LCD]
        os.close(fd)
    finally:
        sim.stop()


def test_without_the_receive_wire_cell_4_bleeds(image, two_macros):
    sim = B6(image, "--no-rx", "--eeprom", two_macros, "--cells", "4", "--soc", "0.9", "--capacity", "20",
             "--cell-spread", "60", "--speed", "0", "--lcd", "--press", "start@0.3:0.7")
    try:
        sim.wait_line(lambda line: line.startswith("BALANCER|") and int(line.split("|")[2]) & 8)
    finally:
        sim.stop()


def test_with_the_receive_wire_the_lcd_and_identify_say_cell_4_is_not_balanced(image, two_macros):
    sim = B6(image, "--eeprom", two_macros, "--cells", "4", "--speed", "0", "--lcd")
    try:
        sim.wait_line("LCD|1 Bench|l 4 not balanced")      # the idle line's end, scrolled
        client = ChargerClient(sim.port, timeout=10)
        try:
            assert "cell 4 not balanced" in client.info.firmware
            assert [s.name for s in client.slots()] == ["Bench", "LiPo"]
        finally:
            client.close()
        slots = subprocess.run([sys.executable, "-m", "zuml_studio.cli.main", "slots", "--port", sim.port],
                               capture_output=True, text=True, cwd=ROOT)
        assert slots.returncode == 0 and "(RX on PD0: cell 4 not balanced)" in slots.stdout, slots.stdout
    finally:
        sim.stop()


def test_once_a_host_has_spoken_the_display_is_not_sent(image, two_macros):
    sim = B6(image, "--eeprom", two_macros, "--speed", "0")
    try:
        fd = os.open(sim.port, os.O_RDWR | os.O_NOCTTY)
        tty.setraw(fd)
        parser = FrameParser(m.DEVICE_TYPES)
        seen: list[int] = []
        while m.LCD not in seen:                    # before: the display goes out unasked
            seen += [f.type for f in parser.feed(os.read(fd, 256))]
        os.write(fd, encode_frame(m.IDENTIFY, 9))
        while seen.count(m.TELEMETRY) < 20:         # four seconds of telemetry after the answer
            frames = parser.feed(os.read(fd, 256))
            if m.IDENTIFY | m.RESPONSE_FLAG in seen:
                assert m.LCD not in [f.type for f in frames]
            seen += [f.type for f in frames]
            if m.IDENTIFY | m.RESPONSE_FLAG not in seen:
                seen = [t for t in seen if t != m.TELEMETRY]
        os.close(fd)
    finally:
        sim.stop()


@needs(AVRDUDE)
def test_macros_flashed_through_the_programmer_run_from_the_buttons_and_are_watched_listen_only(image, tmp_path):
    """Issue 32's "done when", end to end: `zuml flash --programmer` (the real avrdude, the emulated STK500v1
    chip holding the real image) writes two macros and refuses an E303 one, leaving the templates and the
    calibration byte-identical; the simulated B6 without a receive wire, started on that EEPROM, runs the first
    macro from its buttons while `zuml monitor` (listen-only) shows its curve and its end reason."""
    from stk500_chip import Atmega32, Stk500Programmer
    from zuml_studio.device.install.avr_install import FLASH_SIZE, ihex_bytes
    from zuml_studio.device.install.isp_store import TEMPLATES_AT

    # the EEPROM as the firmware leaves it (its templates stored, the simulated board's calibration)
    first = tmp_path / "first.bin"
    sim = B6(image, "--eeprom", first, "--speed", "0")
    try:
        with ChargerClient(sim.port, timeout=10) as client:
            assert client.list_templates() == [1, 2, 3]
    finally:
        sim.stop()
    as_left = first.read_bytes()
    chip = Atmega32(flash=bytearray(ihex_bytes(image.with_suffix(".hex").read_text(), FLASH_SIZE)),
                    eeprom=bytearray(as_left), lfuse=0x3F, hfuse=0xC9)
    hot = tmp_path / "hot.zuml"
    hot.write_text(HOT_LIION)
    zuml = [sys.executable, "-m", "zuml_studio.cli.main", "flash", "--programmer", "stk500v1", "--port"]
    with Stk500Programmer(chip) as programmer:
        done = subprocess.run([*zuml, programmer.port, str(ROOT / "macros" / "LiPo.zuml"),
                               str(ROOT / "macros" / "NiMh.zuml")], capture_output=True, text=True, cwd=ROOT)
        assert done.returncode == 0, done.stderr
        refused = subprocess.run([*zuml, programmer.port, str(hot)], capture_output=True, text=True, cwd=ROOT)
        assert refused.returncode == 1 and "E303" in refused.stdout + refused.stderr
    assert bytes(chip.eeprom[TEMPLATES_AT:]) == as_left[TEMPLATES_AT:]     # templates and calibration untouched
    written = tmp_path / "written.bin"
    written.write_bytes(bytes(chip.eeprom))

    sim = B6(image, "--no-rx", "--eeprom", written, "--cells", "3", "--soc", "0.9", "--capacity", "20",
             "--speed", "0", "--lcd")
    monitor = Monitor("--driver", "zuml-tx", "--port", sim.port, "--until-end")
    try:
        monitor.wait_line(lambda line: line.startswith("LCD |1 LiPo"))
        sim.press("start", 0.7)
        sim.wait_line("PRESS|start|")
        assert monitor.proc.wait(timeout=LINE_WAIT_S) == 0, monitor.proc.stderr.read()
    finally:
        if monitor.proc.poll() is None:
            monitor.proc.terminate()
        sim.stop()
    events = [line for line in monitor.lines if line.startswith("*")]
    assert events[-1].endswith("finish: end of macro"), events
    assert any(e.endswith("IF(I<0.1A) STOP_FAZE") for e in events), events
    samples = [line.split() for line in monitor.lines if line.startswith("  ") and " charge " in line]
    assert samples and max(float(s[5]) for s in samples) > 0.5
