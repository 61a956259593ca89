"""Where the tests' copies of real recordings are (tests/data/logs, sources in tests/data/README.md)."""
from pathlib import Path

DATA = Path(__file__).resolve().parents[1] / "data" / "logs"


def data(name: str) -> bytes:
    return (DATA / name).read_bytes()


def path(name: str) -> Path:
    return DATA / name


REALDATA = DATA.parent / "realdata"
GAP_AFTER_LINE = 2303               # the 3010B charge's middle record
GAP_S = 3.2 * 3600


def lov_from_lines(device: str, lines: list[bytes], times: list[int]) -> bytes:
    """A LogView .lov of the text records ``lines`` at ``times`` (s): the real 208B file's header
    with the device's name, each record laid out as in that file (u32 length, right-aligned
    seconds, the line, CR LF, u32 0, u32 index)."""
    raw = data("iCharger208B_Storage.lov")
    at = raw.index(b"Name=Junsi iCharger 208B")
    length = int.from_bytes(raw[at - 4:at], "little")
    name = f"Name={device}".encode()
    head = raw[:at - 4] + len(name).to_bytes(4, "little") + name + raw[at + length:]
    head = head[:head.index(b"     0;$1;") - 4]
    records = []
    for k, (seconds, line) in enumerate(zip(times, lines)):
        text = f"{seconds:>6};".encode() + line + b"\r\n"
        records.append((len(text) + 8).to_bytes(4, "little") + text + bytes(4) + k.to_bytes(4, "little"))
    return head + b"".join(records)


def gapped_3010b_lov() -> bytes:
    """The real iCharger 3010B NiMH charge (tests/data/realdata, 4606 records 2 s apart) as LogView
    writes it, with a 3.2 h hole after record GAP_AFTER_LINE (LogView paused, the charger running
    on): the shape of the recording issue 24 reports, whose original is not in the project."""
    lines = [line for line in (REALDATA / "icharger3010B_2500NiMh_lines.txt").read_bytes().splitlines() if line]
    times = [2 * k + (int(GAP_S) if k > GAP_AFTER_LINE else 0) for k in range(len(lines))]
    return lov_from_lines("Junsi iCharger 3010B", lines, times)
