"""The virtual charger refuses to START what exceeds its battery's limits: the last line of
defence behind the host's safety check (issue 12, point 1)."""
import pytest

from helpers import compiled, unsafe_record
from zuml_studio.protocol import messages as m
from zuml_studio.device.errors import DeviceError
from zuml_studio.lang.eeprom import pack


def test_start_of_a_record_above_the_passports_chemistry_maximum_is_refused(make_charger, make_client):
    device, port = make_charger(battery="LiIon:2000:1", speed=20000)
    client = make_client(port)
    client.write_image(pack([unsafe_record(), compiled("LiIon-CCCV")], 1024))
    with pytest.raises(DeviceError) as refused:
        client.start(0, series=1, capacity_mah=2000)
    assert refused.value.code == m.ErrorCode.PASSPORT_CONFLICT
    assert any(line.startswith("E303") for line in refused.value.lines), refused.value.lines
    assert client.status().state == "idle"
    assert client.start(1, current_a=1.0, capacity_mah=2000, series=1) == "LiIon-CCCV"
