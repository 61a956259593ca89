"""Acceptance of the lumped battery models (battery-models.md §2-§4) with a plain CC / CV driver."""
from __future__ import annotations

import re

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from zuml_studio.sim.battery import Pack
from zuml_studio import data
from zuml_studio.domain.chemistry import chemistry_names, load_chemistry
from zuml_studio.sim.delta_peak import DeltaPeakDetector

DT = 1.0
CAPACITY = {"Pb": 7000, "NiCd": 1000, "NiMh": 2000, "LiPo": 2280, "LiIon": 5000, "LiFe": 2300}


def cc_until_v(pack: Pack, current: float, v_cell: float, max_h: float = 10.0) -> float:
    """Constant current until the per-cell voltage reaches v_cell; returns hours."""
    steps = 0
    while pack.step(current, DT) < v_cell * pack.series:
        steps += 1
        assert steps * DT < max_h * 3600, "voltage never reached"
    return (steps + 1) * DT / 3600


def cv_until_i(pack: Pack, v_cell: float, i_end: float, i_max: float, max_h: float = 10.0) -> float:
    """Constant voltage (current limited to i_max) until the current falls to i_end; returns hours."""
    steps = 0
    while True:
        i = min(i_max, pack.current_for_voltage(v_cell * pack.series, DT))
        pack.step(i, DT)
        steps += 1
        if i <= i_end:
            return steps * DT / 3600
        assert steps * DT < max_h * 3600, "current never fell"


def ni_charge(name: str, capacity: float, c_rate: float, until_c: float, mv_per_cell: float):
    """Charge 4 cells at c_rate up to until_c x capacity; returns per-cell voltages, temperatures and the
    charge-in (x capacity) at which a -dV of mv_per_cell fired (None if it did not)."""
    cells = 4
    pack = Pack(load_chemistry(name), capacity, cells)
    current = c_rate * capacity / 1000
    det = DeltaPeakDetector()
    volts, temps, fired = [], [], None
    for k in range(1, int(until_c * 3600 / c_rate / DT) + 1):
        v = pack.step(current, DT)
        volts.append(v / cells)
        temps.append(pack.temp_c)
        if fired is None and det.update(k * DT, v) >= mv_per_cell * 1e-3 * cells:
            fired = k * DT * current / 3600 / (capacity / 1000)
    return volts, temps, fired


# -- parameter files -------------------------------------------------------------------------

SPEC_LIMITS = {  # spec §5: nominal, charge end, max, discharge end (per cell)
    "Pb": (2.00, 2.40, 2.50, 1.75),
    "NiCd": (1.20, 1.80, 1.80, 0.85),
    "NiMh": (1.20, 1.80, 1.80, 1.00),
    "LiPo": (3.70, 4.20, 4.35, 3.00),
    "LiIon": (3.60, 4.20, 4.25, 2.50),
    "LiFe": (3.30, 3.60, 3.70, 2.50),
}


def test_names_and_spec_limits():
    assert chemistry_names() == list(SPEC_LIMITS)
    for name, limits in SPEC_LIMITS.items():
        c = load_chemistry(name.upper())
        assert c.name == name
        assert (c.nominal_v, c.charge_end_v, c.max_v, c.discharge_end_v) == limits


@pytest.mark.parametrize("name", ["LiS", "New", "Undef", "NiZn", ""])
def test_unmodelled_chemistry_raises_key_error(name):
    with pytest.raises(KeyError, match="no battery model"):
        load_chemistry(name)


def test_every_modelled_chemistry_has_its_data_file():
    assert data.names("chemistries") == sorted(chemistry_names())


@pytest.mark.parametrize("path", [f"chemistries/{n}.toml" for n in data.names("chemistries")]
                         + [f"chargers/{n}.toml" for n in data.names("chargers")])
def test_every_number_in_a_parameter_file_has_a_source(path):
    """Each numeric value carries a '# source:' comment, or its table has a `sources = [...]` list."""
    text = data.read_text(path)
    tables_with_sources = set(re.findall(r"^\[(\w+)\][^\[]*?^sources\s*=", text, flags=re.M | re.S))
    table = ""
    for n, line in enumerate(text.splitlines(), start=1):
        header = re.match(r"\[(\w+)\]", line)
        if header:
            table = header.group(1)
        code = re.sub(r'"[^"]*"', "", line.split("#", 1)[0])
        if "=" in code and re.search(r"\d", code.split("=", 1)[1]):
            cited = "# source:" in line or table in tables_with_sources
            assert cited, f"{path}:{n} has no source: {line.strip()}"


# -- NiMH / NiCd: peak, -dV, heat ----------------------------------------------------------------

def test_nimh_1c_peak_then_delta_v_then_faster_heating():
    volts, temps, fired = ni_charge("NiMh", 2000, 1.0, 1.3, 5)
    peak = max(range(len(volts)), key=volts.__getitem__)
    # Real NiMH packs peak at 1.55-1.65 V/cell at 0.3-1.1C, measured at the charger (eStation BC6 1C
    # 1.625, Ultramat 0.45C 1.65, Polaron 0.3C 1.55: docs/validation.md); the textbook 1.42-1.52 was too low.
    assert 1.45 <= volts[peak] <= 1.68
    assert volts[-1] < volts[peak] - 0.005          # it falls after the peak
    # The Akkumatik NiCd recording ends its -dV at 1.09-1.18x the fitted capacity (docs/validation.md).
    assert fired is not None and 1.0 <= fired <= 1.20
    window = int(600 / DT)
    before = temps[peak] - temps[peak - window]
    after = temps[peak + window] - temps[peak]
    assert after > before > 0


def test_nimh_02c_dips_about_5mv_per_cell_as_real_packs_do():
    # AkkuMaster C4 AA pack at 0.15 A (0.2C): peak, then 4.8 mV/cell down when the charger stopped at
    # 1.25x its fitted capacity; the default model makes 4.6 on that recording and 3.4 on this 2 Ah
    # pack (docs/validation.md). The old model plateaued with no dip.
    volts, _, fired = ni_charge("NiMh", 2000, 0.2, 1.5, 3)
    assert fired is not None and 1.0 <= fired <= 1.3
    peak = max(range(len(volts)), key=volts.__getitem__)
    assert 0.003 <= volts[peak] - min(volts[peak:]) <= 0.02


@pytest.mark.parametrize("mv", [10, 15])
def test_nicd_1c_delta_v(mv):
    volts, _, fired = ni_charge("NiCd", 1000, 1.0, 1.3, mv)
    assert 1.35 <= max(volts) <= 1.52
    # The Akkumatik NiCd recording (4 cells) ends its -dV of 12.8 mV/cell at 1.20-1.22x its fitted capacity
    # (docs/validation.md); the default, tuned on it, fires at 1.24-1.27x.
    assert fired is not None and 1.0 <= fired <= 1.30


def test_nicd_and_nimh_both_dip_clearly_at_1c():
    # The recordings contradict "the NiCd dip is larger" [N3]: at about 1C the NiCd pack (Akkumatik)
    # fell 10 mV/cell, the NiMH pack (eStation BC6) 12.5 mV/cell (docs/validation.md).
    def dip_5_min_after_peak(name, capacity):
        volts, _, _ = ni_charge(name, capacity, 1.0, 1.3, 100)
        peak = max(range(len(volts)), key=volts.__getitem__)
        return volts[peak] - volts[peak + int(300 / DT)]
    assert dip_5_min_after_peak("NiCd", 1000) > 0.005 and dip_5_min_after_peak("NiMh", 2000) > 0.005


def test_nimh_overcharge_passes_50c():
    # With the heat capacity and loss fitted to the NiMH packs (docs/validation.md) 60 % overcharge at
    # 1C peaks near 59 °C instead of 60+: still far past any charger's T limit.
    _, temps, _ = ni_charge("NiMh", 2000, 1.0, 1.6, 5)
    assert max(temps) > 50.0


# -- Li CC-CV, Pb absorption ---------------------------------------------------------------------

def test_liion_cccv_matches_pybamm_dfn_chen2020():
    # PyBaMM's DFN at 1C: CC 42.5 min, CC + CV 118.3 min (tests/data/pybamm_cv_chen2020.json; tests/sim/test_cv_tail.py
    # holds the CV phase itself at 0.5, 1 and 2C). Its SPM's 0.82 h and 1.78 h were held here before.
    pack = Pack(load_chemistry("LiIon"), 5000, 1)
    t_cc = cc_until_v(pack, 5.0, 4.2)
    t_total = t_cc + cv_until_i(pack, 4.2, 0.1, 5.0)
    assert t_cc == pytest.approx(0.708, rel=0.15)
    assert t_total == pytest.approx(1.972, rel=0.15)
    assert pack.soc > 0.98


def test_lipo_cccv_similar_to_liion():
    pack = Pack(load_chemistry("LiPo"), 2280, 3)
    t_cc = cc_until_v(pack, 2.28, 4.2)
    t_total = t_cc + cv_until_i(pack, 4.2, 2.28 / 50, 2.28)
    assert 0.7 <= t_cc <= 0.95
    assert 1.4 <= t_total <= 2.05
    assert pack.soc > 0.98


def test_life_cccv_has_short_cv_tail():
    pack = Pack(load_chemistry("LiFe"), 2300, 1)
    t_cc = cc_until_v(pack, 2.3, 3.6)
    t_cv = cv_until_i(pack, 3.6, 2.3 / 50, 2.3)
    assert 0.85 <= t_cc <= 1.1
    assert t_cv < 0.15


def test_pb_c4_reaches_absorption_voltage_at_85_percent():
    pack = Pack(load_chemistry("Pb"), 7000, 6, soc=0.2)
    cc_until_v(pack, 1.75, 2.40)
    assert 0.80 <= pack.soc <= 0.90


@pytest.mark.parametrize("name", list(CAPACITY))
def test_1c_discharge_delivers_most_of_the_capacity(name):
    chem, capacity = load_chemistry(name), CAPACITY[name]
    pack = Pack(chem, capacity, 2, soc=1.0)
    current = capacity / 1000
    steps = 0
    while pack.step(-current, DT) > chem.discharge_end_v * 2:
        steps += 1
        assert steps < 2 * 3600
    delivered = (steps + 1) * DT * current / 3600 / (capacity / 1000)
    # NiMH's discharge branch lies 50 mV below the OCV fitted on charges (its hysteresis) and its default
    # resistance is a hobby pack's with leads: 83 % at 1C to 1.0 V (the eStation pack delivered 82 % of its
    # fitted capacity at 1.1C to 0.95 V, docs/validation.md).
    assert (0.80 if name == "NiMh" else 0.85) <= delivered <= 1.0


# -- solver and bookkeeping ----------------------------------------------------------------------

@pytest.mark.parametrize("name", ["NiCd", "NiMh"])
def test_current_for_voltage_on_a_full_nickel_pack_with_its_dip_and_a_long_tick(name):
    # Past the peak the overcharge dip deepens; the solve must still find the one current (the dip
    # of a step depends on the overcharge before it, so the voltage rises with the current).
    pack = Pack(load_chemistry(name), 300, 3, soc=0.99)
    for _ in range(60):
        pack.step(0.3, 30.0)
    target = pack.voltage + 0.003       # a current the step does not cap at full (s = 1)
    i = pack.current_for_voltage(target, 30.0)
    assert i > 0
    assert pack.step(i, 30.0) == pytest.approx(target, abs=1e-9)


@pytest.mark.parametrize("name", list(CAPACITY))
@pytest.mark.parametrize("offset", [0.15, -0.15])
def test_current_for_voltage_hits_the_set_point(name, offset):
    chem = load_chemistry(name)
    pack = Pack(chem, CAPACITY[name], 3, soc=0.5)
    pack.step(CAPACITY[name] / 2000, 60.0)          # some RC and heat history
    target = pack.open_circuit_voltage() + offset * 3
    i = pack.current_for_voltage(target, DT)
    assert (i > 0) == (offset > 0)
    assert pack.step(i, DT) == pytest.approx(target, abs=1e-9)


def test_cells_in_series_and_capacity_scaling_keep_per_cell_behaviour():
    chem = load_chemistry("LiIon")
    one = Pack(chem, 5000, 1, soc=0.3)
    big = Pack(chem, 10000, 4, soc=0.3)
    for _ in range(600):
        v1 = one.step(5.0, DT)
        v4 = big.step(10.0, DT)
    assert v4 == pytest.approx(4 * v1, rel=1e-9)
    assert big.cell_voltage == pytest.approx(one.cell_voltage, rel=1e-9)
    assert big.temp_c == pytest.approx(one.temp_c, rel=1e-9)
    assert big.soc == pytest.approx(one.soc, rel=1e-9)


def test_state_stays_physical_under_abuse():
    pack = Pack(load_chemistry("NiMh"), 2000, 4)
    for current in (50.0, -50.0, 0.0):
        for _ in range(900):
            pack.step(current, 10.0)
            # Below 0 is the over-discharge (reversal) region, bounded; never above full.
            assert -0.06 <= pack.soc <= 1.0
    assert pack.temp_c == pytest.approx(pack.ambient_c, abs=1.0)   # cooled back after the rest


def test_an_empty_cell_collapses_when_the_discharge_goes_on():
    pack = Pack(load_chemistry("NiMh"), 2000, 1, soc=0.02)
    for _ in range(1200):
        v = pack.step(-0.2, DT)
    assert pack.soc < 0 and v < 0.9


def test_rest_relaxes_to_open_circuit_voltage():
    pack = Pack(load_chemistry("LiIon"), 5000, 2, soc=0.5)
    for _ in range(600):
        pack.step(5.0, DT)
    assert pack.voltage > pack.open_circuit_voltage()
    for _ in range(4 * 3600):
        v = pack.step(0.0, DT)
    assert v == pytest.approx(pack.open_circuit_voltage(), abs=1e-4)
    assert pack.current == 0.0


@settings(deadline=None)
@given(
    name=st.sampled_from(list(CAPACITY)),
    soc=st.floats(0.05, 0.95),
    history_c=st.floats(-1.0, 1.0),
    offset=st.one_of(st.floats(-0.3, -0.12), st.floats(0.12, 0.3)),
)
def test_cv_solve_property(name, soc, history_c, offset):
    """Any state, any set point beyond the O2 overvoltage step: the solved current lands on it."""
    chem = load_chemistry(name)
    pack = Pack(chem, CAPACITY[name], 2, soc=soc)
    for _ in range(30):
        pack.step(history_c * CAPACITY[name] / 1000, 2.0)
    # Between the OCV and OCV + dv_o2 near full no current flows (current_for_voltage's gap).
    target = pack.open_circuit_voltage() + 2 * (offset + (chem.dv_o2_v if offset > 0 else 0.0))
    i = pack.current_for_voltage(target, DT)
    assert pack.step(i, DT) == pytest.approx(target, abs=1e-9)


@pytest.mark.parametrize("ambient", [float("nan"), float("inf"), -20.5, 60.5, -300.0])
def test_an_ambient_outside_the_model_range_is_refused(ambient):
    # found by benchmarks/fuzz_cli.py: `zuml simulate --ambient nan` ended in UnboundLocalError
    with pytest.raises(ValueError, match="ambient temperature .* °C: the model covers -20 to 60 °C"):
        Pack(load_chemistry("NiMh"), 2000, 4, ambient_c=ambient)


@pytest.mark.parametrize("capacity", [float("nan"), float("inf"), 0.0])
def test_a_capacity_that_is_no_positive_finite_number_is_refused(capacity):
    with pytest.raises(ValueError, match="capacity_mah must be > 0"):
        Pack(load_chemistry("NiMh"), capacity, 4)


# LiIon's particles' surface leads their bulk (solid-state diffusion): at 1C it passes 4.2 V from 69 % on, as
# PyBaMM's DFN of Chen2020 does (42 min of CC at 1C, tests/data/pybamm_cv_chen2020.json), so 90 % reads 4.39 V.
@pytest.mark.parametrize("name, full_v, at_90", [("LiPo", 4.2, 0.1), ("LiIon", 4.2, 0.2), ("LiFe", 3.6, 0.1)])
def test_a_lithium_cell_past_full_climbs_steeply(name, full_v, at_90):
    """Issue 27: a LiPo taken to 150 % sat at about 4.25 V; past full the voltage climbs (the charge
    goes into plating and the electrolyte, not the cell), so an overcharge shows as one."""
    pack = Pack(load_chemistry(name), 2000, 1)
    volts = {}
    for second in range(1, int(1.5 * 3600) + 1):       # 1C for 90 minutes: 150 % of the capacity
        v = pack.step(2.0, DT)
        if second in (3240, 4680, 5400):               # 90 %, 130 %, 150 %
            volts[second] = v
    assert volts[3240] < full_v + at_90
    assert volts[4680] > full_v + 0.2
    assert volts[5400] > full_v + 0.6 and volts[5400] > volts[4680] + 0.3
    after = pack.open_circuit_voltage()
    pack.step(-2.0, 600.0)                             # a discharge takes the overcharge back first
    assert pack.open_circuit_voltage() < after - 0.3


def test_the_simulator_sees_a_lithium_overcharge():
    """A stop just above the usual 4.2 V per cell ends the charge just past full (it used to run on
    to a default: the model never got there)."""
    from simhelp import macro, run
    text = macro("FAZE\nCONSTANT_I=1C\nIF(V>4.3S) STOP_FAZE\nEND_FAZE", intro="AKK_TYPE=LiPo\nSERIES=2")
    result = run(text, capacity=2000, series=2, sensor=False)
    phase = result.phases[0]
    assert phase.reason == "IF(V>4.3S) STOP_FAZE" and 2000 < phase.mah_in < 2400, (phase.reason, phase.mah_in)


def test_a_discharge_held_at_its_end_voltage_past_empty_falls_to_nothing():
    # The Akkumatik NiCd held 0.86 V/cell for its last 9 minutes: the model held there runs on into its OCV's
    # collapse below empty, and its current must fall with it (it ran on at the table's first slope to -6 %, for hours).
    pack = Pack(load_chemistry("NiCd"), 1000.0, 4, 0.02)
    for _ in range(3600):
        i = min(0.0, pack.current_for_voltage(3.44, 1.0))
        v = pack.step(i, 1.0)
        assert v == pytest.approx(3.44, abs=1e-6)
    assert -0.01 < i <= 0.0 and pack.soc > -0.06
