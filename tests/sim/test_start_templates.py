"""Issue 11.3: START_SHABLON=n takes the start values from the charger's template n."""
import pytest

from simhelp import macro, record_of
from zuml_studio.sim.interpreter import StartError, StartParams
from zuml_studio.sim.simulate import simulate
from zuml_studio.domain.start_templates import StartTemplate, TemplateError, factory_templates

BODY = "FAZE CONSTANT_I=INPUT IF(DELTA_PEAK>0.01S) STOP_FAZE IF(tf>10min) STOP_FAZE END_FAZE"


def test_the_macros_template_gives_the_start_values():
    record = record_of(macro(BODY, intro="AKK_TYPE=NiMh START_SHABLON=5"))
    table = {5: StartTemplate("charge", 1, 1500.0, 0.75, None, 2)}
    r = simulate(record, StartParams(), templates=table)
    p = r.interpreter.params
    assert (p.capacity_mah, p.current_a, p.series, p.template) == (1500.0, 0.75, 2, 5)
    assert r.capacity_mah == 1500 and r.series == 2
    assert r.log.arrays()["current_a"][5] == pytest.approx(0.75)


def test_a_template_beats_the_values_entered_and_keeps_those_it_leaves_out():
    record = record_of(macro(BODY, intro="AKK_TYPE=NiMh START_SHABLON=2"))
    table = {2: StartTemplate("charge", 1, None, 0.5, None, None)}
    r = simulate(record, StartParams(capacity_mah=1000, current_a=2.0, series=4), templates=table)
    p = r.interpreter.params
    assert (p.capacity_mah, p.current_a, p.series) == (1000, 0.5, 4)


def test_a_missing_template_refuses_the_start_with_a_message():
    record = record_of(macro(BODY, intro="AKK_TYPE=NiMh START_SHABLON=9"))
    with pytest.raises(StartError, match=r"start template 9 \(START_SHABLON=9\) does not exist on this charger "
                                         r"\(templates: 1, 2, 3\)"):
        simulate(record, StartParams(capacity_mah=2000, current_a=1.0, series=4))


def test_a_template_chosen_at_start_is_used_when_the_macro_names_none():
    record = record_of(macro(BODY))
    r = simulate(record, StartParams(template=1))
    t = factory_templates()[1]
    assert r.interpreter.params.current_a == t.current_a and r.capacity_mah == t.capacity_mah
    with pytest.raises(StartError, match="start template 7 \\(chosen at start\\)"):
        simulate(record, StartParams(template=7))


def test_a_template_sets_the_task_too():
    record = record_of(macro(BODY, "FAZE CONSTANT_I=0.5C IF(V<1.1S) STOP_FAZE END_FAZE", intro="AKK_TYPE=NiMh "
                             "START_SHABLON=1"))
    table = {1: StartTemplate("discharge", 1, 2000.0, None, None, 4)}
    r = simulate(record, StartParams(task="charge"), templates=table)
    assert [p.section for p in r.phases] == ["discharge"]


@pytest.mark.parametrize("kw", [dict(task="fly"), dict(repetitions=0), dict(capacity_mah=1.0),
                                dict(current_a=70.0), dict(series=0)])
def test_templates_refuse_values_a_charger_cannot_hold(kw):
    with pytest.raises(TemplateError):
        StartTemplate(**kw)
