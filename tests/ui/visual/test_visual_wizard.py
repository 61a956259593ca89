"""The new-macro wizard dialog: a live, checked preview; a bad answer is a red line and no OK."""
import pytest

from zuml_studio.lang.compiler import compile_source
from zuml_studio.domain.chemistry import chemistry_names
from zuml_studio.ui.visual.wizard_dialog import NewMacroWizard, default_rate, parse_rate
from zuml_studio.wizard import Answers, WizardError, new_macro


@pytest.fixture
def wizard(qtbot):
    dialog = NewMacroWizard()
    qtbot.addWidget(dialog)
    dialog.show()
    return dialog


@pytest.mark.parametrize("chemistry", chemistry_names())
@pytest.mark.parametrize("sensor", [False, True])
def test_every_chemistry_preview_compiles_without_diagnostics(wizard, chemistry, sensor):
    wizard.chemistry.setCurrentText(chemistry)
    wizard.sensor.setChecked(sensor)
    text = wizard.preview.toPlainText()
    assert text == wizard.text() == new_macro(Answers(chemistry, 3, 2200, None, sensor))
    result = compile_source(text)
    assert result.ok and result.diagnostics == []
    assert f"AKK_TYPE={chemistry}" in text
    # lithium (lint W315) and a fast nickel charge (W320: the default 1C) always state their 45 °C limit;
    # lead only with a sensor
    assert ("IF(T>" in text) == (sensor or chemistry != "Pb")
    assert wizard.ok_button().isEnabled() and not wizard.error.isVisible()
    assert wizard.rate.placeholderText() == f"default {default_rate(chemistry):g}"


def test_a_bad_rate_shows_the_error_and_disables_ok(wizard):
    wizard.rate.setText("9")
    assert not wizard.ok_button().isEnabled()
    assert wizard.error.isVisible() and "0.01C to 5C" in wizard.error.text()
    assert wizard.text() == ""
    wizard.rate.setText("abc")
    assert not wizard.ok_button().isEnabled() and "number" in wizard.error.text()
    wizard.rate.setText("0.5C")
    assert wizard.ok_button().isEnabled() and not wizard.error.isVisible()
    assert "CONSTANT_I=0.5C" in wizard.text()
    wizard.rate.setText("")
    assert "CONSTANT_I=1C" in wizard.text()


def test_a_nickel_rate_without_a_reliable_end_is_refused(wizard):
    wizard.chemistry.setCurrentText("NiMh")
    wizard.rate.setText("0.25")
    assert not wizard.ok_button().isEnabled() and "-dV" in wizard.error.text()


def test_answers_follow_the_fields(wizard):
    wizard.chemistry.setCurrentText("Pb")
    wizard.cells.setValue(6)
    wizard.capacity.setValue(7000)
    assert wizard.answers() == Answers("Pb", 6, 7000, None, False)
    assert "SERIES=6" in wizard.text() and "CAPACITY=7000" in wizard.text()
    assert wizard.objectName() == "newMacroWizard"


def test_parse_rate():
    assert parse_rate("") is None and parse_rate(" 0,5 c ") == 0.5 and parse_rate("2C") == 2
    with pytest.raises(WizardError):
        parse_rate("fast")
