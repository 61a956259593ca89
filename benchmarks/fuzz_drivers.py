"""Fuzz every monitor-only charger decoder: random bytes and mutated real recordings, cut at
random, fed to every decoder. Counts what escapes (exceptions), implausible samples, and the
decoder's buffer and process memory (tracemalloc peak over the run).

Run from the repository root:  python benchmarks/fuzz_drivers.py [STREAMS_PER_DECODER [DRIVER ...]]
(default 100000 streams for every driver)
Budget: nothing escapes (a stream slower than fuzz_common.LIMIT_S is a hang and escapes too), no implausible sample, buffer <= its cap, memory flat (what the run
retains after each quarter does not grow; the peak is the largest sample list of one feed).
"""
from __future__ import annotations

import gc
import pathlib
import random
import signal
import sys
import time
import tracemalloc

ROOT = pathlib.Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests" / "device"))

from realdata import (ICHARGER_HID_REPORT, IMAXB6_README_FRAME, dollar_lines, imaxb6_frames,  # noqa: E402
                      isdt_frames, raw, skyrc_reply, ultramat_sections)
from zuml_studio.streams.drivers import DRIVERS  # noqa: E402
from fuzz_common import LIMIT_S, Campaign  # noqa: E402

SEEDS = [
    b"".join(line + b"\r\n" for line in dollar_lines("cheali_captured_lines_from_issues.txt")),
    raw("icharger306B_RB_1000_lines_head300.txt")[:3000],
    raw("X6_LiFe_10-3A_Cycle_2_head120.txt")[:3000],
    b"".join(imaxb6_frames()[:20]) + IMAXB6_README_FRAME,
    b"".join(ultramat_sections()["Ultramat16"][:20]) + b"".join(ultramat_sections()["Ultramat18"][:10]),
    b"".join(isdt_frames()),
    ICHARGER_HID_REPORT * 4,
    b"".join(skyrc_reply(1, k, 2 * k, 3800 + k, 300, 0, 30, [3800 + k, 3790]) for k in range(6)),
]
SPECIAL = b"$;\r\n{}\x0c\x0d\xaa\x0f\x02\x00-0123456789"


def stream(rng: random.Random) -> bytes:
    kind = rng.randrange(3)
    if kind == 0:                                        # random bytes, sometimes biased to framing bytes
        n = rng.randrange(1, 600)
        if rng.random() < 0.5:
            return bytes(rng.randrange(256) for _ in range(n))
        return bytes(rng.choice(SPECIAL) for _ in range(n))
    data = bytearray(rng.choice(SEEDS))
    start = rng.randrange(len(data))
    data = data[start:start + rng.randrange(50, 1500)]
    for _ in range(rng.randrange(1, 12 if kind == 1 else 60)):
        if not data:
            break
        at = rng.randrange(len(data))
        op = rng.randrange(5)
        if op == 0:
            data[at] ^= 1 << rng.randrange(8)
        elif op == 1:
            del data[at:at + rng.randrange(1, 30)]
        elif op == 2:
            data[at:at] = bytes(rng.randrange(256) for _ in range(rng.randrange(1, 30)))
        elif op == 3:
            data[at] = rng.choice(SPECIAL)
        else:
            data[at:at] = data[max(0, at - 80):at]          # a repeated piece
    return bytes(data)


def plausible(t) -> bool:
    return 0 <= t.voltage_v < 70 and abs(t.current_a) < 400 and t.time_s >= 0 and \
        all(-40 <= c < 70 for c in t.cells_v)


def run(name: str, count: int, seed: int = 1) -> dict:
    rng = random.Random(seed)
    escaped = implausible = samples = 0
    max_buf = 0
    dec = DRIVERS[name].decoder()                         # one long-lived decoder: memory must stay flat
    tracemalloc.start()
    peaks, kept = [], []
    t0 = time.perf_counter()
    for i in range(count):
        if i % 1000 == 0 and rng.random() < 0.3:
            dec = DRIVERS[name].decoder()
        data = stream(rng)
        at = 0
        signal.setitimer(signal.ITIMER_REAL, LIMIT_S)
        try:
            while at < len(data):
                n = rng.randrange(1, 120)
                try:
                    got = dec.feed(data[at:at + n])
                except Exception:   # noqa: BLE001 - counting what escapes (a hang too) is the point
                    escaped += 1
                    got = []
                samples += len(got)
                implausible += sum(1 for t in got if not plausible(t))
                at += n
        finally:
            signal.setitimer(signal.ITIMER_REAL, 0)
        max_buf = max(max_buf, len(dec._buf))
        if i and i % (count // 4 or 1) == 0:
            peaks.append(tracemalloc.get_traced_memory()[1])
            tracemalloc.reset_peak()
            gc.collect()
            kept.append(tracemalloc.get_traced_memory()[0])
    peaks.append(tracemalloc.get_traced_memory()[1])
    gc.collect()
    kept.append(tracemalloc.get_traced_memory()[0])
    tracemalloc.stop()
    return dict(name=name, streams=count, seconds=time.perf_counter() - t0, escaped=escaped,
                implausible=implausible, samples=samples, good=dec.good, bad=dec.bad, max_buf=max_buf,
                cap=dec.max_record, peaks_kib=[round(p / 1024) for p in peaks], kept_b=kept)


def main() -> int:
    count = int(sys.argv[1]) if len(sys.argv) > 1 else 100_000
    worst = 0
    Campaign(0)                                           # installs the time limit's signal handler
    print(f"{'decoder':<13} {'streams':>8} {'s':>7} {'escaped':>7} {'implaus.':>8} {'samples':>8} "
          f"{'max buf/cap':>11}  peak KiB / retained bytes per quarter")
    for name in sys.argv[2:] or DRIVERS:
        r = run(name, count)
        worst += r["escaped"] + r["implausible"] + (r["max_buf"] > r["cap"])
        print(f"{r['name']:<13} {r['streams']:>8} {r['seconds']:>7.1f} {r['escaped']:>7} {r['implausible']:>8} "
              f"{r['samples']:>8} {r['max_buf']:>5}/{r['cap']:<5}  {r['peaks_kib']} / {r['kept_b']}", flush=True)
    print("OK: nothing escaped" if not worst else f"FAILED: {worst} problem(s)")
    return 1 if worst else 0


if __name__ == "__main__":
    sys.exit(main())
