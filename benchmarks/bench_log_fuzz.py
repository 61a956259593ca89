"""Log readers fuzzed: random bytes and mutated real recordings, N times per reader
(default 100 000). Run: python benchmarks/bench_log_fuzz.py [N] [FORMAT ...]

Every input must give a Log or a LogFormatError within fuzz_common.LIMIT_S; anything else
"escapes" (a hang: slower than the limit) and is printed (first 5 per reader). Prints per reader: inputs, read, refused, escaped, inputs/s, and the
process's resident memory at 10 %, 50 % and 100 % of the run (flat = no leak)."""
from __future__ import annotations

import gc
import io
import os
import random
import signal
import sys
import time
import traceback
import zipfile
from pathlib import Path

from zuml_studio.logs import FORMATS, LogFormatError, read_log

sys.path.insert(0, str(Path(__file__).resolve().parent))
from fuzz_common import LIMIT_S, Campaign

DATA = Path(__file__).resolve().parents[1] / "tests" / "data" / "logs"
RAW = DATA.parent / "realdata"
SESSION = (b"time_s,section,phase,voltage_v,current_a,temp_c,heatsink_c,mah_in,mah_out,event\n"
           b"0.0,charge,1,4.000,1.000,25.00,30.00,0.0,0.0,\n1.0,charge,1,4.100,1.000,,30.00,0.3,0.0,\n"
           b"1.0,,,,,,,,,phase_end charge 1: IF(V>4.1) STOP_FAZE\n") * 20


def seeds() -> dict[str, list[bytes]]:
    osd = (DATA / "PolaronACDC_2014-08-15_LiIo_2_4000.osd").read_bytes()
    z = zipfile.ZipFile(io.BytesIO(osd))
    return {
        "logview-lov": [(DATA / "iCharger208B_Storage.lov").read_bytes(),
                        (DATA / "Ultramat16_2011-04-21_Test_Ultramat16.lov").read_bytes(),
                        (DATA / "iMaxB6_Ladung3S450mAh.lov").read_bytes()[:12000]],
        "dataexplorer-osd": [osd, z.read(z.namelist()[0])],
        "session-csv": [SESSION],
        "icharger-duo-txt": [(DATA / "406DUO_Turnigy_4S_1500_A_Charge_0_CH1.txt").read_bytes()[:6000],
                             (DATA / "X6_LiFe_10-3A_Cycle_2.txt").read_bytes()[:6000]],
        "logview-open": [(DATA / f).read_bytes() for f in ("LogViewOpenFormat_TimeInc_Ch1-2_2Logs.txt",
                                                          "LogViewOpenFormat_TimeGiven_HEX.txt",
                                                          "LogViewOpenFormat_TimeGiven_Offsets_Factor.txt")],
        "dataexplorer-csv": [(DATA / "AkkuMasterC4_2007-12-28-EmpfaengerAA4-Entladen.csv").read_bytes()[:4000]],
        "raw-capture": [(RAW / f).read_bytes()[:6000] for f in (
            "cheali_captured_lines_from_issues.txt", "icharger208B_Storage_lines.txt",
            "imaxb6_Ladung3S450mAh_frames_head300.txt", "ultramat_frames_extracted.txt", "isdt_real_frames.txt")],
        "csv": [(RAW / f).read_bytes() for f in ("skyrc_B6ACv2_Charging_head100.csv",
                                                 "imaxb6_Ladung3S450mAh_decoded_head300.csv")],
    }


def mutate(rng: random.Random, raw: bytes) -> bytes:
    buf = bytearray(raw)
    for _ in range(rng.randint(1, 8)):
        kind = rng.randrange(5)
        at = rng.randrange(len(buf) + 1)
        if kind == 0 and buf:
            buf[at % len(buf)] ^= rng.randrange(1, 256)
        elif kind == 1:
            del buf[at:]
        elif kind == 2:
            buf[at:at] = rng.randbytes(rng.randint(1, 16))
        elif kind == 3:
            del buf[at:at + rng.randint(1, 200)]
        elif buf:                                     # duplicate a stretch: repeated records, headers
            end = min(len(buf), at + rng.randint(1, 300))
            buf[at:at] = buf[at:end]
    return bytes(buf)


def rss_mb() -> float:
    with open("/proc/self/statm") as fh:
        return int(fh.read().split()[1]) * os.sysconf("SC_PAGE_SIZE") / 2**20


def fuzz(fmt: str, inputs: list[bytes], n: int, rng: random.Random) -> None:
    read = refused = 0
    escaped: list[str] = []
    marks = {n // 10: "10%", n // 2: "50%", n: "100%"}
    memory = []
    start = time.perf_counter()
    for k in range(1, n + 1):
        choice = rng.random()
        if choice < 0.25:
            raw = rng.randbytes(rng.randint(0, 2000))
        elif choice < 0.35:
            raw = rng.choice(inputs)[:rng.randint(0, 300)] + rng.randbytes(rng.randint(0, 500))
        else:
            raw = mutate(rng, rng.choice(inputs))
        signal.setitimer(signal.ITIMER_REAL, LIMIT_S)
        try:
            read_log(raw, "fuzz", fmt if rng.random() < 0.8 else None)
            read += 1
        except LogFormatError:
            refused += 1
        except Exception:                              # noqa: BLE001 - counting what escapes is the point
            if len(escaped) < 5:
                escaped.append(traceback.format_exc(limit=3) + f"input: {raw[:300]!r}\n")
            else:
                escaped.append("")
        finally:
            signal.setitimer(signal.ITIMER_REAL, 0)
        if k in marks:
            gc.collect()
            memory.append(f"{marks[k]} {rss_mb():.1f}")
    elapsed = time.perf_counter() - start
    print(f"{fmt:18} {n:7d} inputs  read {read:6d}  refused {refused:6d}  escaped {len(escaped):3d}  "
          f"{n / elapsed:8.0f}/s  RSS MB: {', '.join(memory)}", flush=True)
    for text in escaped[:5]:
        print(text)


def main() -> int:
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 100_000
    wanted = sys.argv[2:] or [f.name for f in FORMATS]
    all_seeds = seeds()
    Campaign(0)                                        # installs the time limit's signal handler
    for fmt in wanted:
        fuzz(fmt, all_seeds[fmt], n, random.Random(f"{fmt}-1"))
    return 0


if __name__ == "__main__":
    sys.exit(main())
