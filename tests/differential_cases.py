"""The cases both differential tests run: the firmware core's (tests/firmware/test_fw_differential.py) and
the C simulation engine's (tests/sim/test_engine.py), each against the Python interpreter."""
from hypothesis import assume, strategies as st

from helpers import compiled
from strategies import macros
from zuml_studio.lang.decoder import decode_record
from zuml_studio.lang.record import DecodeError, RecordTooLarge, encode
from zuml_studio.sim.interpreter import StartParams
from zuml_studio.sim.simulate import BatterySetup

CHEMISTRIES = ("Pb", "NiCd", "NiMh", "LiPo", "LiIon", "LiFe")

# The cases of tests/sim/test_acceptance.py: (macro, task, capacity, series, current, sensor, soc, ambient, reps)
ACCEPTANCE = [
    ("NiMh-dV", "charge", 2000, 4, 2.0, False, None, 25.0, 1),
    ("NiMh-dV", "charge", 2000, 4, 2.0, True, None, 25.0, 1),
    ("NiMh", "charge", 2000, 4, 0.4, False, None, 25.0, 1),
    ("NiMh-dV", "charge", 2000, 4, 0.4, False, None, 25.0, 1),
    ("NiCd-dV", "charge", 1000, 4, 1.0, False, None, 25.0, 1),
    ("NiMh-dV", "charge", 1000, 4, 1.0, False, None, 25.0, 1),
    ("NiCd", "charge", 2000, 4, 2.0, False, None, 25.0, 1),
    ("NiMh", "charge", 2000, 4, 2.0, False, None, 25.0, 1),
    ("LiIon-CCCV", "charge", 5000, 1, 5.0, True, None, 25.0, 1),
    ("LiPo", "charge", 2000, 3, 2.0, True, None, 25.0, 1),
    ("LiFe-CCCV", "charge", 2300, 1, 2.3, True, None, 25.0, 1),
    ("Pb-float", "charge", 7000, 6, 1.75, True, 0.2, 25.0, 1),
    ("LiPo", "train", 2000, 3, 2.0, True, None, 25.0, 3),
    ("NiMh-dV", "charge", 2000, 4, 2.0, True, None, 58.0, 1),
    ("LiPo", "discharge", 2000, 3, None, True, None, 40.0, 1),
]


def text(intro: str, discharge: str, between: str, charge: str, tail: str = "MUSIC(STOP)") -> bytes:
    return compiled(f"MACRO T\n{intro}\nDISCHARGE_SECTION\n{discharge}\nEND_SECTION\n{between}\n"
                    f"CHARGE_SECTION\n{charge}\nEND_SECTION\n{tail}\nEND_MACRO\n")


LIPO = "AKK_TYPE=LiPo SERIES=3"
# Issue #11's semantics, each on both: (record, task, entered current, template chosen at start, sensor, soc)
ISSUE_11 = {
    "storage discharge CC-CV": (text(LIPO, "FAZE CONSTANT_I=0.5C CONSTANT_V=3.8S IF(I<0.05C) STOP_FAZE END_FAZE",
                                     "", ""), "discharge", None, None, True, None),
    "discharge CV alone": (text(LIPO, "FAZE CONSTANT_V=3.9S IF(I<0.1A) STOP_FAZE END_FAZE", "", ""),
                           "discharge", 0.3, None, True, None),
    "commands between the sections": (text(LIPO, "FAZE CONSTANT_I=0.5A IF(V<3.9S) STOP_FAZE END_FAZE",
                                           "MUSIC(1) LIGHT(2)", "FAZE CONSTANT_I=1A IF(V>4.0S) STOP_FAZE END_FAZE"),
                                      "train", None, None, True, None),
    "commands between an empty discharge and the charge": (text(LIPO, "", "MUSIC(2)", ""), "discharge", None, None, True,
                                                             0.1),
    "STOP_MACRO runs the conclusion": (text(LIPO + " IF(tm>10min) STOP_MACRO", "", "LIGHT(3)",
                                            "FAZE CONSTANT_I=1A IF(V>4.2S) STOP_FAZE END_FAZE "
                                            "FAZE CONSTANT_I=0.1A IF(tf>1h) STOP_FAZE END_FAZE"), "charge", None, None, True, None),
    "START_SHABLON": (text("START_SHABLON=2 AKK_TYPE=LiPo", "", "",
                           "FAZE CONSTANT_I=INPUT CONSTANT_V=4.2S IF(I<0.1C) STOP_FAZE END_FAZE"), "discharge", None,
                      None, True, None),
    "START_SHABLON the charger lacks": (text("START_SHABLON=9 AKK_TYPE=LiPo", "", "",
                                             "FAZE CONSTANT_I=1A IF(V>4.2S) STOP_FAZE END_FAZE"), "charge", 1.0, None, True, None),
    "template chosen at start": (text("AKK_TYPE=NiMh", "", "", "FAZE CONSTANT_I=INPUT IF(DELTA_PEAK>10mV) STOP_FAZE "
                                      "IF(tf>3h) STOP_FAZE END_FAZE"), "charge", None, 1, False, None),
    "-dV after the charger's hold-off": (text("AKK_TYPE=NiMh SERIES=4", "", "",
                                              "FAZE CONSTANT_I=1C IF(DELTA_PEAK>20mV) STOP_FAZE END_FAZE"),
                                         "charge", None, None, False, None),
}


@st.composite
def runs(draw):
    try:
        record = encode(draw(macros())).record
        decode_record(record)
    except (RecordTooLarge, DecodeError):
        assume(False)
    params = StartParams(draw(st.sampled_from(["charge", "discharge", "train"])), draw(st.integers(1, 3)),
                         draw(st.sampled_from([300, 2000, 5000])),
                         draw(st.none() | st.sampled_from([0.1, 1.0, 2.5])),
                         draw(st.none() | st.sampled_from([1.3, 4.2, 12.0])),
                         draw(st.integers(1, 6)), draw(st.booleans()), draw(st.none() | st.sampled_from([1, 2, 9])))
    setup = BatterySetup(draw(st.sampled_from(CHEMISTRIES)), draw(st.none() | st.sampled_from([0.5])),
                         draw(st.sampled_from([25.0, 45.0])))
    return record, params, setup, draw(st.sampled_from([10.0, 30.0]))
