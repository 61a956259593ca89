"""Graupner Ultramat / Ultra Duo Plus / Ultra Trio Plus: ``0x0C`` + ASCII hex + 4 hex checksum
chars + ``0x0D``, 9600 baud, sent unsolicited.

The checksum is the sum of the ASCII payload characters; some firmwares add a constant
(Ultramat18 +0x180, Ultra Duo Plus 45 +0x480, as DataExplorer learns it): only a model's
known offset is accepted, never one learned from the line. Field layouts (``LAYOUTS``, indices
into the frame counting the 0x0C, as ``shared/realdata/ultramat.md`` and DataExplorer's
``Ultramat18``/``UltraDuoPlus45.convertDataBytes`` give them):

* 52 bytes (Ultramat 12/16/16S): Vin, V, I, capacity, 6 cells; no state, so no direction:
  the section is "".
* 78 bytes (Ultramat 18): Vin, mode (0 none, 1 charge, 2 discharge, 3 pause, 4 done,
  5 error, 6 balance, 11/12 storage charge/discharge), cycle, V, I, capacity, 12 cells.
* 146 bytes (Ultra Duo Plus 45): two outlets, each with Vin, mode (0 none, 1 charge,
  2 discharge, 3 delay, 4 pause, 5 done, 6 error, 7 balancer, 8 tyre heater, 9 motor),
  V, I, capacity, battery temperature (0.1°, a sign field "00" for below zero, a unit field
  1 for Fahrenheit) and 14 (outlet 1) or 4 (outlet 2) cells. One outlet is read: the first
  that runs a program (its frames before that carry no sample: ``skipped``).

Frames of the other models are checked and counted but carry no sample (``skipped``).
The current is sent unsigned: a discharging mode makes it negative. The frame has no time:
frame k (every valid one counted) is at k s."""
from __future__ import annotations

from dataclasses import dataclass

from .frame_scanner import INVALID, SKIP, FrameDecoder
from .stream_decoder import Reading

STEP_S = 1.0
# frame length (with 0x0C and 0x0D) -> accepted checksum offsets
LENGTHS = {52: (0,), 56: (0,), 70: (0,), 78: (0x180, 0), 106: (0,), 114: (0,), 124: (0,), 138: (0,),
           140: (0,), 146: (0x480, 0)}
_HEX = frozenset(b"0123456789ABCDEFabcdef")


@dataclass(frozen=True)
class Outlet:
    """Where one outlet's fields start in the frame (None: not sent) and its mode table."""
    mode: int | None
    voltage: int
    current: int
    capacity: int
    cells: int
    n_cells: int
    modes: dict | None = None           # mode -> (state, section, running, paused)
    temp: int | None = None             # value, then sign (2 chars) and unit (2 chars)


_DONE = ("done", "", False, False)
ULTRAMAT18_MODES = {0: ("idle", "", False, False), 1: ("charging", "charge", True, False),
                    2: ("discharging", "discharge", True, False), 3: ("pause", "", True, True), 4: _DONE,
                    5: ("error", "", False, False), 6: ("balancing", "", True, False),
                    11: ("storage charge", "charge", True, False), 12: ("storage discharge", "discharge", True, False)}
DUO_PLUS_MODES = {0: ("idle", "", False, False), 1: ("charging", "charge", True, False),
                  2: ("discharging", "discharge", True, False), 3: ("delay", "", True, True),
                  4: ("pause", "", True, True), 5: _DONE, 6: ("error", "", False, False),
                  7: ("balancing", "", True, False), 8: ("tyre heater", "", True, False), 9: ("motor", "", True, False)}
LAYOUTS: dict[int, tuple[Outlet, ...]] = {
    52: (Outlet(None, 11, 15, 19, 23, 6),),
    78: (Outlet(9, 13, 17, 21, 25, 12, ULTRAMAT18_MODES),),
    146: (Outlet(15, 21, 25, 29, 41, 14, DUO_PLUS_MODES, temp=33),
          Outlet(101, 105, 109, 113, 125, 4, DUO_PLUS_MODES, temp=117)),
}


def _word(buf: bytes, at: int, size: int = 4) -> int:
    return int(buf[at:at + size], 16)


def _mode(frame: bytes, o: Outlet) -> tuple[str, str, bool, bool]:
    """(state, section, running, paused) of the outlet's mode field; ValueError: no such mode."""
    mode = _word(frame, o.mode, 2)
    if mode not in o.modes:
        raise ValueError(f"mode {mode}")
    return o.modes[mode]


class UltramatDecoder(FrameDecoder):
    name = "ultramat"
    starts = b"\x0c"
    max_record = max(LENGTHS)

    def __init__(self) -> None:
        super().__init__()
        self._count = 0
        self._outlet: dict[int, int] = {}      # frame length -> the outlet read (chosen once)

    def frame(self, buf: bytearray, at: int):
        i = at + 1
        n = len(buf)
        limit = min(n, at + self.max_record)
        while i < limit and buf[i] in _HEX:
            i += 1
        if i >= n:
            return None if i - at < self.max_record else (INVALID, None)
        if buf[i] != 0x0D:
            return INVALID, None
        length = i - at + 1
        offsets = LENGTHS.get(length)
        if offsets is None:
            return INVALID, None
        payload = bytes(buf[at + 1:i - 4])
        got = int(bytes(buf[i - 4:i]), 16)
        if (got - sum(payload)) & 0xFFFF not in offsets:
            return INVALID, None
        t = self._count * STEP_S
        self._count += 1
        outlet = self._pick(length, bytes(buf[at:at + length]))
        if outlet is None:
            return length, SKIP
        return length, self._reading(bytes(buf[at:at + length]), outlet, t)

    def _pick(self, length: int, frame: bytes) -> Outlet | None:
        """The outlet this model's frames are read from: the only one, or the first that runs."""
        outlets = LAYOUTS.get(length)
        if not outlets:
            return None
        if length not in self._outlet:
            running = [k for k, o in enumerate(outlets) if o.mode is None or _mode(frame, o)[2]]
            if not running:
                return None
            self._outlet[length] = running[0]
        return outlets[self._outlet[length]]

    @staticmethod
    def _reading(frame: bytes, o: Outlet, t: float) -> Reading:
        state, section, running, paused = "running", "", True, False
        if o.modes is not None:
            state, section, running, paused = _mode(frame, o)
        amps = _word(frame, o.current) / 1000
        temp = None
        if o.temp is not None:
            temp = _word(frame, o.temp) / 10 * (-1 if frame[o.temp + 4:o.temp + 6] == b"00" else 1)
            if _word(frame, o.temp + 6, 2) == 1:
                temp = (temp - 32) / 1.8
        cells = tuple(_word(frame, o.cells + 4 * k) / 1000 for k in range(o.n_cells))
        return Reading(time_s=t, state=state, section=section, running=running, paused=paused,
                       voltage_v=_word(frame, o.voltage) / 1000,
                       current_a=-amps if section == "discharge" else amps,
                       charge_mah=float(_word(frame, o.capacity)), temp_c=temp, cells_v=cells,
                       task="discharge" if section == "discharge" else "charge")


def decoder() -> UltramatDecoder:
    return UltramatDecoder()
