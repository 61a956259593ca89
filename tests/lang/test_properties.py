"""Property tests: round trips, and no input ever makes the language core raise."""
from hypothesis import assume, given, strategies as st

from helpers import SEED_MACROS, seed_text
from strategies import macros
from zuml_studio.lang.compiler import compile_source
from zuml_studio.lang.decoder import decode_record
from zuml_studio.lang.formatter import format_macro
from zuml_studio.lang.record import DecodeError, RecordTooLarge, check_byte, encode

SEED_RECORDS = [compile_source(seed_text(n)).record for n in SEED_MACROS]


@given(macros())
def test_text_bytes_text_bytes_is_identical(macro):
    try:
        first = encode(macro).record
    except RecordTooLarge:
        assume(False)
    text = format_macro(macro)
    compiled = compile_source(text)
    # A random macro may be legal yet dangerous: the safety lint's errors (E3xx) are not the subject here.
    assume(not compiled.errors or not all(d.code.startswith("E3") for d in compiled.errors))
    assert compiled.errors == [], (text, compiled.errors)
    assert compiled.record == first
    again = compile_source(format_macro(decode_record(first).macro))
    assert again.record == first


def _decode_or_own_error(data: bytes) -> None:
    try:
        decode_record(data)
    except DecodeError as exc:
        assert 0 <= exc.offset <= max(len(data), 1) and exc.message


@given(st.binary(max_size=300))
def test_random_bytes_decode_or_give_a_decode_error(data):
    _decode_or_own_error(data)


@given(st.sampled_from(SEED_RECORDS), st.lists(st.tuples(st.integers(0, 254), st.integers(0, 255)),
                                               min_size=1, max_size=4), st.booleans())
def test_mutated_records_with_fixed_check_byte_never_crash(record, edits, fix_check):
    data = bytearray(record)
    for at, value in edits:
        if at < len(data):
            data[at] = value
    if fix_check:
        # Keep the header plausible so the decoder gets past it into the program.
        data[0] = len(data)
        data[-1] = check_byte(bytes(data[:-1]))
    _decode_or_own_error(bytes(data))


@given(st.sampled_from(SEED_RECORDS), st.integers(0, 60), st.binary(max_size=8))
def test_truncated_or_spliced_records_never_crash(record, cut, junk):
    data = bytearray(record[:cut] + junk + record[cut + len(junk):])
    if len(data) > 1:
        data[0] = len(data)
        data[-1] = check_byte(bytes(data[:-1]))
    _decode_or_own_error(bytes(data))


@given(st.text(max_size=400))
def test_random_text_never_makes_the_checker_raise(text):
    compile_source(text)


@given(st.sampled_from([seed_text(n) for n in SEED_MACROS]), st.integers(0, 400), st.integers(0, 20),
       st.text(alphabet="()=,<>.;/ \nIFAZEVCS0123456789_", max_size=12))
def test_mutated_seed_text_never_makes_the_checker_raise(text, at, cut, insert):
    compile_source(text[:at] + insert + text[at + cut:])
