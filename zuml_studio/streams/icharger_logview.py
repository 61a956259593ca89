"""Junsi iCharger ``$``-lines: the LogView serial stream of the 106B/206B/208B/306B/3010B and
the DUO/X text-log lines (same framing and checksum), recognised by the time field.

* empty time field (older models, one line every 2 s): ``$ch;state;;Vin;Vbat;I;cell1..N;Tint;
  Text;mAh`` with N = 6, 8 or 10. The line carries no time: sample k is at ``2.0 * k`` s (the
  models' fixed LogView step, confirmed by the 2 s spacing of the recordings).
* time in ms (DUO/X): ``$ch;state;ms;type;cycle;I;Vin;Vbat;mAh;Tint;Text;cell1..N`` with
  N = 6, 8, 10 or 12. State 128 (internal resistance) and 130 (cell capacity) are skipped.

Current is in 10 mA, signed by the DUO/X (the section follows its sign in charge and
discharge states); the older models send it unsigned, so a discharging state makes it
negative; temperatures in 0.1 °C (0 = no sensor); a file header line
``@Model:…`` is skipped. Only the first channel seen is followed (a DUO logs ``$1`` and
``$2``); the other channel's lines are skipped.
"""
from __future__ import annotations

from .stream_decoder import DollarLineDecoder, Reading, integers
from ..i18n import _

LEGACY_STEP_S = 2.0
U16 = 0xFFFF
S16 = (-0x8000, 0x7FFF)           # the firmware's 16-bit signed fields (current, temperatures, DUO cells)

# state: name, section, running, paused
LEGACY_STATES = {
    1: ("charging", "charge", True, False), 2: ("discharging", "discharge", True, False),
    3: ("monitor", "", True, False), 4: ("waiting", "", True, True), 5: ("motor test", "", True, False),
    6: ("done", "", False, False), 7: ("error", "", False, False), 8: ("LiXX trickle", "charge", True, False),
    9: ("NiXX trickle", "charge", True, False), 10: ("foam cut", "", True, False), 11: ("info", "", False, False),
    12: ("ext. discharging", "discharge", True, False),
}
DUO_STATES = {
    0: ("normal", "", True, False), 1: ("charge", "charge", True, False), 2: ("discharge", "discharge", True, False),
    3: ("monitor", "", True, False), 4: ("wait", "", True, True), 5: ("precharge", "charge", True, False),
    6: ("done", "", False, False), 7: ("error", "", False, False), 8: ("trickle", "charge", True, False),
    9: ("balance only", "", True, False), 10: ("foam cut", "", True, False), 11: ("info", "", False, False),
    30: ("digital power", "", True, False),
}
SKIPPED_DUO_STATES = frozenset((128, 130))
LEGACY_CELLS = {15: 6, 17: 8, 19: 10}
DUO_CELLS = {17: 6, 19: 8, 21: 10, 23: 12}


def _temp(c10: int) -> float | None:
    return None if c10 == 0 else c10 / 10.0


def _direction(section: str, amps: float) -> str:
    """The charger signs its current: a charge state with a negative current (Storage brings a
    full pack down) is discharging."""
    if section and amps:
        return "charge" if amps > 0 else "discharge"
    return section


class IChargerLineDecoder(DollarLineDecoder):
    name = "icharger"

    def __init__(self) -> None:
        super().__init__()
        self.channel: str | None = None
        self._legacy_count = 0

    def ignorable(self, line: bytes) -> bool:
        return line.startswith(b"@")

    def record(self, fields: list[str]) -> Reading | None:
        if fields[0] not in ("1", "2"):
            raise ValueError(_("not a channel"))
        state = integers(fields[1:2], 0, 255)[0]
        if self.channel is not None and fields[0] != self.channel:
            integers(fields[1:2] + fields[3:])          # well-formed, just the other channel
            return None
        if fields[2] == "":
            reading = self._legacy(state, fields)
        elif state in SKIPPED_DUO_STATES:
            integers(fields[2:])
            reading = None
        else:
            reading = self._duo(state, fields)
        self.channel = fields[0]
        return reading

    def _legacy(self, state: int, fields: list[str]) -> Reading:
        n = LEGACY_CELLS.get(len(fields))
        if n is None or state not in LEGACY_STATES:
            raise ValueError(_("no legacy layout"))
        vin, vbat = integers(fields[3:5], 0, U16)
        (i10,) = integers(fields[5:6], *S16)
        cells = integers(fields[6:6 + n], 0, U16)
        tint, text = integers(fields[6 + n:8 + n], *S16)
        (mah,) = integers(fields[8 + n:9 + n])
        name, section, running, paused = LEGACY_STATES[state]
        if section == "discharge":
            i10 = -abs(i10)      # these models send the discharge current unsigned (306B recording)
        section = _direction(section, i10)
        t = self._legacy_count * LEGACY_STEP_S
        self._legacy_count += 1
        return Reading(t, name, section, running, vbat / 1000, i10 / 100, _temp(text),
                       _temp(tint), float(mah), tuple(c / 1000 for c in cells), paused,
                       "discharge" if section == "discharge" else "charge")

    def _duo(self, state: int, fields: list[str]) -> Reading:
        n = DUO_CELLS.get(len(fields))
        if n is None or state not in DUO_STATES:
            raise ValueError(_("no DUO/X layout"))
        (ms,) = integers(fields[2:3], 0, (1 << 32) - 1)
        integers(fields[3:5], 0, 255)                        # battery type, cycle
        (i10,) = integers(fields[5:6], *S16)
        _vin, vbat = integers(fields[6:8], 0, U16)
        (mah,) = integers(fields[8:9])
        tint, text = integers(fields[9:11], *S16)
        cells = integers(fields[11:11 + n], *S16)
        name, section, running, paused = DUO_STATES[state]
        section = _direction(section, i10)
        # the DUO/X counter is signed (the notes), and still holds the last phase's count on the
        # first record of the next: signing it by the section would count that twice
        return Reading(ms / 1000, name, section, running, vbat / 1000, i10 / 100, _temp(text),
                       _temp(tint), float(mah), tuple(c / 1000 for c in cells), paused,
                       "discharge" if section == "discharge" else "charge", charge_signed=True)


def decoder() -> IChargerLineDecoder:
    return IChargerLineDecoder()
