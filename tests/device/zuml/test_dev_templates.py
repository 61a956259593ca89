"""Issue 11.3: the charger's start templates over the protocol; START_SHABLON=n on the virtual charger."""
import pytest

from helpers import compiled
from zuml_studio.protocol import messages as m
from zuml_studio.device.errors import DeviceError
from zuml_studio.lang.eeprom import pack
from zuml_studio.domain.start_templates import StartTemplate, factory_templates

SHABLON = ("MACRO Tpl\nAKK_TYPE=NiMh\nSTART_SHABLON={n}\nCHARGE_SECTION\nFAZE\nCONSTANT_I=INPUT\n"
           "IF(DELTA_PEAK>0.01S) STOP_FAZE\nIF(tf>10min) STOP_FAZE\nEND_FAZE\nEND_SECTION\nEND_MACRO\n")


def test_templates_list_get_and_set(any_client):
    charger, client = any_client
    assert client.list_templates() == sorted(factory_templates())
    assert client.get_template(1) == factory_templates()[1]
    stored = client.set_template(7, StartTemplate("train", 3, 1500.0, 0.75, None, 4))
    assert stored == StartTemplate("train", 3, 1500.0, 0.75, None, 4) == client.get_template(7)
    if charger.virtual:
        assert device_template(charger, 7) == stored
    assert 7 in client.list_templates()
    with pytest.raises(DeviceError) as exc:
        client.get_template(9)
    # the code is the protocol's, the text each device's own
    assert exc.value.code == m.ErrorCode.NO_TEMPLATE and "start template" in str(exc.value)
    with pytest.raises(DeviceError) as exc:
        client.set_template(17, StartTemplate())
    assert exc.value.code == m.ErrorCode.BAD_RANGE and "1..16" in str(exc.value)


def device_template(charger, number):
    return charger.device.templates[number]


def test_a_macro_with_start_shablon_starts_with_the_template_values(any_client):
    charger, client = any_client
    client.set_template(5, StartTemplate("train", 1, 2000.0, 1.5, None, 4))
    client.write_image(pack([compiled(SHABLON.format(n=5)), compiled(SHABLON.format(n=6))], client.info.eeprom_size))
    assert client.start(0, "charge") == "Tpl"                  # nothing entered: the template has it all
    assert client.status().task == "train"                     # the template's task, not the one asked
    if charger.virtual:
        p = charger.device.interpreter.params
        assert (p.current_a, p.capacity_mah, p.series, p.template) == (1.5, 2000.0, 4, 5)
    client.stop()
    with pytest.raises(DeviceError) as exc:
        client.start(1, "charge", 1, 2000, 1.0, None, 4)
    assert exc.value.code == m.ErrorCode.START_ERROR and "START_SHABLON" in str(exc.value)
    if charger.virtual:
        assert "start template 6 (START_SHABLON=6) does not exist on this charger" in str(exc.value)


def test_the_passport_lockout_sees_the_templates_current(charger):
    device, port, client = charger                    # the battery's passport allows 4 A (2C of 2000 mAh)
    client.set_template(5, StartTemplate("charge", 1, 2000.0, 4.5, None, 4))
    client.write_image(pack([compiled(SHABLON.format(n=5))]))
    with pytest.raises(DeviceError) as exc:
        client.start(0, "charge", 1, 2000, 1.0, None, 4)
    assert exc.value.code == m.ErrorCode.PASSPORT_CONFLICT
    assert exc.value.lines == ["the macro charges at 4.50 A (charge phase 1: CONSTANT_I=INPUT); the battery allows 4 A"]
