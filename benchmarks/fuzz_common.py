"""What the hand-run fuzzers share: byte and text mutations, hostile numbers, and one loop that
runs a parser on generated inputs, each under a time limit, and reports what escapes.

An input escapes when it raises anything but the parser's own precise errors (a crash), or when
it takes longer than the limit (a hang: SIGPROF interrupts it). The limit is the process's CPU
time (ITIMER_PROF), not the wall clock: on a machine shared with other work a wall-clock limit
counted the neighbours' load (a fit of 4 s CPU took 33 s of wall time at a load of 12 on 2 cores).
A parser allowed a longer limit (a simulation, a fit) has its inputs slower than LIMIT_S counted as
slow. Every finding's input is written
to FINDINGS (one file per kind) so it can be replayed and minimised."""
from __future__ import annotations

import collections
import random
import resource
import signal
import time
import traceback
from pathlib import Path

LIMIT_S = 2.0                                       # an input slower than this is a hang finding
MEMORY_B = 4 << 30                                  # address space: a runaway read is a MemoryError, not the OOM killer
FINDINGS = Path("/tmp/zuml-fuzz-findings")
HOSTILE_NUMBERS = ["nan", "NaN", "inf", "-inf", "Infinity", "1e999", "-1e999", "9" * 40, "-0", "0x1F", "1_000",
                   "0." + "0" * 40 + "1", "4e-320", "+", "-", ".", "1e", "٣", "１２"]


class Hang(Exception):
    """An input ran past LIMIT_S."""


def _alarm(signum, frame):
    raise Hang("over the time limit")


def mutate_bytes(rng: random.Random, data: bytes, extra: tuple[bytes, ...] = ()) -> bytes:
    """Flips, overwrites, inserts (random bytes or ``extra`` pieces), cuts, repeats, truncation."""
    buf = bytearray(data)
    for _ in range(rng.randint(1, 6)):
        kind = rng.random()
        at = rng.randrange(len(buf) + 1)
        if kind < 0.25 and buf:
            buf[at % len(buf)] ^= 1 << rng.randrange(8)
        elif kind < 0.35 and buf:
            buf[at % len(buf)] = rng.randrange(256)
        elif kind < 0.5:
            buf[at:at] = rng.randbytes(rng.randint(1, 8))
        elif kind < 0.65 and extra:
            buf[at:at] = rng.choice(extra)
        elif kind < 0.8:
            del buf[at:at + rng.randint(1, 40)]
        elif kind < 0.9 and buf:
            buf[at:at] = buf[at:at + rng.randint(1, 200)] * rng.randint(1, 4)
        else:
            del buf[at:]
    return bytes(buf)


def number_swap(rng: random.Random, text: str) -> str:
    """One number of ``text`` replaced by a hostile one (NaN, inf, huge, malformed)."""
    starts = [k for k in range(len(text)) if text[k].isdigit() and (k == 0 or not text[k - 1].isalnum())]
    if not starts:
        return text
    k = rng.choice(starts)
    end = k
    while end < len(text) and (text[end].isdigit() or text[end] in ".eE"):
        end += 1
    return text[:k] + rng.choice(HOSTILE_NUMBERS) + text[end:]


def _hangs_again(check, item, allowed: tuple, limit_s: float) -> bool:
    """Whether an input that ran past the limit does so again (else the machine stalled)."""
    signal.setitimer(signal.ITIMER_PROF, limit_s)
    try:
        check(item)
    except Hang:
        return True
    except allowed:
        pass
    except Exception:   # noqa: BLE001 - a crash on the second run is no hang; the first said what ran over
        pass
    finally:
        signal.setitimer(signal.ITIMER_PROF, 0)
    return False


class Campaign:
    """Runs parsers and keeps one row per parser for the summary table."""

    def __init__(self, seed: int):
        self.seed = seed
        self.rows: list[tuple[str, int, int, int, int, float]] = []
        FINDINGS.mkdir(parents=True, exist_ok=True)
        resource.setrlimit(resource.RLIMIT_AS, (MEMORY_B, resource.getrlimit(resource.RLIMIT_AS)[1]))
        signal.signal(signal.SIGALRM, _alarm)          # bench_log_fuzz's own wall-clock limit
        signal.signal(signal.SIGPROF, _alarm)

    def run(self, name: str, n: int, make, check, allowed: tuple, limit_s: float = LIMIT_S) -> int:
        """``limit_s`` above LIMIT_S is for a parser that legitimately takes longer (a simulation,
        a fit): an input between the two is counted as slow (and shown), past ``limit_s`` a hang."""
        rng = random.Random(f"{name}-{self.seed}")
        count: collections.Counter = collections.Counter()
        example: dict[str, object] = {}
        hangs = slow = 0
        slowest = (0.0, None)
        t0 = time.perf_counter()
        for _ in range(n):
            item = make(rng)
            signal.setitimer(signal.ITIMER_PROF, limit_s)
            began = time.process_time()
            try:
                check(item)
            except allowed:
                pass
            except Hang:
                if _hangs_again(check, item, allowed, limit_s):
                    hangs += 1
                    kind = f"hang (> {limit_s:g} s)"
                    count[kind] += 1
                    example.setdefault(kind, item)
                else:                                # the machine stalled (2 cores, shared): not the input
                    print(f"    {name}: one input ran past {limit_s:g} s once, not when run again")
            except Exception:   # noqa: BLE001 - what a fuzzer is for
                kind = traceback.format_exc().strip().splitlines()[-1][:160]
                count[kind] += 1
                if kind not in example:
                    example[kind] = item
                    print(traceback.format_exc(limit=-4))
            finally:
                signal.setitimer(signal.ITIMER_PROF, 0)
            took = time.process_time() - began
            if LIMIT_S < took < limit_s:
                slow += 1
                slowest = max(slowest, (took, item), key=lambda s: s[0])
        took = time.perf_counter() - t0
        total = sum(count.values())
        self.rows.append((name, n, total - hangs, hangs, slow, took))
        print(f"{name:<22} {n:>7} inputs  {total - hangs:>5} crashes  {hangs:>3} hangs  {slow:>3} slow  "
              f"{took:7.1f} s", flush=True)
        if slow:
            print(f"    slowest {slowest[0]:.1f} s: {repr(slowest[1])[:300]}")
        for k, (kind, item) in enumerate(example.items()):
            where = FINDINGS / f"{name.replace(' ', '_')}-{k}.txt"
            where.write_text(repr(item))
            print(f"    {count[kind]} x {kind}\n      e.g. {repr(item)[:200]}  (whole input: {where})")
        return total

    def table(self) -> None:
        print(f"\n| parser | inputs | crashes | hangs | slow (> {LIMIT_S:g} s) | seconds |")
        print("|---|---:|---:|---:|---:|---:|")
        for name, n, crashes, hangs, slow, took in self.rows:
            print(f"| {name} | {n} | {crashes} | {hangs} | {slow} | {took:.0f} |")
