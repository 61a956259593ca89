"""New macros from a few answers (chemistry, cells, capacity, rate, sensor): the logic behind
``zuml new`` and the GUI's wizard. Limits come from the chemistry data (docs/zuml-2.0.md §5), the choices
around them from the package's data/templates.toml. The result is text; it is checked like any macro."""
from __future__ import annotations

from dataclasses import dataclass
from decimal import Decimal

from . import data
from .lang.lint import NICKEL_FAST_RATE, NICKEL_NO_SENSOR_MAX_RATE
from .domain.chemistry import Chemistry, chemistry_names, load_chemistry
from .errors import ZumlError
from .i18n import _

TEMPLATES = "templates.toml"


class WizardError(ZumlError, ValueError):
    pass


@dataclass(frozen=True)
class Answers:
    chemistry: str
    series: int
    capacity_mah: int
    rate_c: float | None = None         # charge rate; None: the chemistry's default
    sensor: bool = False                # a battery temperature sensor is fitted


def _num(x: float) -> str:
    text = format(Decimal(str(round(x, 2))), "f")
    return text.rstrip("0").rstrip(".") if "." in text else text


def choices(name: str) -> dict:
    """The template's choices for a chemistry (its canonical name), e.g. ``default_rate_c``."""
    table = data.read_toml(TEMPLATES).get(name)
    if not isinstance(table, dict):
        raise data.DataFileError(_("data file {location} has no [{name}] table").format(
                location=data.location(TEMPLATES), name=name))
    return table


def default_name(a: Answers, chem: Chemistry) -> str:
    return f"{chem.name}-{a.series}S-{a.capacity_mah}"[:16]


def new_macro(a: Answers) -> str:
    try:
        chem = load_chemistry(a.chemistry)
    except KeyError:
        raise WizardError(_("no template for {chemistry!r}; choose one of {chemistry_names}").format(
                chemistry=a.chemistry, chemistry_names=', '.join(chemistry_names()))) from None
    if not 1 <= a.series <= 255:
        raise WizardError(_("{series} cells in series: choose 1 to 255").format(series=a.series))
    if not 2 <= a.capacity_mah <= 65534:
        raise WizardError(_("a capacity of {capacity} mAh: choose 2 to 65534 mAh").format(capacity=a.capacity_mah))
    c = choices(chem.name)
    rate = c["default_rate_c"] if a.rate_c is None else a.rate_c
    if not 0.01 <= rate <= 5:
        raise WizardError(_("a charge rate of {rate:g}C: choose 0.01C to 5C").format(rate=rate))
    cells = f"{a.series} cell" if a.series == 1 else f"{a.series} cells"     # the file's comment: English
    head = [f"MACRO {default_name(a, chem)}",
            f"  // {chem.name}, {cells}, {a.capacity_mah} mAh, charge at {_num(rate)}C, "
            f"temperature sensor {'fitted' if a.sensor else 'not fitted'} (written by zuml new)",
            f"  AKK_TYPE={chem.name}", f"  SERIES={a.series}", f"  CAPACITY={a.capacity_mah}"]
    discharge = ["  DISCHARGE_SECTION", "    FAZE", f"      CONSTANT_I={_num(c['discharge_rate_c'])}C",
                 f"      IF(V<{_num(chem.discharge_end_v)}S) STOP_FAZE", "    END_FAZE", "  END_SECTION"]
    if chem.name in ("NiMh", "NiCd"):
        charge = _nickel(chem, c, a, rate)
    elif chem.name == "Pb":
        charge = _lead(chem, c, a, rate)
    else:
        charge = _lithium(chem, c, a, rate)
    return "\n".join(head + discharge + ["  CHARGE_SECTION"] + charge + ["  END_SECTION", "  MUSIC(STOP)",
                                                                        "END_MACRO"]) + "\n"


def _sensor(c: dict, a: Answers) -> list[str]:
    return [f"      IF(T>{c['t_max_c']}) STOP_FAZE"] if a.sensor else []


def _nickel(chem: Chemistry, c: dict, a: Answers, rate: float) -> list[str]:
    timer = round(c["timer_factor"] * 60 / rate)
    if rate >= c["min_delta_rate_c"]:
        # Volts for the whole pack keep the -dV close to the per-cell value (the byte code stores 10 mV steps).
        dv = max(0.01, round(c["delta_v_per_cell"] * a.series, 2))
        ends = [f"      IF(DELTA_PEAK>{_num(dv)}V) STOP_FAZE", f"      IF(V>{_num(chem.max_v)}S) STOP_FAZE"]
    elif rate <= c["timed_max_rate_c"]:
        ends = [f"      IF(V>{_num(chem.max_v)}S) STOP_FAZE"]
    else:
        raise WizardError(_("{name} at {rate}C shows no reliable -dV and is too fast for a timed charge: choose "
                            "{low}C or more, or {high}C or less").format(
                name=chem.name, rate=_num(rate), low=c['min_delta_rate_c'], high=c['timed_max_rate_c']))
    if rate > NICKEL_NO_SENSOR_MAX_RATE and not a.sensor:
        raise WizardError(_("{name} at {rate}C needs the temperature sensor: above {top:g}C the charger refuses to "
                            "start without it").format(name=chem.name, rate=_num(rate), top=NICKEL_NO_SENSOR_MAX_RATE))
    # A fast charge always states its temperature limit (the lint's W320), as lithium does: inert
    # without a sensor, in force with one.
    fast = [f"      IF(T>{c['t_max_c']}) STOP_FAZE"] if rate >= NICKEL_FAST_RATE else _sensor(c, a)
    main = ["    FAZE", f"      CONSTANT_I={_num(rate)}C"] + ends + fast + \
           [f"      IF(tf>{timer}min) STOP_FAZE", "    END_FAZE"]
    topoff = ["    FAZE", f"      TRICKLE({_num(c['topoff_rate_c'])}C, {_num(c['topoff_v1'])}S, "
                          f"{_num(c['topoff_v2'])}S)"] + _sensor(c, a) + \
             [f"      IF(tf>{c['topoff_minutes']}min) STOP_FAZE", "    END_FAZE"]
    return main + topoff


def _lead(chem: Chemistry, c: dict, a: Answers, rate: float) -> list[str]:
    absorption = ["    FAZE", f"      CONSTANT_I={_num(rate)}C", f"      CONSTANT_V={_num(chem.charge_end_v)}S",
                  f"      IF(I<{_num(c['absorption_end_c'])}C) STOP_FAZE"] + _sensor(c, a) + \
                 [f"      IF(tf>{c['absorption_max_minutes']}min) STOP_FAZE", "    END_FAZE"]
    float_ = ["    FAZE", f"      CONSTANT_I={_num(c['float_rate_c'])}C", f"      CONSTANT_V={_num(c['float_v'])}S"] + \
        _sensor(c, a) + [f"      IF(tf>{c['float_minutes']}min) STOP_FAZE", "    END_FAZE"]
    return absorption + float_


def _lithium(chem: Chemistry, c: dict, a: Answers, rate: float) -> list[str]:
    # Lithium always states its 45 °C limit (the lint's W315): inert without a sensor, in force with one.
    return ["    FAZE", f"      CONSTANT_I={_num(rate)}C", f"      CONSTANT_V={_num(chem.charge_end_v)}S",
            f"      IF(I<{_num(c['end_rate_c'])}C) STOP_FAZE", f"      IF(T>{c['t_max_c']}) STOP_FAZE"] + \
           [f"      IF(tf>{c['timer_minutes']}min) STOP_FAZE", "    END_FAZE"]
