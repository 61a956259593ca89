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


GOOD_LI = "FAZE CONSTANT_I=1C IF(V>4.2S) STOP_FAZE END_FAZE\nFAZE CONSTANT_V=4.2S IF(I<0.05C) STOP_FAZE END_FAZE"

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
    "W307": (charge("FAZE CONSTANT_I=3C IF(DELTA_PEAK>0.01S) STOP_FAZE END_FAZE", "AKK_TYPE=NiCd SERIES=4 CAPACITY=1000"),
             charge("FAZE CONSTANT_I=1C IF(DELTA_PEAK>0.01S) STOP_FAZE END_FAZE", "AKK_TYPE=NiCd SERIES=4 CAPACITY=1000")),
    "W308": (charge("FAZE CONSTANT_I=0.5C IF(tf>3h) STOP_FAZE END_FAZE", "AKK_TYPE=NiMh SERIES=4 CAPACITY=2000"),
             charge("FAZE CONSTANT_I=0.1C IF(tf>16h) STOP_FAZE END_FAZE", "AKK_TYPE=NiMh SERIES=4 CAPACITY=2000")),
    "W309": (charge("FAZE CONSTANT_I=1C IF(V>4.2S) STOP_FAZE IF(t>120) STOP_FAZE END_FAZE"),
             charge("FAZE CONSTANT_I=1C IF(V>4.2S) STOP_FAZE IF(t>12s) STOP_FAZE END_FAZE")),
    "W310": (charge(GOOD_LI, intro="AKK_TYPE=LiPo"), charge(GOOD_LI)),
    "E311": (charge(GOOD_LI + "\nFAZE TRICKLE(0.05C, 4.0S, 4.1S) IF(tf>1h) STOP_FAZE END_FAZE"), charge(GOOD_LI)),
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
