"""Bytes a battery sends are shown escaped; a passport with control bytes is flagged (issue 12, point 6)."""
from zuml_studio.protocol import passport as pp


def forged(serial: bytes = b"\x1b[2J\x1b[Hok\r\nFAKE", vendor: bytes = b"Z\x07\x00\x00") -> pp.Passport:
    image = bytearray(pp.Passport("S", "V", 3).to_bytes())
    image[0x02:0x12] = serial.ljust(16, b"\0")
    image[0x12:0x16] = vendor
    image[0x1E:0x20] = pp.check_word(image).to_bytes(2, "little")
    return pp.Passport.from_bytes(bytes(image))


def test_control_and_high_bytes_are_escaped_one_for_one():
    p = forged(b"A\x1b\x85\x7f~")
    assert pp.printable(p.serial) == "A\\x1b\\x85\\x7f~"
    assert pp.printable("plain text 123") == "plain text 123"


def test_a_passport_with_non_printable_fields_is_flagged():
    assert forged().unprintable_fields == ["serial", "vendor"]
    assert forged(b"CLEAN", b"ZUML").unprintable_fields == []
