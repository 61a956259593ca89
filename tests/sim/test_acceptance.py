"""Issue 3's acceptance points, each on the project's macros."""
import numpy as np
import pytest

from simhelp import run


def per_cell(result, series):
    a = result.log.arrays()
    return a, a["voltage_v"] / series


def test_nimh_1c_ends_by_minus_dv_with_a_peak_and_faster_heating_after_it():
    r = run("NiMh-dV", capacity=2000, series=4, current=2.0, sensor=False)
    (phase,) = r.phases
    assert phase.reason == "IF(DELTA_PEAK>0.01S) STOP_FAZE" and not phase.by_default
    assert 1.0 <= phase.mah_in / 2000 <= 1.15
    a, v = per_cell(r, 4)
    peak = int(np.argmax(v))
    # Real packs peak at 1.55-1.65 V/cell (eStation BC6 1C 1.625: docs/validation.md).
    assert 1.45 <= v[peak] <= 1.68
    t, temp = a["time_s"], a["temp_c"]
    before = (temp[peak] - temp[peak - 600]) / 10
    after_end = min(peak + 240, len(temp) - 1)
    after = (temp[after_end] - temp[peak]) / ((t[after_end] - t[peak]) / 60)
    assert after > before > 0


def test_nimh_with_a_sensor_ends_by_dtdt_first_as_real_chargers_do():
    r = run("NiMh-dV", capacity=2000, series=4, current=2.0, sensor=True)
    assert r.phases[0].reason == "default: dT/dt>1C/min"
    assert 0.9 <= r.phases[0].mah_in / 2000 <= 1.1


def test_nimh_at_0_2c_dips_as_real_packs_do_and_the_seeds_threshold_leaves_it_to_a_default():
    r = run("NiMh", capacity=2000, series=4, current=0.4, sensor=False)
    (phase,) = r.phases
    # The seed's DELTA_PEAK=0.2S never fires: the charger's capacity default ends the charge.
    assert phase.reason == "default: capacity 1.5x" and phase.by_default
    a, v = per_cell(r, 4)
    # Real NiMH packs dip at 0.2C (AkkuMaster C4 AA pack at 0.15 A: 4.8 mV/cell; Polaron 5S at 0.3C:
    # 4.2 mV/cell; docs/validation.md); the old model's plateau without a dip was wrong.
    assert 0.003 <= v.max() - v[-1] <= 0.02


def test_nimh_at_0_2c_is_outside_the_macros_stated_use_and_its_timer_is_flagged_before_full():
    r = run("NiMh-dV", capacity=2000, series=4, current=0.4, sensor=False)
    (phase,) = r.phases
    assert phase.reason == "IF(tf>4h) STOP_FAZE" and phase.mah_in < 2000
    assert phase.timer_before_full and r.to_json()["phases"][0]["timer_before_full"] is True


def test_nimh_at_2c_ends_by_minus_dv_at_full_not_on_early_heating():
    # The model's -dV comes from the overcharge, not from heat: a 2C charge heats from the start, and
    # when the dip came from heat alone it fired a third of the way in (docs/validation.md).
    r = run("NiMh-dV", capacity=2000, series=4, current=4.0, sensor=False)
    (phase,) = r.phases
    assert phase.reason == "IF(DELTA_PEAK>0.01S) STOP_FAZE" and not phase.timer_before_full
    assert 1.0 <= phase.mah_in / 2000 <= 1.15


@pytest.mark.parametrize("name, capacity, c_rates", [("NiMh-dV", 2000, (0.3, 0.5, 1.0, 2.0)),
                                                     ("NiCd-dV", 1000, (0.5, 1.0, 2.0))])
def test_standard_nickel_macros_fill_the_battery_over_their_stated_range(name, capacity, c_rates):
    for rate in c_rates:
        r = run(name, capacity=capacity, series=4, current=rate * capacity / 1000, sensor=False)
        (phase,) = r.phases
        assert not phase.timer_before_full and phase.mah_in >= capacity, (rate, phase.reason)


def test_nicd_1c_ends_by_minus_dv_and_both_nickel_chemistries_fall_after_the_peak():
    nicd = run("NiCd-dV", capacity=1000, series=4, current=1.0, sensor=False)
    assert nicd.phases[0].reason == "IF(DELTA_PEAK>0.01S) STOP_FAZE"
    # The Akkumatik NiCd recording (4 cells) ends at 1.20-1.22x its fitted capacity (docs/validation.md).
    assert 1.0 <= nicd.phases[0].mah_in / 1000 <= 1.30
    nimh = run("NiMh-dV", capacity=1000, series=4, current=1.0, sensor=False)

    def dip_5min_after_peak(r):
        a, v = per_cell(r, 4)
        peak = int(np.argmax(v))
        return v[peak] - v[min(peak + 300, len(v) - 1)]

    # The charge stops at the threshold, so compare the slope just after the peak instead. The
    # recordings contradict "NiCd falls faster" [N3]: the eStation NiMH pack fell 1.9 mV/cell per
    # minute at 1.1C, the Akkumatik NiCd pack 1.3 at 0.85C (docs/validation.md); both fall.
    a1, v1 = per_cell(nicd, 4)
    a2, v2 = per_cell(nimh, 4)
    p1, p2 = int(np.argmax(v1)), int(np.argmax(v2))
    assert (v1[p1] - v1[-1]) / (len(v1) - p1) > 0 and (v2[p2] - v2[-1]) / (len(v2) - p2) > 0
    assert dip_5min_after_peak(nicd) > 0


@pytest.mark.parametrize("name", ["NiCd", "NiMh"])
def test_seed_nickel_macros_end_by_a_default_and_say_so(name):
    r = run(name, capacity=2000, series=4, current=2.0, sensor=False)
    assert r.phases[0].by_default and r.phases[0].reason == "default: capacity 1.5x"
    assert r.to_json()["phases"][0]["by_default"] is True


def test_liion_5ah_cc_cv_to_c50_matches_pybamm_dfn_within_15_percent():
    # PyBaMM 26.10's DFN of Chen2020 at 1C (tests/data/pybamm_cv_chen2020.json): CC 42.5 min, CV 75.8 min
    # (its SPM: 49.2 and 57.8 min, the figures this test held before the model had diffusion).
    r = run("LiIon-CCCV", capacity=5000, series=1, current=5.0)
    cc, cv = r.phases
    assert cc.reason == "IF(V>4.2S) STOP_FAZE" and cv.reason == "IF(I<0.02C) STOP_FAZE"
    assert abs(cc.end_s / 3600 - 0.708) / 0.708 < 0.15
    assert abs(cv.end_s / 3600 - 1.972) / 1.972 < 0.15
    a = r.log.arrays()
    in_cv = a["phase"] == 2
    current = a["current_a"][in_cv]
    # It tapers, with a shoulder where the surface crosses the OCV's flat stretch (85-92 %, the DFN's shoulder:
    # 3.07 -> 2.45 A over its CV's second tenth): the current may rise there by under 1 % of the CC current.
    later_max = np.maximum.accumulate(current[::-1])[::-1]
    assert current[0] > 4.0 and current[-1] < 0.1 and np.all(later_max[10:] - current[10:] < 0.05)
    assert np.all(np.abs(a["voltage_v"][in_cv][5:] - 4.2) < 0.005)


def test_lipo_seed_macro_is_cc_then_cv_tapering_to_its_end():
    r = run("LiPo", capacity=2000, series=3, current=2.0)
    assert [p.reason for p in r.phases] == ["IF(V>4.1S) STOP_FAZE", "IF(I<0.1A) STOP_FAZE"]
    assert r.phases[1].v_end == pytest.approx(12.6, abs=0.01)


def test_life_cc_about_an_hour_then_a_short_cv():
    r = run("LiFe-CCCV", capacity=2300, series=1, current=2.3)
    a = r.log.arrays()
    cc_end = a["time_s"][np.argmax(a["current_a"] < 2.29)]
    assert 0.85 <= cc_end / 3600 <= 1.1
    assert (r.phases[0].end_s - cc_end) / 3600 < 0.15


# A bulk charge to 2.40 V per cell, then a TRICKLE top-up between 2.25 and 2.40 V (the standard
# Pb-float was this until it gained an absorption stage and a float at 2.27 V: issue 25).
BULK_THEN_TRICKLE = """MACRO Pb-trickle
  AKK_TYPE=Pb
  CHARGE_SECTION
    FAZE
      CONSTANT_I=INPUT
      IF(V>2.4S) STOP_FAZE
    END_FAZE
    FAZE
      TRICKLE(0.1C, 2.25S, 2.4S)
      IF(tf>6h) STOP_FAZE
    END_FAZE
  END_SECTION
END_MACRO
"""


def test_lead_acid_reaches_2_40_v_at_80_to_90_percent_then_trickle_holds_it_between_its_limits():
    r = run(BULK_THEN_TRICKLE, capacity=7000, series=6, current=1.75, soc=0.2)
    bulk, float_ = r.phases
    assert bulk.reason == "IF(V>2.4S) STOP_FAZE" and 0.80 <= bulk.soc_end <= 0.90
    a = r.log.arrays()
    in_float = a["phase"] == 2
    v = a["voltage_v"][in_float] / 6
    i = a["current_a"][in_float]
    assert v.max() <= 2.40 + 0.02 and v.min() >= 2.25 - 0.02
    switches = np.count_nonzero(np.diff((i > 0).astype(int)))
    assert switches >= 4                      # the top-up switches on and off


def test_training_reports_the_capacity_of_each_discharge():
    r = run("LiPo", "train", capacity=2000, series=3, current=2.0, repetitions=3)
    sections = [(p.section, p.repetition) for p in r.phases]
    assert sections == [("discharge", 1), ("charge", 1), ("charge", 1), ("discharge", 2), ("charge", 2),
                        ("charge", 2), ("discharge", 3), ("charge", 3), ("charge", 3)]
    reps = r.repetitions()
    assert [x["repetition"] for x in reps] == [1, 2, 3]
    assert all(1800 < x["discharged_mah"] < 2100 for x in reps)


def test_battery_overheat_ends_the_phase_by_the_default():
    r = run("NiMh-dV", capacity=2000, series=4, current=2.0, sensor=True, ambient=58.0)
    assert r.phases[0].reason == "default: T>60"


def test_heatsink_overheat_pauses_and_continues_the_macro():
    r = run("LiPo", "discharge", capacity=2000, series=3, ambient=40.0)
    kinds = [e.kind for e in r.interpreter.events]
    assert "pause" in kinds and "resume" in kinds
    assert kinds.index("pause") < kinds.index("resume")
    a = r.log.arrays()
    assert a["heatsink_c"].max() < 72
    assert r.phases[0].reason == "IF(V<2.8S) STOP_FAZE"
    # Every pause is on the phase, as the events tell it, and in the JSON.
    phase = r.phases[0]
    pauses = [e.time_s for e in r.interpreter.events if e.kind == "pause"]
    assert [p[0] for p in phase.pauses] == pauses and all(b > a for a, b in phase.pauses)
    assert r.to_json()["phases"][0]["pauses"][0] == [round(x, 1) for x in phase.pauses[0]]
    assert phase.notes[0].startswith(f"heat-sink pause {len(pauses)}x")
