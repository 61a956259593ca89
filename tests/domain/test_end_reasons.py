"""An end reason is its English words (the contract the C core and the protocol share) and carries
the code and parameters it was worded from; text that crossed the protocol reads back to its code."""
import pickle

import pytest

from zuml_studio.domain import end_reasons
from zuml_studio.domain.end_reasons import EndCode, EndReason, read

# Every reason the interpreter, the C core (firmware/core/text.c) and the virtual charger make, worded.
MADE = [(EndReason(EndCode.END_OF_MACRO), "end of macro"), (end_reasons.STOPPED, "stopped"),
        (EndReason(EndCode.CANCELLED), "cancelled"), (EndReason(EndCode.DEVICE_ERROR), "device error"),
        (EndReason(EndCode.DEFAULT_T, limit_c=60.0), "default: T>60"),
        (EndReason(EndCode.DEFAULT_DTDT, rate=1.0), "default: dT/dt>1C/min"),
        (EndReason(EndCode.DEFAULT_CAPACITY, factor=1.5), "default: capacity 1.5x"),
        (EndReason(EndCode.DEFAULT_EMPTY_DISCHARGE, end_v=0.9), "default: empty discharge section, V<0.90V/cell"),
        (EndReason(EndCode.CEILING, cell=3, volts=4.2), "balancer: cell 3 reached 4.20V (ceiling)"),
        (EndReason(EndCode.SIM_LIMIT, hours=1000.0), "limit: simulation stopped after 1000h"),
        (end_reasons.condition("IF(V>4.2S) STOP_FAZE"), "IF(V>4.2S) STOP_FAZE"),
        (EndReason(EndCode.PROTECTION, what="battery disconnected"), "protection: battery disconnected")]


@pytest.mark.parametrize("reason, words", MADE)
def test_a_reason_is_worded_from_its_code_and_reads_back_to_it(reason, words):
    assert reason == words and str(reason) == words
    back = read(words)
    assert back.code is reason.code and back.params == reason.params


@pytest.mark.parametrize("reason, words", MADE)
def test_a_reason_pickles_with_its_code(reason, words):
    back = pickle.loads(pickle.dumps(reason))
    assert back == words and back.code is reason.code


def test_a_text_not_worded_here_stays_itself():
    for text in ("", "DELTA_PEAK>0.2S", "default: T>sixty", "default: capacity 1.50x", "ended"):
        reason = read(text)
        assert reason == text and reason.code is EndCode.OTHER


def test_the_charger_and_the_simulator_end_by_default_the_macro_does_not():
    by_default = {reason.code for reason, _ in MADE if reason.by_default}
    assert by_default == {EndCode.DEFAULT_T, EndCode.DEFAULT_DTDT, EndCode.DEFAULT_CAPACITY,
                          EndCode.DEFAULT_EMPTY_DISCHARGE, EndCode.CEILING, EndCode.SIM_LIMIT}
