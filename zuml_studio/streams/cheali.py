"""cheali-charger (iMAX B6 clones with the open firmware): ``$1;…`` lines on the UART.

Layout by field count (docs/real-chargers.md; /shared/realdata/cheali.md):

* 25 fields (before the checksum): firmware 0.2x–0.33, 6 cells, no percent/ETA, field 1 is
  ``programState`` (0 None … 9 Storage);
* 27 fields: firmware ≥ 1.00 (and the late 0.33 dev builds), 6 cells, percent + ETA, field 1
  is ``programType + 1`` (1 Charge … 11 Calibrate);
* 31 fields: the same with 8 cells (``MAX_BALANCE_CELLS > 6`` builds).

``$2``/``$3`` debug lines are skipped. cheali sends the current unsigned: the sign comes from
the program (Discharge negative). Programs that charge and discharge (Storage, Cycle,
Capacity check) do not say which they are doing on this line: their section is "" and the
current is shown as sent. A temperature of exactly 0 is "no sensor" (the firmware's value
for an absent thermistor).
"""
from __future__ import annotations

from .stream_decoder import DollarLineDecoder, Reading, integers
from ..i18n import _


# programType + 1 (firmware >= 1.00): name, section, task, running
STATES_1X = {
    1: ("charge", "charge", "charge", True), 2: ("charge balance", "charge", "charge", True),
    3: ("balance", "", "charge", True), 4: ("discharge", "discharge", "discharge", True),
    5: ("fast charge", "charge", "charge", True), 6: ("storage", "", "charge", True),
    7: ("storage balance", "", "charge", True), 8: ("discharge-charge cycle", "", "train", True),
    9: ("capacity check", "", "train", True), 10: ("edit battery", "", "charge", False),
    11: ("calibrate", "", "charge", False),
}
# programState (firmware 0.2x-0.33)
STATES_0X = {
    0: ("none", "", "charge", False), 1: ("info", "", "charge", False), 2: ("calibration", "", "charge", False),
    3: ("done", "", "charge", False), 4: ("error", "", "charge", False), 5: ("charging", "charge", "charge", True),
    6: ("charging balancing", "charge", "charge", True), 7: ("discharging", "discharge", "discharge", True),
    8: ("balancing", "", "charge", True), 9: ("storage", "", "charge", True),
}
LAYOUTS = {25: (STATES_0X, 6), 27: (STATES_1X, 6), 31: (STATES_1X, 8)}


def _time(text: str) -> float:
    whole, dot, tenth = text.partition(".")
    if not whole.isdigit() or not whole.isascii() or (dot and (len(tenth) != 1 or not tenth.isdigit())):
        raise ValueError(_("bad time {text!r}").format(text=text))
    return int(whole) + (int(tenth) / 10 if dot else 0.0)


def _temp(c100: int) -> float | None:
    return None if c100 == 0 else c100 / 100.0


class ChealiDecoder(DollarLineDecoder):
    name = "cheali"

    def record(self, fields: list[str]) -> Reading | None:
        if fields[0] in ("2", "3"):
            return None
        if fields[0] != "1":
            raise ValueError(_("not channel 1"))
        layout = LAYOUTS.get(len(fields))
        if layout is None:
            raise ValueError(_("{n_fields} fields fit no cheali layout").format(n_fields=len(fields)))
        states, cells = layout
        state = int(fields[1]) if fields[1].isdigit() and fields[1].isascii() else -1
        if state not in states:
            raise ValueError(_("unknown state {fields}").format(fields=fields[1]))
        name, section, task, running = states[state]
        v = integers(fields[3:3 + 8 + cells], 0, 0xFFFF)
        mv, ma, mah, _pw, _wh, text, tint, _vin = v[:8]
        sign = -1 if section == "discharge" else 1
        return Reading(time_s=_time(fields[2]), state=name, section=section, running=running,
                       voltage_v=mv / 1000, current_a=sign * ma / 1000, temp_c=_temp(text),
                       heatsink_c=_temp(tint), charge_mah=float(mah), cells_v=tuple(c / 1000 for c in v[8:]),
                       task=task)


def decoder() -> ChealiDecoder:
    return ChealiDecoder()
