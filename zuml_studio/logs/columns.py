"""Which column is what, in the text formats that name their columns ("U_Lipo [V]",
"Spannung [V]", "Strom [A]"): by unit first, then by words in the name.

The pack voltage is a column in V that is not a supply, cell, balance or BEC voltage,
preferring names that say battery (``bat``, ``akku``, ``lipo``, ``pack``…); the current the
first in A (preferring "current"/"strom"); the battery temperature the first in °C; the
charge a column in mAh or Ah; the cells the columns in V named ``cell n``/``zelle n``/
``ZellenSpannung n``, in their number's order."""
from __future__ import annotations

import re
from dataclasses import dataclass

from .model import SampleBuilder, state_from_current

_COLUMN = re.compile(r"^\s*([^\[\]]*?)\s*(?:\[([^\],]*)(?:,([^\]]*))?\])?\s*$")
BATTERY_WORDS = ("bat", "akku", "accu", "lipo", "pack")
NOT_PACK = ("versorgung", "eingang", "input", "supply", "zelle", "cell", "balance", "bec")
_CELL = re.compile(r"(?:zellenspannung|cellvoltage|cell|zelle)\s*_?\s*(\d{1,2})", re.IGNORECASE)
TEMP_UNITS = ("°C", "C", "degC")


def parse_column(spec: str) -> tuple[str, str]:
    """``"Temp 1 [°C,T]"`` -> ("Temp 1", "°C")."""
    m = _COLUMN.match(spec)
    return (m.group(1), (m.group(2) or "").strip()) if m else (spec.strip(), "")


def _pick(columns: list[tuple[str, str]], units: tuple[str, ...], prefer: tuple[str, ...] = (),
          avoid: tuple[str, ...] = (), skip=frozenset()) -> int | None:
    candidates = [k for k, (name, unit) in enumerate(columns)
                  if unit in units and k not in skip and not any(a in name.lower() for a in avoid)]
    for k in candidates:
        if any(w in columns[k][0].lower() for w in prefer):
            return k
    return candidates[0] if candidates else None


@dataclass(frozen=True)
class Roles:
    voltage: int | None
    current: int | None
    temp: int | None
    mah: int | None
    ah: int | None
    cells: tuple[int, ...]


def roles(columns: list[tuple[str, str]]) -> Roles:
    cells: dict[int, int] = {}
    for k, (name, unit) in enumerate(columns):
        m = _CELL.search(name)
        if m and unit == "V":
            cells.setdefault(int(m.group(1)), k)
    return Roles(voltage=_pick(columns, ("V",), BATTERY_WORDS, NOT_PACK, set(cells.values())),
                 current=_pick(columns, ("A",), ("current", "strom", "curr")),
                 temp=_pick(columns, TEMP_UNITS, BATTERY_WORDS),
                 mah=_pick(columns, ("mAh",)), ah=_pick(columns, ("Ah",)),
                 cells=tuple(cells[n] for n in sorted(cells)))


def add_row(builder: SampleBuilder, r: Roles, numbers: list[float], t: float) -> None:
    """One row of numbers (in the columns' order) as a sample; the state from the current's sign."""
    current = numbers[r.current] if r.current is not None else 0.0
    counter = None
    if r.mah is not None:
        counter = numbers[r.mah]
    elif r.ah is not None:
        counter = numbers[r.ah] * 1000.0
    builder.add(t, numbers[r.voltage], current, state_from_current(current),
                temp=numbers[r.temp] if r.temp is not None else None,
                cells=[numbers[k] for k in r.cells], counter=counter)
