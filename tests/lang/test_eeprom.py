import pytest

from helpers import SEED_MACROS, seed_text
from zuml_studio.lang.compiler import compile_source
from zuml_studio.lang.eeprom import ImageError, extract, pack, replace, slots, used_bytes

RECORDS = [compile_source(seed_text(n)).record for n in SEED_MACROS]


def test_pack_lists_every_record_with_its_check_byte():
    image = pack(RECORDS, 1024)
    assert len(image) == 1024
    found = slots(image)
    assert [s.name for s in found] == list(SEED_MACROS)
    assert all(s.ok for s in found)
    assert used_bytes(image) == sum(len(r) for r in RECORDS)
    assert set(image[used_bytes(image):]) == {0xFF}


def test_end_marker_zero_and_end_of_memory():
    exact = pack(RECORDS[:2], sum(len(r) for r in RECORDS[:2]))
    assert [s.name for s in slots(exact)] == ["Pb", "NiCd"]
    zero_marked = RECORDS[0] + b"\x00" + RECORDS[1]
    assert [s.name for s in slots(zero_marked)] == ["Pb"]


def test_a_bad_check_byte_is_reported_per_slot():
    image = bytearray(pack(RECORDS, 1024))
    image[len(RECORDS[0]) - 1] ^= 0x55
    found = slots(bytes(image))
    assert not found[0].ok and "check byte" in found[0].error.message
    assert all(s.ok for s in found[1:])


def test_extract_and_replace():
    image = pack(RECORDS, 1024)
    assert extract(image, 3) == RECORDS[3]
    new = replace(image, 1, RECORDS[5])
    assert [s.name for s in slots(new)] == ["Pb", "LiFe", "NiMh", "LiPo", "LiIon", "LiFe"]
    with pytest.raises(ImageError):
        extract(image, 6)


def test_too_many_records_do_not_fit():
    with pytest.raises(ImageError, match="need"):
        pack(RECORDS * 5, 1024)


def test_a_record_running_past_the_end_is_an_image_error():
    with pytest.raises(ImageError, match="past the end"):
        slots(RECORDS[0][:-3])
    with pytest.raises(ImageError, match="at least"):
        slots(b"\x05" + bytes(20))
