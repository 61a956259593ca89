"""Per-cell chemistry parameters, loaded from the package's ``resources/chemistries/<name>.toml``.

The TOML files are the single source of numbers; this module only checks and
flattens them. Every value is per cell at the file's reference capacity; `Pack`
scales resistances and thermal values to the real capacity.
"""
from __future__ import annotations

import functools
import math
from dataclasses import dataclass, fields

from .. import data
from ..data import DataFileError
from ..i18n import _

# ZUML AKK_TYPE names with a model; LiS/New/Undef deliberately have none (spec §5).
_NAMES = ("Pb", "NiCd", "NiMh", "LiPo", "LiIon", "LiFe")


@dataclass(frozen=True)
class Chemistry:
    """One cell of a chemistry at `ref_capacity_ah`; see battery-models.md §2.2 for the equations."""

    name: str
    # [limits], V per cell (spec §5)
    nominal_v: float
    charge_end_v: float
    max_v: float
    discharge_end_v: float
    charging_v: float            # typical voltage under charge (a charge's median): a log's cell count
    delta_v_per_cell: float      # typical -dV termination, V per cell (0 = not a -dV chemistry)
    # [ocv]
    ocv_soc: tuple[float, ...]   # 0 .. 1, strictly increasing
    ocv_v: tuple[float, ...]     # OCV at 25 °C, non-decreasing: the charge branch
    hyst_v: float                # the discharge branch lies this much lower (0: no hysteresis)
    hyst_soc: float              # ... and a cell moves between the branches e-fold over this share of its capacity
    diffusion_tau_s: float       # solid-state diffusion: the OCV is read at the particles' surface, which leads
                                 # the bulk by this many seconds of current (R^2 / 15 D; 0 = none)
    # [resistance]
    ref_capacity_ah: float
    r0_ohm: float
    r1_ohm: float
    tau1_s: float
    r2_ohm: float                # slow RC pair; 0 where one pair is enough
    tau2_s: float
    ea_j_per_mol: float          # Arrhenius activation energy for R0, R1, R2
    k_charge_ohm: float          # Tremblay polarisation on charge: k / (1 - soc + eps)
    pol_tau_s: float             # ... reached through an RC of this time constant (surface charge relaxes)
    pol_max_v: float             # ... and capped here (gassing clamps a lead-acid cell's voltage)
    k_discharge_ohm: float       # ... and on discharge: k / (soc + eps)
    pol_eps: float
    # [acceptance]
    w0: float                    # eta = 1 - exp(-(1 - soc) / (w0 * (1 + w_t * (T - 25))))
    w_t_per_k: float
    dv_o2_v: float               # O2-cycle overvoltage, weighted by (1 - eta)
    k_t_v_per_k: float           # terminal voltage falls k_t per K above 25 °C
    q_rev_v: float               # reversible heat per ampere stored (negative = endothermic charge)
    dip_v_per_charge: float      # end-of-charge dip, V per cell per capacity's worth of O2-cycle overcharge
    dip_tau_s: float             # ... which relaxes with this time constant
    overcharge_v_per_charge: float   # lithium past full: V per cell at a capacity's worth not accepted, squared
    # [thermal]
    cth_j_per_k: float
    ha_w_per_k: float


_SECTIONS = ("limits", "ocv", "resistance", "acceptance", "thermal")


def chemistry_names() -> list[str]:
    """The AKK_TYPE names that have a battery model."""
    return list(_NAMES)


def _canonical(name: str) -> str:
    for known in _NAMES:
        if known.lower() == name.strip().lower():
            return known
    raise KeyError(
        _("no battery model for chemistry {name!r}; modelled chemistries are {names} (LiS, New and Undef have no "
          "defaults)").format(name=name, names=', '.join(_NAMES))
    )


def load_chemistry(name: str) -> Chemistry:
    """Load one chemistry by its AKK_TYPE name (case-insensitive)."""
    return _load(_canonical(name))


@functools.cache
def _load(canonical: str) -> Chemistry:
    # Read once per process: the lint asks on every keystroke, and a Chemistry is frozen.
    relative = f"chemistries/{canonical}.toml"
    try:
        return _from_toml(canonical, data.read_toml(relative))
    except (TypeError, ValueError) as exc:
        raise DataFileError(_("data file {location}: {exc}").format(
                location=data.location(relative), exc=exc)) from None


def _from_toml(name: str, parsed: dict) -> Chemistry:
    flat: dict[str, object] = {"name": name}
    for section in _SECTIONS:
        table = parsed.get(section)
        if not isinstance(table, dict):
            raise ValueError(_("missing [{section}] table").format(section=section))
        for key, value in table.items():
            if key == "sources":
                continue
            if key in ("soc", "v"):
                flat[f"ocv_{key}"] = tuple(float(x) for x in value)
            else:
                flat[key] = float(value)
    wanted = {f.name for f in fields(Chemistry)}
    missing = wanted - flat.keys()
    extra = flat.keys() - wanted
    if missing or extra:
        raise ValueError(_("missing keys {missing}, unknown keys {unknown}").format(
                missing=sorted(missing), unknown=sorted(extra)))
    chem = Chemistry(**flat)  # type: ignore[arg-type]
    _check(chem)
    return chem


def _check(c: Chemistry) -> None:
    soc, v = c.ocv_soc, c.ocv_v
    if len(soc) != len(v) or len(soc) < 2:
        raise ValueError(_("ocv soc and v must have the same length >= 2"))
    if soc[0] != 0.0 or soc[-1] != 1.0 or any(b <= a for a, b in zip(soc, soc[1:])):
        raise ValueError(_("ocv soc must rise strictly from 0 to 1"))
    if any(b < a for a, b in zip(v, v[1:])):
        raise ValueError(_("ocv v must not fall with soc"))
    positive = ("charging_v", "ref_capacity_ah", "r0_ohm", "tau1_s", "tau2_s", "w0", "cth_j_per_k", "ha_w_per_k",
                "pol_eps", "pol_tau_s", "pol_max_v", "dip_tau_s", "hyst_soc")
    for key in positive:
        if not getattr(c, key) > 0.0:
            raise ValueError(_("{key} must be > 0").format(key=key))
    if c.diffusion_tau_s < 0.0:
        raise ValueError(_("{key} must be >= 0").format(key="diffusion_tau_s"))
    if c.hyst_v < 0.0:
        raise ValueError(_("{key} must be >= 0").format(key="hyst_v"))
    if c.overcharge_v_per_charge < 0.0:
        raise ValueError(_("{key} must be >= 0").format(key="overcharge_v_per_charge"))
    if c.dip_v_per_charge < 0.0:
        raise ValueError(_("{key} must be >= 0 (the voltage falls past the peak, never rises)").format(
            key="dip_v_per_charge"))
    for f in fields(Chemistry):
        value = getattr(c, f.name)
        if isinstance(value, float) and not math.isfinite(value):
            raise ValueError(_("{name} is not finite").format(name=f.name))
    if not c.discharge_end_v < c.nominal_v < c.charge_end_v <= c.max_v:
        raise ValueError(_("limits must satisfy discharge_end < nominal < charge_end <= max"))
