"""How fast a log is read, and that the time grows linearly with its size (issue 27: 17 of 6 085
mutated logs took 2-5.5 s to summarise; raw captures took 5 s per MB).

Each format's real file (tests/data) is repeated to 1, 2 and 4 MB and read with `zuml log info`'s
path (``read_log`` + ``summarize``). Prints CPU seconds (the machine is shared: wall time says more
about the neighbours than about the reader) and MB/s per size: a linear reader keeps its rate.
Run: python benchmarks/bench_log_read.py [MB ...]"""
from __future__ import annotations

import lzma
import sys
import time
from pathlib import Path

from zuml_studio.logs import read_log
from zuml_studio.logs.summary import summarize

DATA = Path(__file__).resolve().parents[1] / "tests" / "data"
# (what, file, bytes before the records: a header read once)
FILES = [
    ("iCharger DUO/X text", DATA / "logs" / "406DUO_Turnigy_4S_1500_A_Charge_0_CH1.txt", 0),
    ("LogView open format", DATA / "logs" / "LogViewOpenFormat_TimeGiven_Offsets_Factor.txt", 5),
    ("DataExplorer CSV", DATA / "logs" / "AkkuMasterC4_2007-12-28-EmpfaengerAA4-Laden.csv", 2),
    ("DataExplorer record-set CSV export", DATA / "realdata" / "NiMH_AA_Rx_eStationBC6_cycle.csv.xz", 0),
    ("raw capture: iCharger lines", DATA / "realdata" / "icharger306B_RB_1000_lines_head300.txt", 0),
    ("raw capture: cheali lines", DATA / "realdata" / "cheali_captured_lines_from_issues.txt", 0),
    ("raw capture: iMAX B6 frames", DATA / "realdata" / "imaxb6_Ladung3S450mAh_frames_head300.txt", 0),
    ("raw capture: Ultramat frames", DATA / "realdata" / "ultramat_frames_extracted.txt", 0),
]


def grown(path: Path, head_lines: int, size: int) -> bytes:
    """The file with its records repeated to ``size`` bytes. Their times repeat too, so each
    repetition goes back in time and is left out (``logs.model.in_time_order``): the figures
    include that search, the worst case of a log's time order."""
    raw = lzma.decompress(path.read_bytes()) if path.suffix == ".xz" else path.read_bytes()
    lines = raw.splitlines(keepends=True)
    head, body = b"".join(lines[:head_lines]), b"".join(lines[head_lines:])
    return head + body * max(1, (size - len(head)) // len(body))


def main() -> int:
    sizes = [float(a) for a in sys.argv[1:]] or [1.0, 2.0, 4.0]
    print(f"| log | {' | '.join(f'{s:g} MB: CPU s (MB/s)' for s in sizes)} |")
    print("|---|" + "---:|" * len(sizes))
    for what, path, head in FILES:
        cells = []
        for mb in sizes:
            data = grown(path, head, int(mb * 1e6))
            t0 = time.process_time()
            summarize(read_log(data, path.name.removesuffix(".xz")))
            took = time.process_time() - t0
            cells.append(f"{took:.2f} ({len(data) / 1e6 / took:.1f})")
        print(f"| {what} | {' | '.join(cells)} |", flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
