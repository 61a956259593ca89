"""``device.zuml.flashing.merge_record``: the rule Compile & Flash and ``zuml flash`` share."""
import pytest

from helpers import compiled
from zuml_studio.device.zuml.flashing import ImageFull, SlotOutOfRange, merge_record
from zuml_studio.lang.eeprom import pack, records


def test_append_replace_by_name_and_by_slot():
    a, b, c = compiled("NiMh-dV"), compiled("LiPo"), compiled("NiCd")
    empty = b"\xff" * 1024
    m = merge_record(empty, a)
    assert (m.index, m.name, m.replaced, m.size, m.appended) == (0, "NiMh-dV", None, len(a), True)
    assert m.action == "appended as slot 0" and records(m.image) == [a] and len(m.image) == 1024
    m = merge_record(m.image, b)
    assert m.action == "appended as slot 1" and records(m.image) == [a, b]
    again = merge_record(m.image, a)
    assert again.action == "replaced slot 0 (NiMh-dV)" and again.image == m.image
    m = merge_record(m.image, c, slot=1)
    assert m.action == "replaced slot 1 (LiPo)" and records(m.image) == [a, c]
    m = merge_record(m.image, b, slot=2)
    assert m.action == "appended as slot 2" and m.used == len(a) + len(c) + len(b)


def test_refusals():
    a = compiled("NiMh-dV")
    image = pack([a], 1024)
    with pytest.raises(SlotOutOfRange) as bad:
        merge_record(image, a, slot=5)
    assert str(bad.value) == "slot 5: the charger has slots 0..0 (1 appends)"
    with pytest.raises(ImageFull) as full:
        merge_record(b"\xff" * 32, a)
    assert (full.value.needed, full.value.size) == (len(a), 32)
    assert str(full.value) == f"1 record needs {len(a)} bytes; the EEPROM has 32"
