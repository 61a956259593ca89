"""Every reader, fed random bytes and mutated real recordings: a Log or a LogFormatError,
never another exception (bounded; benchmarks/bench_log_fuzz.py runs 100 000 per reader)."""
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from logdata import data

from zuml_studio.logs import FORMATS, LogFormatError, read_log

SEEDS = {  # a small real file of each format, for mutations
    "logview-lov": "iCharger208B_Storage.lov",
    "dataexplorer-osd": "PolaronACDC_2014-08-15_LiIo_2_4000.osd",
    "session-csv": None,
    "icharger-duo-txt": "4010DUO_LiFe_2S_3A_Charge_1_CH1.txt",
    "logview-open": "LogViewOpenFormat_TimeInc_Ch1-2_2Logs.txt",
    "dataexplorer-csv": "AkkuMasterC4_2007-12-28-EmpfaengerAA4-Entladen.csv",
    "raw-capture": "../realdata/icharger208B_Storage_lines.txt",
    "csv": "../realdata/skyrc_B6ACv2_Charging_head100.csv",
}
SESSION = (b"time_s,section,phase,voltage_v,current_a,temp_c,heatsink_c,mah_in,mah_out,event\n"
           b"0.0,charge,1,4.000,1.000,25.00,30.00,0.0,0.0,\n1.0,charge,1,4.100,1.000,,30.00,0.3,0.0,\n"
           b"1.0,,,,,,,,,phase_end charge 1: IF(V>4.1) STOP_FAZE\n")


def seed(name: str) -> bytes:
    return SESSION if SEEDS[name] is None else data(SEEDS[name])


def inner_osd() -> bytes:
    import io
    import zipfile
    z = zipfile.ZipFile(io.BytesIO(data(SEEDS["dataexplorer-osd"])))
    return z.read(z.namelist()[0])


def read_or_refuse(raw: bytes, fmt: str | None) -> None:
    try:
        log = read_log(raw, "fuzz", fmt)
    except LogFormatError as exc:
        assert str(exc)
        return
    assert log.samples and log.bad_records >= 0


mutation = st.lists(st.tuples(st.sampled_from(("flip", "cut", "insert", "drop")), st.integers(0, 2**31),
                              st.binary(min_size=1, max_size=8)), min_size=1, max_size=6)


def mutate(raw: bytes, steps) -> bytes:
    buf = bytearray(raw)
    for kind, where, blob in steps:
        at = where % (len(buf) + 1)
        if kind == "flip" and buf:
            buf[at % len(buf)] ^= blob[0] or 1
        elif kind == "cut":
            del buf[at:]
        elif kind == "insert":
            buf[at:at] = blob
        elif kind == "drop":
            del buf[at:at + len(blob) * 16]
    return bytes(buf)


@pytest.mark.parametrize("fmt", [f.name for f in FORMATS])
@settings(max_examples=150)
@given(raw=st.binary(max_size=600))
def test_random_bytes(fmt, raw):
    read_or_refuse(raw, fmt)
    read_or_refuse(seed(fmt)[:200] + raw, None)


@pytest.mark.parametrize("fmt", [f.name for f in FORMATS])
@settings(max_examples=150)
@given(steps=mutation)
def test_mutated_recordings(fmt, steps):
    read_or_refuse(mutate(seed(fmt), steps), fmt)


@settings(max_examples=150)
@given(steps=mutation)
def test_mutated_osd_without_its_zip(steps):
    read_or_refuse(mutate(inner_osd(), steps), "dataexplorer-osd")
