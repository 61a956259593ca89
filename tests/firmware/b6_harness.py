"""The simulated iMAX B6 (`firmware/build/simavr/zuml_b6_sim`) as tests drive it: started on an image, its pty
on the first stdout line, its stderr lines (`LCD|…`, `FAULT|…`, `RESET|…`) collected as they come so a test
waits for a line, never for a time; its trace read back as rows."""
from __future__ import annotations

import csv
import os
import select
import subprocess
import termios
import threading
import time
import tty
from dataclasses import dataclass
from pathlib import Path


from tools import SIMAVR, skip_unless
from host_core import FIRMWARE
from zuml_studio.protocol import messages as m
from zuml_studio.protocol.frames import FrameParser, encode_frame
from zuml_studio.device.zuml.client import ChargerClient

B6_SIM = FIRMWARE / "build" / "simavr" / "zuml_b6_sim"
LINE_WAIT_S = 120.0        # a bound on a wait for a line, far above any run here: a hang fails, it does not wait
# The bound is on the simulator's own CPU time: a loaded machine stretches the wall time a run takes (60 s
# simulated took over 120 s of wall time under `stress-ng --cpu 2`), not the work it does. The wall time's
# backstop only catches a simulator that stopped being scheduled at all.
WALL_BACKSTOP_S = 15 * LINE_WAIT_S


def build(*targets: str) -> None:
    """`make` firmware targets (the harness, an image); skips naming the tools that are missing."""
    skip_unless(SIMAVR)
    done = subprocess.run(["make", "-s", "-C", str(FIRMWARE), *targets], capture_output=True, text=True)
    assert done.returncode == 0, done.stdout + done.stderr


@dataclass
class Row:
    t_ms: int
    buck_duty: float
    boost_duty: float
    output_enabled: int
    current_a: float
    voltage_v: float
    cell_max_v: float          # the highest cell's true voltage


def read_trace(path: Path) -> list[Row]:
    with open(path, newline="") as f:
        reader = csv.reader(f)
        assert next(reader) == ["t_ms", "buck_duty", "boost_duty", "output_enabled", "current_a", "voltage_v",
                                "cell_max_v"]
        return [Row(int(r[0]), float(r[1]), float(r[2]), int(r[3]), float(r[4]), float(r[5]), float(r[6]))
                for r in reader]


def rx_at(seconds: float, name: str, seq: int, **fields) -> tuple[str, str]:
    """The option that makes a PC request (`name` with its fields) reach the B6's receiver at simulated
    `seconds`, whatever the host's speed: `--rx HEX@SECONDS`. `seq` tells its answer apart (`B6.answers`)."""
    frame = encode_frame(m.BY_NAME[name].code, seq, m.encode_request(name, **fields))
    return "--rx", f"{frame.hex()}@{seconds}"


def start_at(seconds: float, cells: int, capacity_mah: int = 2000, seq: int = 7) -> tuple[str, str]:
    """The PC's START of slot 1's charge (`cells` in series), reaching the B6 at simulated `seconds`."""
    return rx_at(seconds, "START", seq, slot=0, task=0, repetitions=1, capacity_mah=capacity_mah, current_ma=0,
                 voltage_mv=0, series=cells, sensor=1)


class B6:
    """One zuml_b6_sim process; `port` its pty, `lines` what it said on stderr so far."""

    def __init__(self, elf: Path, *args: str):
        self.proc = subprocess.Popen([str(B6_SIM), str(elf), *map(str, args)], stdin=subprocess.PIPE,
                                     stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        self.port = self.proc.stdout.readline().rstrip("\n")
        self.lines: list[str] = []
        self.changed = threading.Condition()
        self.reader = threading.Thread(target=self._read, daemon=True)
        self.reader.start()
        self.fd = None

    def _read(self) -> None:
        for line in self.proc.stderr:
            with self.changed:
                self.lines.append(line.rstrip("\n"))
                self.changed.notify_all()
        with self.changed:
            self.lines.append("<exit>")
            self.changed.notify_all()

    def _cpu_s(self) -> float:
        """The simulator's CPU seconds so far (0 once it has exited or where /proc is missing)."""
        try:
            with open(f"/proc/{self.proc.pid}/stat") as f:
                fields = f.read().rpartition(")")[2].split()
        except OSError:
            return 0.0
        return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")

    def _patience(self):
        """A test for "waited too long": LINE_WAIT_S of the simulator's CPU time, or the wall time's backstop."""
        wall, cpu = time.monotonic(), self._cpu_s()
        return lambda: (self._cpu_s() - cpu > LINE_WAIT_S or time.monotonic() - wall > WALL_BACKSTOP_S)

    def _readable(self, what: str) -> None:
        """Wait until the pty has bytes to read, as patiently as `_patience` says."""
        expired = self._patience()
        while not select.select([self.fd], [], [], 1.0)[0]:
            assert not expired(), f"{what} after {LINE_WAIT_S} s of the simulator's CPU time"

    def wait_line(self, predicate, start: int = 0) -> tuple[int, str]:
        """The first stderr line from index `start` on that satisfies `predicate` (a prefix or a function)."""
        test = (lambda line: line.startswith(predicate)) if isinstance(predicate, str) else predicate
        expired = self._patience()
        with self.changed:
            while not self.changed.wait_for(
                    lambda: any(test(line) or line == "<exit>" for line in self.lines[start:]), timeout=1.0):
                assert not expired(), (f"no line for {predicate!r} in {LINE_WAIT_S} s of the simulator's CPU time: "
                                       f"{self.lines[-10:]}")
            for k in range(start, len(self.lines)):
                if test(self.lines[k]):
                    return k, self.lines[k]
        raise AssertionError(f"the simulator ended before {predicate!r}: {self.lines[-10:]}")

    def press(self, button: str, hold_s: float = 0.2) -> None:
        """A front-panel button pressed now, live (the simulator's stdin; it answers PRESS|…)."""
        self.proc.stdin.write(f"{button} {hold_s}\n")
        self.proc.stdin.flush()

    def ask(self, request: str) -> str:
        """One probe request on the pty (tests/firmware/b6_probe.c), its answer line."""
        if self.fd is None:
            self.fd = os.open(self.port, os.O_RDWR | os.O_NOCTTY)
            tty.setraw(self.fd)
        os.write(self.fd, request.encode())
        answer = b""
        while not answer.endswith(b"\n"):
            self._readable(f"no answer to {request!r}: {answer!r}")
            answer += os.read(self.fd, 64)
        return answer.decode().strip()

    def answers(self, count: int) -> dict[int, dict]:
        """The next `count` answers to --rx requests on the pty, decoded, by their seq ({"error": (request, code, text)} for a refusal; telemetry and events skipped)."""
        if self.fd is None:
            self.fd = os.open(self.port, os.O_RDWR | os.O_NOCTTY)
            tty.setraw(self.fd, termios.TCSANOW)        # not TCSAFLUSH: an answer already waiting is kept
        parser, got = FrameParser(), {}
        while len(got) < count:
            self._readable(f"no answer after {sorted(got)}")
            for frame in parser.feed(os.read(self.fd, 256)):
                if frame.type == m.ERROR:
                    got[frame.seq] = {"error": m.decode_error(frame.payload)}
                elif frame.type & m.RESPONSE_FLAG:
                    got[frame.seq] = m.decode_response(frame.type & 0x7F, frame.payload)
        return got

    def stop(self) -> None:
        if self.proc.stdin and not self.proc.stdin.closed:
            self.proc.stdin.close()
        if self.fd is not None:
            os.close(self.fd)
            self.fd = None
        if self.proc.poll() is None:
            self.proc.terminate()
        self.proc.wait(timeout=30)
        self.reader.join(timeout=30)

def switched_on(line: str) -> bool:
    """The stage switched on by the firmware (not the instant at power-up before its first instructions)."""
    return line.startswith("OUTPUT|on|") and float(line.split("|")[2]) > 0.01


def started(sim, task: str, cells: int, capacity_mah: int = 2000) -> None:
    """The macro in slot 1 started from the PC."""
    client = ChargerClient(sim.port, timeout=10)
    try:
        client.start(0, task, capacity_mah=capacity_mah, series=cells)
    finally:
        client.close()


def trace_rows(sim) -> list[Row]:
    """The trace's complete rows so far (the harness writes it while the test reads)."""
    lines = sim.trace.read_text().splitlines()[1:]
    return [Row(int(r[0]), *map(float, r[1:3]), int(r[3]), *map(float, r[4:7]))
            for r in (line.split(",") for line in lines[:-1])]
