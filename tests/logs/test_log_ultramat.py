"""Graupner Ultramat 18 and Ultra Duo Plus 45 recordings: the real frames of the two .lov files
(tests/data/realdata/ultramat_frames_extracted.txt, extracted from DataExplorer's test samples),
read as a raw capture and inside a LogView container. The expected values are cut from the hex
text here, by the field positions of shared/realdata/ultramat.md and DataExplorer's layouts."""
from pathlib import Path

import pytest
from logdata import data

from zuml_studio.logs import LogFormatError, read_log

FRAMES = Path(__file__).resolve().parents[1] / "data" / "realdata" / "ultramat_frames_extracted.txt"
RECORD_TAIL = b"\x00\x00\x00\x00\x01\x00\x00\x00"      # what follows each frame in the real Ultramat 16 .lov


def sections() -> dict[str, list[str]]:
    out: dict[str, list[str]] = {}
    for line in FRAMES.read_text().splitlines():
        if line.startswith("## "):
            current = line[3:].split("_", 1)[0]
            out[current] = []
        elif line and not line.startswith("#"):
            out[current].append(line.strip())
    return out


def lov(device: str, frames: list[str]) -> bytes:
    """The real Ultramat 16 .lov with another device name and these frames as its records."""
    raw = data("Ultramat16_2011-04-21_Test_Ultramat16.lov")
    at = raw.index(b"Name=Ultramat 16")
    length = int.from_bytes(raw[at - 4:at], "little")
    name = f"Name={device}".encode()
    head = raw[:at - 4] + len(name).to_bytes(4, "little") + name + raw[at + length:]
    head = head[:head.index(b"\x0c8236")]            # up to the first frame
    return head + b"".join(b"\x0c" + f.encode() + b"\r" + RECORD_TAIL for f in frames)


def field(frame: str, at: int, size: int = 4) -> int:
    """The hex field at ``at`` counting the 0x0C (the text lines leave it out)."""
    return int(frame[at - 1:at - 1 + size], 16)


def test_ultramat_18_lov_reads_its_discharge():
    frames = sections()["Ultramat18"]
    log = read_log(lov("Graupner Ultramat 18", frames))
    assert (log.format, log.device, len(log.samples), log.bad_records) == (
        "logview-lov", "Graupner Ultramat 18", 38, 0)
    assert all(field(f, 9, 2) == 2 for f in frames)            # mode 2: discharging, every frame
    for s, f in zip(log.samples, frames):
        assert s.voltage_v == field(f, 13) / 1000
        assert s.current_a == -field(f, 17) / 1000
        assert s.section == "discharge" and s.running
    assert log.samples[-1].mah_out == pytest.approx(field(frames[-1], 21), abs=0.5) and log.samples[-1].mah_in == 0
    assert [p.state for p in log.phases()] == ["discharge"]
    assert log.samples[-1].time_s == 37.0


def test_ultra_duo_plus_45_lov_reads_the_outlet_that_charges():
    frames = sections()["UltraDuoPlus45"]
    log = read_log(lov("Graupner Ultra Duo Plus 45", frames))
    assert (log.device, len(log.samples), log.bad_records) == ("Graupner Ultra Duo Plus 45", 157, 0)
    # Outlet 1 runs nothing (mode 0) in every frame; outlet 2 charges (mode 1) from the first.
    assert {field(f, 15, 2) for f in frames} == {0} and {field(f, 101, 2) for f in frames} == {1}
    for s, f in zip(log.samples, frames):
        assert s.voltage_v == field(f, 105) / 1000
        assert s.current_a == field(f, 109) / 1000
        assert s.temp_c == pytest.approx(field(f, 117) / 10)
        assert s.section == "charge"
    last = frames[-1]
    assert log.samples[-1].mah_in == pytest.approx(field(last, 113), abs=0.5) and field(last, 113) == 24
    assert log.samples[0].temp_c == 23.1 and log.samples[-1].voltage_v == 6.058
    assert log.cells == 0                      # the 4 balance taps read 0 V: not connected


def test_frames_of_a_model_without_a_layout_are_not_called_unread():
    # The checksummed 140-byte frame of an Ultra Duo Plus 40 has no layout here: the message
    # says what the records are, not "no record read (N records, 0 bad)".
    payload = "0" * 134
    frame = payload + f"{sum(payload.encode()) & 0xFFFF:04X}"
    with pytest.raises(LogFormatError, match="its 3 records are ultramat frames whose field layout is not known"):
        read_log(lov("Graupner Ultra Duo Plus 40", [frame] * 3))
