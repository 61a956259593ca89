"""The firmware's own check of a record before it runs, and its chemistry table, against the PC's."""
from hypothesis import assume, given, settings, strategies as st

from helpers import SEED_MACROS, compiled
from strategies import macros
from zuml_studio.lang.decoder import decode_record
from zuml_studio.lang.record import DecodeError, RecordTooLarge, check_byte, encode
from zuml_studio.domain.chemistry import load_chemistry
from zuml_studio.sim.interpreter import AKK_NAMES

SEED_RECORDS = [compiled(n) for n in SEED_MACROS]


@settings(max_examples=300, deadline=None)
@given(macros())
def test_every_record_the_pc_decodes_passes_the_firmwares_check(core_lib, macro):
    try:
        record = encode(macro).record
        decode_record(record)
    except (RecordTooLarge, DecodeError):
        assume(False)
    assert core_lib.zh_validate(record, len(record)) == 0


@settings(max_examples=500, deadline=None)
@given(st.sampled_from(SEED_RECORDS), st.lists(st.tuples(st.integers(0, 254), st.integers(0, 255)), min_size=1,
                                                max_size=4))
def test_mutated_records_run_only_when_the_pc_decodes_them_too_or_are_refused(core_lib, record, edits):
    data = bytearray(record)
    for at, value in edits:
        if at < len(data):
            data[at] = value
    data[-1] = check_byte(bytes(data[:-1]))
    verdict = core_lib.zh_validate(bytes(data), len(data))
    try:
        decode_record(bytes(data))
    except DecodeError:
        return                              # the firmware may still run it: its structure is sound (or refused)
    assert verdict == 0


@settings(max_examples=300, deadline=None)
@given(st.binary(max_size=300))
def test_random_bytes_never_crash_the_check(core_lib, data):
    core_lib.zh_validate(data, len(data))


def test_chemistry_table_matches_the_chemistry_data(core_lib):
    for code, name in AKK_NAMES.items():
        try:
            expected = round(load_chemistry(name).discharge_end_v * 1e6)
        except KeyError:
            expected = 0
        assert core_lib.zh_chemistry_end_uv(code) == expected, name
