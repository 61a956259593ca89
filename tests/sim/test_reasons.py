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


LEAD_TRIP = "protection: balance lead 3 cells"      # the B6 ended a run: its lead shows other cells than at start


def test_a_chargers_balance_lead_protection_is_said_with_the_cells_asked_for():
    assert shown_reason(LEAD_TRIP, 4, 0) == "protection: you entered 4 cells; the balance lead shows 3"
    assert shown_reason(LEAD_TRIP, 4, 2) == "protection: the macro declares 2 cells (SERIES); the balance lead shows 3"
    assert shown_reason(LEAD_TRIP) == LEAD_TRIP                 # started elsewhere: as the charger said it
    assert shown_reason("protection: over current", 4, 0) == "protection: over current"


def test_a_chargers_balance_lead_protection_in_russian(russian):
    assert shown_reason(LEAD_TRIP, 4, 0) == "защита: вы ввели 4 элемента; разъём балансира показывает 3"
    assert shown_reason(LEAD_TRIP, 5, 0) == "защита: вы ввели 5 элементов; разъём балансира показывает 3"
