"""Phase end reasons stay English where they are made (the firmware and the interpreter compare
them byte for byte) and are shown in the user's language."""
import pytest

from zuml_studio import i18n
from zuml_studio.sim.reasons import shown_reason

# Every kind of reason the interpreter and the firmware (firmware/core/text.c) make.
MADE = ["end of macro", "stopped", "stopped: a new macro was started", "default: T>60", "default: dT/dt>1C/min",
        "default: capacity 1.5x", "default: empty discharge section, V<0.90V/cell",
        "limit: simulation stopped after 1000h"]


@pytest.fixture
def russian():
    i18n.install("ru")
    yield
    i18n.install("en")


def test_english_is_shown_as_made():
    assert [shown_reason(r) for r in MADE] == MADE


def test_russian_translates_the_words_and_keeps_the_symbols(russian):
    shown = dict(zip(MADE, map(shown_reason, MADE)))
    assert shown["end of macro"] == "конец макроса"
    assert shown["default: dT/dt>1C/min"] == "по умолчанию: dT/dt>1C/min"
    assert shown["default: capacity 1.5x"] == "по умолчанию: ёмкость 1.5x"
    assert shown["default: empty discharge section, V<0.90V/cell"] == "по умолчанию: пустая секция разряда, V<0.90V/cell"
    assert shown["limit: simulation stopped after 1000h"] == "предел: симуляция остановлена через 1000 h"
    assert all(any("а" <= ch <= "я" for ch in text) for text in shown.values()), shown


def test_the_macros_own_conditions_are_zuml_and_pass_through(russian):
    assert shown_reason("DELTA_PEAK>0.2S") == "DELTA_PEAK>0.2S"
    assert shown_reason("") == ""
