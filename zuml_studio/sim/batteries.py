"""Named batteries: a chemistry with fitted parameters, a capacity and a cell count, saved as
``<config>/batteries/<name>.json`` (config dir as in ``user_dirs.config_dir``), offered wherever a
battery model is chosen (``zuml simulate --battery``, the simulator panel, the virtual charger)."""
from __future__ import annotations

import json
import math
import re
from dataclasses import fields, replace
from pathlib import Path
from typing import Sequence

from ..recovery import atomic_write
from ..user_dirs import config_dir
from .cell_pack import CellSpec, check_cells
from ..domain.chemistry import Chemistry, _check, load_chemistry
from .fit import Battery
from ..errors import ZumlError
from ..i18n import _

_NAME = re.compile(r"^[\w][\w .,+()-]{0,79}$")
_FORMAT = 1


class BatteryFileError(ZumlError, ValueError):
    """A named battery that does not exist or whose file is not one we wrote; the message says which."""


def batteries_dir(root: Path | None = None) -> Path:
    return (root or config_dir()) / "batteries"


def _file_name(name: str) -> str:
    if not _NAME.match(name) or name.strip() != name:
        raise BatteryFileError(_("battery name {name!r}: use letters, digits, spaces and . , + ( ) - (at most "
                                 "80)").format(
                name=name))
    return re.sub(r"[^\w.-]", "_", name) + ".json"


def save_battery(name: str, battery: Battery, source: str = "", root: Path | None = None,
                 cells: Sequence[CellSpec] | None = None) -> Path:
    """Write the battery under `name` (an existing one of that name is replaced); returns the file.
    ``cells``: each cell's capacity, resistance (x the pack's cell resistance) and start state (None:
    the run's), in order from the pack's negative end; else the battery's own (a weak cell a discharge
    fit found)."""
    cells = battery.cells if cells is None else cells
    base = load_chemistry(battery.chem.name)
    changed = {f.name: getattr(battery.chem, f.name) for f in fields(Chemistry)
               if getattr(battery.chem, f.name) != getattr(base, f.name)}
    doc = {"format": _FORMAT, "name": name, "chemistry": battery.chem.name, "capacity_mah": battery.capacity_mah,
           "series": battery.series, "fitted_from": source,
           "parameters": {k: list(v) if isinstance(v, tuple) else v for k, v in changed.items()}}
    if cells is not None:
        doc["cells"] = [{"capacity_mah": c.capacity_mah, "r_scale": c.r_scale, "soc": c.soc} for c in cells]
    path = batteries_dir(root) / _file_name(name)
    atomic_write(path, (json.dumps(doc, indent=2) + "\n").encode())
    return path


def battery_names(root: Path | None = None) -> list[str]:
    """Names of the saved batteries, sorted; files that are not ours are skipped here (load says why)."""
    names = []
    folder = batteries_dir(root)
    for path in sorted(folder.glob("*.json")) if folder.is_dir() else ():
        try:
            names.append(str(json.loads(path.read_text("utf-8"))["name"]))
        except (OSError, ValueError, KeyError, TypeError):
            continue
    return sorted(names, key=str.lower)


def _number(value: object, what: str) -> float:
    """A finite JSON number: a hand-edited file may hold true, "2000", 1e999 or a 400-digit integer."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise ValueError(_("{what} must be a number, not {value!r}").format(what=what, value=value))
    try:
        number = float(value)
    except OverflowError:
        number = math.inf
    if not math.isfinite(number):
        raise ValueError(_("{what} must be a finite number, not {value}").format(what=what, value=str(value)[:20]))
    return number


def load_battery(name: str, root: Path | None = None) -> Battery:
    return load_battery_cells(name, root)[0]


def load_battery_cells(name: str, root: Path | None = None) -> tuple[Battery, list[CellSpec] | None]:
    """The battery and its cells (None when the file lists none: identical cells)."""
    path = batteries_dir(root) / _file_name(name)
    try:
        doc = json.loads(path.read_text("utf-8"))
    except FileNotFoundError:
        known = ", ".join(battery_names(root)) or _("none saved yet (zuml fit LOG --save NAME)")
        raise BatteryFileError(_("no saved battery {name!r}; saved: {known}").format(name=name, known=known)) from None
    except (OSError, ValueError) as exc:
        raise BatteryFileError(_("{path}: not a battery file: {exc}").format(path=path, exc=exc)) from None
    try:
        if not isinstance(doc, dict):
            raise ValueError(_("a JSON object expected, not {kind}").format(kind=type(doc).__name__))
        if doc.get("format") != _FORMAT:
            raise ValueError(_("format {found!r}, expected {expected}").format(
                    found=doc.get('format'), expected=_FORMAT))
        chem = load_chemistry(str(doc["chemistry"]))
        wanted = {f.name: f.type for f in fields(Chemistry)}
        params = {}
        for key, value in doc["parameters"].items():
            if key not in wanted or key == "name":
                raise ValueError(_("unknown parameter {key!r}").format(key=key))
            params[key] = tuple(_number(x, key) for x in value) if isinstance(value, list) else _number(value, key)
        fitted = replace(chem, **params)
        _check(fitted)
        capacity, series = _number(doc["capacity_mah"], "capacity_mah"), _number(doc["series"], "series")
        if not capacity > 0 or not 1 <= series <= 255 or series != int(series):
            raise ValueError(_("capacity_mah must be > 0 and series a whole number 1..255"))
        cells = _cells(doc["cells"], int(series)) if doc.get("cells") is not None else None
    except (KeyError, TypeError, ValueError, AttributeError) as exc:
        raise BatteryFileError(_("{path}: bad battery file: {exc}").format(path=path, exc=exc)) from None
    return Battery(fitted, capacity, int(series)), cells


def _cells(value: object, series: int) -> list[CellSpec]:
    if not isinstance(value, list) or len(value) != series:
        raise ValueError(_("cells must be a list of {series} cells").format(series=series))
    cells = []
    for k, cell in enumerate(value, 1):
        if not isinstance(cell, dict) or set(cell) - {"capacity_mah", "r_scale", "soc"}:
            raise ValueError(_("cell {k}: an object with capacity_mah, r_scale and soc").format(k=k))
        soc = cell.get("soc")
        cells.append(CellSpec(_number(cell["capacity_mah"], "capacity_mah"),
                              _number(cell.get("r_scale", 1.0), "r_scale"),
                              None if soc is None else _number(soc, "soc")))
    check_cells(cells)
    return cells
