"""The serial monitor's bytes as text or hex, and a send line read back into bytes."""
import re

import pytest

from zuml_studio.device.links.serial_text import SendLineError, as_hex, as_text, parse_send


def test_text_keeps_printable_bytes_and_line_breaks_and_escapes_the_rest():
    assert as_text(b"V=4.20\r\nI=1.0\t\x00\xff") == "V=4.20\nI=1.0\t\\x00\\xff"


def test_hex_is_two_digits_a_byte_so_chunks_join_up():
    assert as_hex(b"\x55\xaa") + as_hex(b"\x01") == "55 aa 01 "


@pytest.mark.parametrize("line, hex_mode, ending, sent", [
    ("PING", False, "crlf", b"PING\r\n"),
    ("a\\x00b\\n\\\\", False, "none", b"a\x00b\n\\"),
    ("55 aa 01", True, "none", b"\x55\xaa\x01"),
    ("0x55aa", True, "lf", b"\x55\xaa\n"),
    ("Ω", False, "cr", "Ω".encode() + b"\r"),
])
def test_a_send_line_is_the_bytes_it_says(line, hex_mode, ending, sent):
    assert parse_send(line, hex_mode, ending) == sent


@pytest.mark.parametrize("line, hex_mode, says", [
    ("5", True, "not hex bytes"),
    ("zz", True, "not hex bytes"),
    ("a\\q", False, "unknown escape \\q at column 2"),
])
def test_a_bad_send_line_is_refused_in_one_line(line, hex_mode, says):
    with pytest.raises(SendLineError, match=re.escape(says)) as refused:
        parse_send(line, hex_mode)
    assert "\n" not in str(refused.value)
