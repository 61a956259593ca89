"""Calibrating an iMAX B6 running the ZUML firmware, from the PC: the host side of CAL_READ, CAL_WRITE,
CAL_MEASURE and CAL_OUTPUT (docs/protocol.md) and the procedure of docs/firmware.md (*Calibration*).

The charger's block: version 1, then per input (the order of ``INPUTS``) ``zero`` (the ADC16 reading at
0) and ``full`` (the value at ``zero`` + 65536: mV, mA or 0.01 °C), then an XOR check byte. Voltages
are calibrated from one point (zero 0), the currents from two. What the reference instruments read
comes from a ``Meter``: the user's multimeter in the CLI and the dialog, the model's truth in tests."""
from __future__ import annotations

import struct
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Protocol

from ...errors import ZumlError
from ...i18n import _
from ...protocol.messages import BY_NAME, decode_response

INPUTS = ("Vout+", "Vout-", "I discharge", "I smps", "Vin", "Vb0", "Vb1", "Vb2", "Vb3", "Vb4", "Vb5", "Vb6",
          "T extern")
VOUT, VOUT_MINUS, IDIS, ISMPS, VIN, VB0, VB1, VB2 = range(8)
VERSION = 1
BLOCK_SIZE = 2 + 4 * len(INPUTS)
FULL_SCALE = 65536
OFF, CHARGE, DISCHARGE = 0, 1, 2
# The two points of each current (mA), as docs/firmware.md's procedure takes them (cheali's points).
CURRENT_POINTS = {CHARGE: (100, 1000), DISCHARGE: (50, 300)}
SETTLE_TOLERANCE = 0.005        # two whole-second averages this close: the output has settled
# How far a meter's reading may be from the charger's own (docs/firmware.md, *Calibration*): the firmware
# takes a calibration only within 3 % of the nominal one for a voltage and 8 % for a current, so the one
# in use and the new one are at most twice that apart; at the 50 and 100 mA points the amplifiers' offset
# (a quarter of the window at 0) adds up to 20 mA.
VOLTAGE_AGREES = 0.06
CURRENT_AGREES = 0.16
CURRENT_SLACK_MA = 20
# With the output off the taps and the output see the same pack: its cells add up to it within the
# meter's and the wires' error.
CELLS_ADD_UP = 0.03
CELL_PRESENT_MV = 1000          # the firmware's: a tap above this carries a cell
MAX_CELLS = 6
ZERO_BELOW_0_KEPT = 64          # ADC16 counts: one 10-bit step
SETTLE_SECONDS = 15
EXTRA_S = 1.0                   # seconds added to each request's wait for its answer
POLL_S = 0.1                    # how often the charger's clock is asked while waiting for a second to end


class CalibrationError(ZumlError):
    """A one-line reason the calibration stopped (nothing was written unless it says so)."""


@dataclass(frozen=True)
class Block:
    pairs: tuple[tuple[int, int], ...]          # (zero, full) per input

    def encode(self) -> bytes:
        body = bytes((VERSION,)) + b"".join(struct.pack("<HH", zero, full) for zero, full in self.pairs)
        return body + bytes((check_byte(body),))

    @classmethod
    def decode(cls, data: bytes) -> Block:
        if len(data) != BLOCK_SIZE:
            raise CalibrationError(_("a calibration block is {size} bytes, not {n}").format(size=BLOCK_SIZE,
                                                                                         n=len(data)))
        if data[0] != VERSION or check_byte(data[:-1]) != data[-1]:
            raise CalibrationError(_("the calibration block's version or check byte is wrong"))
        return cls(tuple(struct.unpack_from("<HH", data, 1 + 4 * k) for k in range(len(INPUTS))))

    def value(self, input_no: int, adc16: int) -> float:
        zero, full = self.pairs[input_no]
        return (adc16 - zero) * full / FULL_SCALE

    def replaced(self, input_no: int, zero: int, full: int) -> Block:
        if not (0 <= zero < FULL_SCALE and 0 < full < FULL_SCALE):
            raise CalibrationError(_("{input}: the readings give a calibration the charger cannot store (check the "
                                     "meter's readings)").format(input=INPUTS[input_no]))
        return Block(self.pairs[:input_no] + ((zero, full),) + self.pairs[input_no + 1:])


def check_byte(data: bytes) -> int:
    x = 0
    for byte in data:
        x ^= byte
    return x


@dataclass(frozen=True)
class Reading:
    adc16: int          # the input's average over the last whole second, 10-bit × 64
    value: int          # through the present calibration: mV, mA or 0.01 °C


def voltage_point(mv: float, adc16: int) -> tuple[int, int]:
    """(zero, full) of a voltage input (zero 0) that reads ``mv`` at ``adc16``."""
    if adc16 <= 0:
        raise CalibrationError(_("the charger reads 0 on that input: is it connected?"))
    return 0, round(mv * FULL_SCALE / adc16)


def current_points(low: tuple[float, int], high: tuple[float, int]) -> tuple[int, int]:
    """(zero, full) of a current input from two (meter mA, ADC16) points."""
    (i1, a1), (i2, a2) = low, high
    if a2 <= a1 or i2 <= i1:
        raise CalibrationError(_("the two current points do not rise (the meter read {i1:g} mA, then {i2:g} mA): "
                                 "is the ammeter in series with the battery?").format(i1=i1, i2=i2))
    full = (i2 - i1) * FULL_SCALE / (a2 - a1)
    zero = round(a1 - i1 * FULL_SCALE / full)
    # The block stores zero unsigned: an amplifier offset a little below 0 (seen on the discharge input)
    # is stored as 0, off by under a count's worth of current; a larger one means a wrong reading.
    return (0 if -ZERO_BELOW_0_KEPT <= zero < 0 else zero), round(full)


def parse_cells(text: str) -> list[float] | None:
    """The cells' volts as typed (``3.91,3.92,3.90``, or with ``;`` and decimal commas), cell 1 first, in mV;
    None for "keep" (empty or ``none``). An empty item is refused: the cells after it would shift. The
    error says what is wrong with the text; the caller names the field."""
    text = text.strip()
    if not text or text.lower() == "none":
        return None
    items = text.split(";") if ";" in text else text.split(",")
    if len(items) > MAX_CELLS:
        raise CalibrationError(_("the B6's balance port has at most 6 cells"))
    cells = []
    for number, item in enumerate(items, 1):
        item = item.strip()
        if not item:
            raise CalibrationError(_("item {n} is empty: give every cell from cell 1 on").format(
                n=number))
        try:
            volts = float(item.replace(",", "."))
        except ValueError:
            raise CalibrationError(_("{text!r} is not a number of volts").format(text=item)) from None
        if not 0 < volts <= 5:
            raise CalibrationError(_("cell {n}: {v:g} V is outside 0..5 V").format(n=number, v=volts))
        cells.append(volts * 1000)
    return cells


def balance_cells_mv(readings: list[Reading]) -> list[float]:
    """The cells the charger reads at its balance port, as the firmware computes them (cell 1 = Vb1 - Vb0,
    cell 2 = Vb2 - Vb1, cells 3..6 alone), as many in a row as carry a cell."""
    v = [r.value for r in readings]
    all_cells = [v[VB1] - v[VB0], v[VB2] - v[VB1]] + v[VB2 + 1:VB2 + 5]
    cells = []
    for mv in all_cells:
        if mv <= CELL_PRESENT_MV:
            break
        cells.append(float(mv))
    return cells


def _volts(mv: float) -> str:
    return f"{mv / 1000:.2f} V"


def _apart(a: float, b: float, share: float) -> bool:
    return abs(a - b) > share * max(abs(a), abs(b))


def check_voltages(readings: list[Reading], pack_mv: float, supply_mv: float | None,
                   cells_mv: list[float] | None) -> None:
    """The meter's voltages against what the charger reads and against each other, before any is used: a
    typo (1.17 V for 11.7 V, a cell missed) stops the calibration with a sentence in volts."""
    port = balance_cells_mv(readings)
    if cells_mv is not None and len(cells_mv) != len(port):
        raise CalibrationError(_("the cells: {n} entered, but the balance port shows {port}").format(
            n=len(cells_mv), port=len(port)))
    if _apart(pack_mv, readings[VOUT].value, VOLTAGE_AGREES):
        raise CalibrationError(_("the pack: {typed} entered, but the charger reads {reads} at its output (more than "
                                 "{pct} % apart): check the meter's reading").format(
            typed=_volts(pack_mv), reads=_volts(readings[VOUT].value), pct=round(VOLTAGE_AGREES * 100)))
    cells_sum = sum(cells_mv) if cells_mv else sum(port)
    if port and _apart(pack_mv, cells_sum, CELLS_ADD_UP):
        raise CalibrationError(_("the pack: {typed} entered, but its cells add up to {sum}: check the meter's "
                                 "reading").format(typed=_volts(pack_mv), sum=_volts(cells_sum)))
    if supply_mv is not None and _apart(supply_mv, readings[VIN].value, VOLTAGE_AGREES):
        raise CalibrationError(_("the supply: {typed} entered, but the charger reads {reads} at its input (more "
                                 "than {pct} % apart): check the meter's reading").format(
            typed=_volts(supply_mv), reads=_volts(readings[VIN].value), pct=round(VOLTAGE_AGREES * 100)))
    for number, (typed, reads) in enumerate(zip(cells_mv or [], port), 1):
        if _apart(typed, reads, VOLTAGE_AGREES):
            raise CalibrationError(_("cell {n}: {typed} entered, but the charger reads {reads} (more than {pct} % "
                                     "apart): check the meter's reading").format(
                n=number, typed=_volts(typed), reads=_volts(reads), pct=round(VOLTAGE_AGREES * 100)))


def check_current(mode: int, entered_ma: float, reading_ma: float) -> None:
    """The ammeter's reading against the current the charger reads it holds."""
    if abs(entered_ma - reading_ma) > CURRENT_AGREES * abs(reading_ma) + CURRENT_SLACK_MA:
        what = _("charging") if mode == CHARGE else _("discharging")
        raise CalibrationError(_("the ammeter: {typed:.3f} A entered, but the charger reads {reads:.3f} A {what} "
                                 "(more than {pct} % apart): check the meter's reading").format(
            typed=entered_ma / 1000, reads=reading_ma / 1000, what=what, pct=round(CURRENT_AGREES * 100)))


class Meter(Protocol):
    """The reference instruments: what the user's meter reads (None: not measured, keep the value)."""

    def pack_mv(self) -> float: ...

    def supply_mv(self) -> float | None: ...

    def cells_mv(self) -> list[float] | None: ...

    def current_ma(self, mode: int, asked_ma: int) -> float: ...


class Calibrator:
    """The charger's requests over a ChargerClient (device/zuml/client.py)."""

    def __init__(self, client, say: Callable[[str], None] = lambda line: None):
        self.client = client
        self.say = say

    def _request(self, name: str, payload: bytes = b"", response_len: int = 64) -> bytes:
        # A charger busy with its stage (or a simulated one slower than real time) may answer late; a
        # calibration is not in a hurry.
        return self.client.request(name, payload, response_len=response_len, extra_s=EXTRA_S)

    def uptime_s(self) -> float:
        """The charger's own clock (STATUS)."""
        return decode_response(BY_NAME["STATUS"].code, self._request("STATUS"))["uptime_ms"] / 1000

    def read(self) -> tuple[bool, Block]:
        answer = self._request("CAL_READ", response_len=1 + BLOCK_SIZE)
        return bool(answer[0]), Block.decode(answer[1:])

    def measure(self) -> list[Reading]:
        answer = self._request("CAL_MEASURE", response_len=6 * len(INPUTS))
        if len(answer) != 6 * len(INPUTS):
            raise CalibrationError(_("the charger's CAL_MEASURE answer is {n} bytes, not {size}").format(
                n=len(answer), size=6 * len(INPUTS)))
        return [Reading(*struct.unpack_from("<Hi", answer, 6 * k)) for k in range(len(INPUTS))]

    def output(self, mode: int, current_ma: int = 0) -> None:
        self._request("CAL_OUTPUT", struct.pack("<BH", mode, current_ma), response_len=3)

    def write(self, block: Block) -> Block:
        answer = self._request("CAL_WRITE", block.encode(), response_len=1 + BLOCK_SIZE)
        stored = Block.decode(answer[1:])
        if not answer[0] or stored != block:
            raise CalibrationError(_("the charger did not keep the calibration block it was sent"))
        return stored

    def after_next_second(self) -> list[Reading]:
        """The readings of the first whole second of the charger's clock that starts after now."""
        due = int(self.uptime_s()) + 2
        while self.uptime_s() < due:
            time.sleep(POLL_S)
        return self.measure()

    def settled(self, input_no: int) -> Reading:
        """The input's reading once two whole-second averages in a row agree (the output has settled)."""
        last = self.after_next_second()[input_no]
        for _try in range(SETTLE_SECONDS):
            now = self.after_next_second()[input_no]
            if abs(now.adc16 - last.adc16) <= max(2, SETTLE_TOLERANCE * last.adc16):
                return now
            last = now
        raise CalibrationError(_("{input} does not settle: the output is not steady").format(input=INPUTS[input_no]))

    def run(self, meter: Meter) -> Block:
        """The whole procedure; the block written (the output is off at the end, whatever happened)."""
        _calibrated, block = self.read()
        self.say(_("Measuring the voltages…"))
        readings = self.after_next_second()
        pack, supply, cells = meter.pack_mv(), meter.supply_mv(), meter.cells_mv()
        if cells is not None and len(cells) > MAX_CELLS:
            raise CalibrationError(_("the B6's balance port has at most 6 cells"))
        check_voltages(readings, pack, supply, cells)
        block = block.replaced(VOUT, *voltage_point(pack, readings[VOUT].adc16))
        if supply is not None:
            block = block.replaced(VIN, *voltage_point(supply, readings[VIN].adc16))
        for k, mv in enumerate(cells or []):
            # Vb1 and Vb2 are taps to ground (cell 1, cells 1 + 2); Vb3..Vb6 are cells 3..6 alone.
            total = sum(cells[:k + 1]) if k < 2 else mv
            block = block.replaced(VB1 + k, *voltage_point(total, readings[VB1 + k].adc16))
        try:
            for mode, input_no in ((CHARGE, ISMPS), (DISCHARGE, IDIS)):
                points = []
                for asked in CURRENT_POINTS[mode]:
                    self.say((_("Charging at {ma} mA: waiting for it to settle…") if mode == CHARGE else
                              _("Discharging at {ma} mA: waiting for it to settle…")).format(ma=asked))
                    self.output(mode, asked)
                    reading = self.settled(input_no)
                    entered = meter.current_ma(mode, asked)
                    check_current(mode, entered, reading.value)
                    points.append((entered, reading.adc16))
                block = block.replaced(input_no, *current_points(*points))
        finally:
            self.output(OFF)
        self.say(_("Writing the calibration to the charger…"))
        return self.write(block)
