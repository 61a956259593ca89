"""One test per safety-lint rule: a macro that trips it and one that does not."""
import pytest

from helpers import seed_text
from zuml_studio.lang.compiler import compile_source


def codes(text):
    result = compile_source(text)
    assert not result.errors or all(d.code.startswith("E3") for d in result.errors), result.errors
    return [d.code for d in result.diagnostics]


def charge(body, intro="AKK_TYPE=LiPo SERIES=3 CAPACITY=2000", discharge=""):
    dis = f"DISCHARGE_SECTION\n{discharge}\nEND_SECTION\n" if discharge else ""
    return f"MACRO T\n{intro}\n{dis}CHARGE_SECTION\n{body}\nEND_SECTION\nEND_MACRO\n"


GOOD_LI = ("FAZE CONSTANT_I=1C IF(V>4.2S) STOP_FAZE IF(T>45) STOP_FAZE END_FAZE\n"
           "FAZE CONSTANT_V=4.2S IF(I<0.05C) STOP_FAZE IF(T>45) STOP_FAZE END_FAZE")
NIMH = "AKK_TYPE=NiMh SERIES=4 CAPACITY=2000"
NIMH_DV = "FAZE CONSTANT_I={} IF(DELTA_PEAK>0.01S) STOP_FAZE END_FAZE"

CASES = {
    # rule code: (tripping macro, clean macro)
    "W301": (charge(GOOD_LI, intro="SERIES=3 CAPACITY=2000"), charge(GOOD_LI)),
    "W302": (charge("FAZE CONSTANT_I=1C END_FAZE"), charge(GOOD_LI)),
    "W303": (charge("FAZE CONSTANT_I=1C IF(V>4.3S) STOP_FAZE END_FAZE"), charge(GOOD_LI)),
    "E303": (charge("FAZE CONSTANT_I=1C IF(V>4.4S) STOP_FAZE END_FAZE"), charge(GOOD_LI)),
    "W304": (charge(GOOD_LI, discharge="FAZE CONSTANT_I=1C IF(V<2.8S) STOP_FAZE END_FAZE"),
             charge(GOOD_LI, discharge="FAZE CONSTANT_I=1C IF(V<3.0S) STOP_FAZE END_FAZE")),
    "W305": (charge("FAZE CONSTANT_I=1C IF(DELTA_PEAK>0.2S) STOP_FAZE END_FAZE", "AKK_TYPE=NiMh SERIES=4 CAPACITY=2000"),
             charge("FAZE CONSTANT_I=1C IF(DELTA_PEAK>0.01S) STOP_FAZE END_FAZE", "AKK_TYPE=NiMh SERIES=4 CAPACITY=2000")),
    "W306": (charge("FAZE CONSTANT_I=0.1C IF(DELTA_PEAK>0.01S) STOP_FAZE IF(tf>16h) STOP_FAZE END_FAZE",
                    "AKK_TYPE=NiMh SERIES=4 CAPACITY=2000"),
             charge("FAZE CONSTANT_I=1C IF(DELTA_PEAK>0.01S) STOP_FAZE END_FAZE", "AKK_TYPE=NiMh SERIES=4 CAPACITY=2000")),
    "W307": (charge("FAZE CONSTANT_I=4.5C IF(DELTA_PEAK>0.01S) STOP_FAZE END_FAZE", "AKK_TYPE=NiCd SERIES=4 CAPACITY=1000"),
             charge("FAZE CONSTANT_I=4C IF(DELTA_PEAK>0.01S) STOP_FAZE END_FAZE", "AKK_TYPE=NiCd SERIES=4 CAPACITY=1000")),
    "W308": (charge("FAZE CONSTANT_I=0.5C IF(tf>3h) STOP_FAZE END_FAZE", "AKK_TYPE=NiMh SERIES=4 CAPACITY=2000"),
             charge("FAZE CONSTANT_I=0.1C IF(tf>16h) STOP_FAZE END_FAZE", "AKK_TYPE=NiMh SERIES=4 CAPACITY=2000")),
    "W309": (charge("FAZE CONSTANT_I=1C IF(V>4.2S) STOP_FAZE IF(t>120) STOP_FAZE END_FAZE"),
             charge("FAZE CONSTANT_I=1C IF(V>4.2S) STOP_FAZE IF(t>12s) STOP_FAZE END_FAZE")),
    "W310": (charge(GOOD_LI, intro="AKK_TYPE=LiPo"), charge(GOOD_LI)),
    "E311": (charge(GOOD_LI + "\nFAZE TRICKLE(0.05C, 4.0S, 4.1S) IF(tf>1h) STOP_FAZE END_FAZE"), charge(GOOD_LI)),
    "W313": (charge("FAZE TRICKLE(0.2C, 1.35S, 1.45S) IF(tf>2h) STOP_FAZE END_FAZE", NIMH),
             charge("FAZE TRICKLE(0.05C, 1.35S, 1.45S) IF(tf>2h) STOP_FAZE END_FAZE", NIMH)),
    "W314": (charge("FAZE CONSTANT_I=0.1C IF(V>1.6S) STOP_FAZE END_FAZE", NIMH),
             charge("FAZE CONSTANT_I=0.1C IF(V>1.6S) STOP_FAZE IF(tf>16h) STOP_FAZE END_FAZE", NIMH)),
    "W315": (charge(GOOD_LI.replace("IF(T>45)", "IF(T>50)")), charge(GOOD_LI)),
    "W316": (charge(GOOD_LI.replace("IF(T>45) STOP_FAZE", "IF(T>45) STOP_FAZE IF(DELTA_PEAK>0.01S) STOP_FAZE", 1)),
             charge(GOOD_LI)),
    "W317": (charge("FAZE CONSTANT_I=1C IF(V>1.5S) STOP_FAZE END_FAZE", NIMH),
             charge("FAZE CONSTANT_I=1C IF(V>1.5S) STOP_FAZE IF(DELTA_PEAK>0.01S) STOP_FAZE END_FAZE", NIMH)),
    "W320": (charge(NIMH_DV.format("1C"), NIMH),
             charge("FAZE CONSTANT_I=1C IF(DELTA_PEAK>0.01S) STOP_FAZE IF(T>40) STOP_FAZE END_FAZE", NIMH)),
    "W312": (charge("FAZE CONSTANT_I=1C IF(V>4.2S) STOP_FAZE END_FAZE\nFAZE CONSTANT_I=0.5C IF(V>4.1S) STOP_FAZE END_FAZE"),
             charge("FAZE CONSTANT_I=1C IF(V>4.1S) STOP_FAZE END_FAZE\nFAZE CONSTANT_I=0.5C IF(V>4.2S) STOP_FAZE END_FAZE")),
}


@pytest.mark.parametrize("code", sorted(CASES))
def test_rule_trips_and_stays_quiet(code):
    trips, clean = CASES[code]
    assert code in codes(trips)
    assert code not in codes(clean)


def test_the_clean_lithium_macro_has_no_warning_at_all():
    assert codes(charge(GOOD_LI)) == []


def test_minus_dv_in_a_discharge_phase_is_misplaced():
    text = charge(NIMH_DV.format("1C"), NIMH, discharge="FAZE CONSTANT_I=0.5C IF(DELTA_PEAK>0.01S) STOP_FAZE "
                  "IF(V<1S) STOP_FAZE END_FAZE")
    assert codes(text).count("W316") == 1


@pytest.mark.parametrize("current, intro, message", [
    ("INPUT", NIMH, "The current is entered at start: below 0.60 A (0.3C of the declared 2000 mAh) a NiMh cell "
                    "shows no reliable -dV"),
    ("INPUT", "AKK_TYPE=NiCd SERIES=4", "The current is entered at start: below 0.5C (1 A for a 2000 mAh pack) a "
                                        "NiCd cell shows no reliable -dV"),
    ("0.4A", "AKK_TYPE=NiMh SERIES=4", "At 0.4 A the -dV of a NiMh cell is reliable only up to 1333 mAh (0.3C)"),
    ("0.2C", NIMH, "At 0.2C a NiMh cell shows no reliable -dV")])
def test_minus_dv_plausibility_also_for_entered_currents(current, intro, message):
    result = compile_source(charge(NIMH_DV.format(current), intro))
    (d,) = [d for d in result.diagnostics if d.code == "W306"]
    assert d.message.startswith(message)


def test_minus_dv_plausibility_for_charge_ex():
    text = charge("FAZE CHARGE_EX(30, 0.2C, 1, 0.1C) IF(DELTA_PEAK>0.01S) STOP_FAZE IF(tf>8h) STOP_FAZE END_FAZE",
                  NIMH)
    assert "W306" in codes(text)


def test_nicd_fast_charge_up_to_4c_is_legitimate_nimh_is_not():
    assert "W307" not in codes(charge(NIMH_DV.format("3C"), "AKK_TYPE=NiCd SERIES=4 CAPACITY=1000"))
    (d,) = [d for d in compile_source(charge(NIMH_DV.format("3C"), NIMH)).diagnostics if d.code == "W307"]
    assert d.message == "Charging NiMh at 3C is above 2C"


def test_a_fast_nickel_charge_without_a_temperature_end_warns_as_loud_as_lithium_and_a_slow_one_not():
    """Seed 001 §5.1.3: a fast charge (0.5-1C and up) is ended by temperature or voltage."""
    from zuml_studio.lang.diagnostics import Severity
    for intro in (NIMH, "AKK_TYPE=NiCd SERIES=4 CAPACITY=1000"):
        (w320,) = [d for d in compile_source(charge(NIMH_DV.format("5C"), intro)).diagnostics if d.code == "W320"]
        (w315,) = [d for d in compile_source(charge(GOOD_LI.replace("IF(T>45) STOP_FAZE", ""))).diagnostics
                   if d.code == "W315"][:1]
        assert w320.severity is w315.severity is Severity.WARNING and "no temperature limit" in w320.message
    assert "W320" not in codes(charge(NIMH_DV.format("0.4C"), NIMH))
    assert "W320" not in codes(charge(NIMH_DV.format("INPUT"), NIMH))      # judged with the current entered


def test_messages_spell_the_chemistry_as_the_spec_does():
    for text in (charge(NIMH_DV.format("0.1C"), NIMH), charge(NIMH_DV.format("3C"), NIMH),
                 charge(NIMH_DV.format("0.1C"), "AKK_TYPE=NiCd SERIES=4 CAPACITY=1000")):
        for d in compile_source(text).diagnostics:
            assert "Nimh" not in d.message and "Nicd" not in d.message


def test_charger_limits_warn_only_when_the_charger_is_known():
    from zuml_studio.sim.charger_model import load_charger
    text = charge(GOOD_LI, discharge="FAZE CONSTANT_I=1C IF(V<3.0S) STOP_FAZE END_FAZE")
    assert "W318" not in codes(text)
    result = compile_source(text, charger=load_charger("imax_b6"))
    (d,) = [d for d in result.diagnostics if d.code == "W318"]
    assert d.message == ("The macro asks 2.00 A; the iMAX B6 gives at most 1 A (discharge)")
    big = charge(GOOD_LI.replace("CONSTANT_I=1C", "CONSTANT_I=2C"), "AKK_TYPE=LiPo SERIES=6 CAPACITY=2000")
    (d,) = [d for d in compile_source(big, charger=load_charger("imax_b6")).diagnostics if d.code == "W318"]
    assert "at the nominal 22.2 V that is 89 W, the iMAX B6 gives at most 50 W (charge): about 2.25 A" in d.message


def test_the_seed_macros_show_the_thesis_warnings():
    """Issue 11.5: -dV with an entered current (NiCd, NiMh), lithium without a 45 °C limit."""
    for name in ("NiCd", "NiMh"):
        assert "W306" in codes(seed_text(name))
    for name in ("LiPo", "LiIon", "LiFe"):
        assert codes(seed_text(name)).count("W315") == 2
    assert not {"W313", "W314", "W316", "W317"} & set(codes(seed_text("Pb")))


def test_seed_nickel_macros_warn_about_their_delta_peak_and_pb_about_its_bare_time():
    for name in ("NiCd", "NiMh"):
        result = compile_source(seed_text(name))
        (d,) = [d for d in result.diagnostics if d.code == "W305"]
        assert d.line == 12 and "200 mV per cell" in d.message
    pb = compile_source(seed_text("Pb"))
    (d,) = [d for d in pb.diagnostics if d.code == "W309"]
    assert (d.line, d.column) == (16, 10) and "12s" in d.message


def test_dangerous_voltage_is_an_error_that_stops_compiling():
    result = compile_source(charge("FAZE CONSTANT_I=1C IF(V>4.4S) STOP_FAZE END_FAZE"))
    assert not result.ok and result.errors[0].code == "E303"


def test_lint_stays_quiet_on_a_macro_that_has_errors():
    result = compile_source(charge("FAZE CONSTANT_I=1 END_FAZE"))
    assert [d.code for d in result.diagnostics] == ["E201"]


def test_a_lithium_pack_on_a_charger_without_a_balancer_is_warned_once():
    from dataclasses import replace
    from zuml_studio.sim.charger_model import load_charger
    b6 = load_charger("imax_b6")
    bare = replace(b6, name="bare charger", balancer=None)
    found = [d for d in compile_source(charge(GOOD_LI), charger=bare).diagnostics if d.code == "W319"]
    assert len(found) == 1 and "LiPo charge of more than one cell" in found[0].message
    assert "bare charger has no balancer" in found[0].message
    assert (found[0].line, found[0].column) == (4, 20)    # the first phase's IF(V>4.2S)
    assert "W319" not in [d.code for d in compile_source(charge(GOOD_LI), charger=b6).diagnostics]
    one_cell = charge(GOOD_LI, "AKK_TYPE=LiPo SERIES=1 CAPACITY=2000")
    assert "W319" not in [d.code for d in compile_source(one_cell, charger=bare).diagnostics]
    nimh = charge(NIMH_DV.format("1C") + "\n", NIMH)
    assert "W319" not in [d.code for d in compile_source(nimh, charger=bare).diagnostics]
    assert "W319" not in codes(charge(GOOD_LI))           # no charger known: nothing to say
