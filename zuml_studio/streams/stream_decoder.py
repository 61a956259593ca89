"""What every monitor-only charger driver shares: counters, the step from one decoded record
to a ``Telemetry`` sample, and the framing of ``$``-lines.

A driver decodes the charger's record into a ``Reading`` (what the charger said, in SI units);
``StreamDecoder.sample`` turns it into the ``Telemetry`` our own protocol yields, so the live
plot, phase bands, session CSV and ``zuml monitor`` work unchanged:

* ``run`` counts the charger's state changes (a new band whenever the state or the section
  changes while a program runs); ``phase`` counts the bands of the same section;
* the charger's one capacity counter counts into ``mah_in`` while charging and into
  ``mah_out`` while discharging; each phase's count is banked when the next starts
  (``charge_counter.ChargeCounter``, the log readers' rule too), so both are totals.

Decoders never raise on bytes: a record that fails its checksum, its shape or a range check
is counted in ``bad`` and dropped; a well-formed record that carries no measurement (debug
channel, IR record, a reply to another command) is counted in ``skipped``. Partial records
are capped (``max_record``), so garbage without a terminator cannot grow memory.
"""
from __future__ import annotations

from dataclasses import dataclass

from .charge_counter import ChargeCounter
from ..protocol.messages import Telemetry
from ..i18n import _


@dataclass(frozen=True)
class Reading:
    """One record as the charger reported it, in SI units."""

    time_s: float
    state: str                     # the charger's own name for its state ("charging", "done", ...)
    section: str                   # "charge" | "discharge" | "" (neither, or not told)
    running: bool
    voltage_v: float
    current_a: float               # signed: + charge, - discharge
    temp_c: float | None = None    # battery (external) sensor
    heatsink_c: float | None = None
    charge_mah: float | None = None
    cells_v: tuple[float, ...] = ()
    paused: bool = False
    task: str = "charge"           # charge | discharge | train (what the program is, for the panel)
    # The counter carries its own sign (negative: discharged). Otherwise it counts up in either
    # direction and the section signs it.
    charge_signed: bool = False


class StreamDecoder:
    """Base of every driver decoder: ``feed(bytes) -> list[Telemetry]``."""

    name = ""
    max_record = 512               # bytes a partial record may hold before it is dropped as garbage

    def __init__(self) -> None:
        self.good = 0
        self.bad = 0
        self.skipped = 0
        self._key: tuple[str, str] | None = None
        self._run = 0
        self._phase_of: dict[str, int] = {}
        self._phase = 0
        self._charge = ChargeCounter()

    def feed(self, data: bytes) -> list[Telemetry]:
        raise NotImplementedError

    @property
    def pending(self) -> int:
        """Bytes held for a record not complete yet (at most ``max_record``)."""
        return len(self._buf)

    def take_extras(self) -> list[tuple[str, object]]:
        """What the charger said besides samples since the last call: ``("event", DeviceEvent)`` and
        ``("lcd", (line1, line2))`` (the ZUML firmware's listen-only stream); none for the others."""
        return []

    def sample(self, r: Reading) -> Telemetry:
        key = (r.state, r.section)
        if r.running and key != self._key:
            self._run += 1
            if r.section:
                self._phase_of[r.section] = self._phase_of.get(r.section, 0) + 1
                self._phase = self._phase_of[r.section]
            else:
                self._phase = 0
        self._key = key if r.running else None
        if r.charge_mah is not None and r.charge_signed:
            self._charge.add(r.charge_mah)
        elif r.charge_mah is not None and r.section:
            self._charge.add(abs(r.charge_mah) if r.section == "charge" else -abs(r.charge_mah))
        mah_in, mah_out = self._charge.totals
        return Telemetry(
            time_s=r.time_s, task=r.task, section=r.section if r.running else "", repetition=0, cycle=0,
            phase=self._phase if r.running else 0, run=self._run if r.running else 0, running=r.running,
            paused=r.paused, sensor=r.temp_c is not None, voltage_v=r.voltage_v, current_a=r.current_a,
            temp_c=r.temp_c, heatsink_c=r.heatsink_c, mah_in=mah_in, mah_out=mah_out, cells_v=r.cells_v,
            state=r.state)


def xor8(data: bytes) -> int:
    """The XOR of every byte: the halves of the bytes as one integer folded onto each other (a
    handful of big-integer steps instead of a Python step per byte: a day's capture is megabytes)."""
    x = int.from_bytes(data, "little")
    n = len(data)
    while n > 1:
        half = (n + 1) // 2
        x = (x & ((1 << (8 * half)) - 1)) ^ (x >> (8 * half))
        n = half
    return x


class DollarLineDecoder(StreamDecoder):
    """``$<ch>;...;<xor>\\r\\n`` lines (cheali-charger, Junsi iCharger LogView).

    The checksum is the XOR of every byte from ``$`` through the ``;`` before it, printed in
    decimal. Stray NULs and CRs are ignored; a ``$`` inside a line starts a new one (the part
    before it was torn). Subclasses implement ``record(fields) -> Reading | None`` (None:
    skipped) and raise ``ValueError`` for a record that does not fit."""

    max_record = 256

    def __init__(self) -> None:
        super().__init__()
        self._buf = bytearray()
        self._overlong = False     # the line being read passed max_record: only a '$' part after it may count

    def feed(self, data: bytes) -> list[Telemetry]:
        """The samples of the lines ``data`` completes. A serial port cuts its bytes anywhere: each
        line is judged as a whole, so the samples do not depend on the pieces. A line longer than
        ``max_record`` is one bad record; a ``$`` line at its end within the cap still counts (a
        line torn by garbage without a line end)."""
        out: list[Telemetry] = []
        start = 0
        while True:
            nl = data.find(b"\n", start)
            self._take(data[start:nl] if nl >= 0 else data[start:])
            if nl < 0:
                return out
            line = bytes(self._buf)
            self._buf.clear()
            if line or not self._overlong:
                self._line(line, out)
            self._overlong = False
            start = nl + 1

    def _take(self, part: bytes) -> None:
        buf = self._buf
        if not self._overlong:
            buf += part
            if len(buf) <= self.max_record:
                return
            self.bad += 1
            self._overlong = True
            part = bytes(buf)
            buf.clear()
        dollar = part.rfind(b"$")
        if dollar >= 0:
            buf[:] = part[dollar:]
        elif buf:                      # the '$' part kept so far goes on
            buf += part
        if len(buf) > self.max_record:
            buf.clear()

    def _line(self, line: bytes, out: list[Telemetry]) -> None:
        line = line.replace(b"\x00", b"").replace(b"\r", b"").strip(b" \t")
        if not line:
            return
        start = line.rfind(b"$")
        if start != 0:
            if start < 0 and self.ignorable(line):
                self.skipped += 1
                return
            self.bad += 1                    # garbage, or the torn part before a new line
            if start < 0:
                return
            line = line[start:]
        body_end = line.rfind(b";")
        ck = line[body_end + 1:]
        if body_end < 2 or not ck.isdigit() or len(ck) > 3 or int(ck) != xor8(line[:body_end + 1]):
            self.bad += 1
            return
        try:
            text = line[1:body_end].decode("ascii")
            reading = self.record(text.split(";"))
        except (ValueError, IndexError, UnicodeDecodeError):
            self.bad += 1
            return
        if reading is None:
            self.skipped += 1
            return
        self.good += 1
        out.append(self.sample(reading))

    def ignorable(self, line: bytes) -> bool:
        """A line without ``$`` that is not garbage (a file header)."""
        return False

    def record(self, fields: list[str]) -> Reading | None:
        raise NotImplementedError


def integers(fields: list[str], lo: int = -(1 << 31), hi: int = (1 << 31) - 1) -> list[int]:
    """Decimal integers (no sign but '-', no spaces); ValueError otherwise or out of range."""
    out = []
    for f in fields:
        body = f[1:] if f.startswith("-") else f
        if not body.isdigit() or not body.isascii():
            raise ValueError(_("not an integer: {f!r}").format(f=f))
        v = int(f)
        if not lo <= v <= hi:
            raise ValueError(_("out of range: {v}").format(v=v))
        out.append(v)
    return out
