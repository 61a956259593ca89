"""Hostile text sizes (issue 12, point 3). Run: python benchmarks/bench_hostile_text.py

1. Check time per keystroke on 10 000-line files (target < 5 ms): mostly comments around a
   real macro; 10 000 lines of statements (far past 255 bytes: E160); blank lines.
2. A 50 MB macro: time and peak memory until its one-line refusal (E161).
3. 300 keystrokes on a line of 1 MB: time, and the text the parse cache holds after them
   (bounded by parser._CACHE_MAX_CHARS).
"""
from __future__ import annotations

import statistics
import time
import tracemalloc
from pathlib import Path

from zuml_studio.lang import parser
from zuml_studio.lang.compiler import compile_source

ROOT = Path(__file__).resolve().parent.parent
LIPO = (ROOT / "macros" / "LiPo.zuml").read_text().splitlines()


def ten_thousand(kind: str) -> list[str]:
    if kind == "comments around a macro":
        return [f"// note {i}: a long comment line about the charge" for i in range(9_980)] + LIPO
    if kind == "statements (too large)":
        body = []
        while len(body) < 9_990:
            body += ["    FAZE", "      CONSTANT_I=1A", "      IF(tf>10min) STOP_FAZE", "    END_FAZE"]
        return ["MACRO Big", "  AKK_TYPE=NiMh", "  CHARGE_SECTION"] + body[:9_990] + ["  END_SECTION", "END_MACRO"]
    return LIPO[:5] + [""] * 9_990 + LIPO[5:]


def keystrokes(lines: list[str], at: int, count: int = 200) -> list[str]:
    out = []
    for i in range(count):
        changed = list(lines)
        changed[at] = changed[at] + f" // {i}"
        out.append("\n".join(changed))
    return out


def per_keystroke_ms(texts: list[str]) -> tuple[float, float]:
    compile_source(texts[0])
    times = []
    for text in texts[1:]:
        t0 = time.perf_counter()
        compile_source(text)
        times.append((time.perf_counter() - t0) * 1000)
    times.sort()
    return statistics.median(times), times[int(len(times) * 0.9)]


def main() -> None:
    for kind in ("comments around a macro", "statements (too large)", "blank lines in a macro"):
        lines = ten_thousand(kind)
        codes = [d.code for d in compile_source("\n".join(lines)).diagnostics if d.is_error]
        for where, at in (("middle", len(lines) // 2), ("end", len(lines) - 3)):
            med, p90 = per_keystroke_ms(keystrokes(lines, at))
            print(f"10 000 lines, {kind}, typing at the {where}: median {med:.2f} ms, p90 {p90:.2f} ms "
                  f"(target < 5 ms); errors {codes or 'none'}")

    huge = "\n".join(LIPO) + "\n" + ("// padding padding padding padding padding padding\n" * 1_000_000)
    tracemalloc.start()
    t0 = time.perf_counter()
    result = compile_source(huge)
    took = time.perf_counter() - t0
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    print(f"{len(huge) / 1e6:.0f} MB macro: {[d.code for d in result.diagnostics]} after {took * 1000:.1f} ms, "
          f"peak {peak / 1e6:.1f} MB beyond the text")

    head = "\n".join(LIPO[:5])
    long_line = "      IF(V>4.2S) STOP_FAZE // " + "x" * 999_000
    t0 = time.perf_counter()
    for i in range(300):
        compile_source(f"{head}\n{long_line}{i}\n" + "\n".join(LIPO[5:]))
    took = time.perf_counter() - t0
    print(f"300 keystrokes on a 1 MB line: {took / 300 * 1000:.1f} ms each; the parse cache holds "
          f"{parser._cache_chars / 1e6:.2f} MB of text in {len(parser._CACHE)} lines "
          f"(bound {parser._CACHE_MAX_CHARS / 1e6:.0f} MB)")

    big_number = "\n".join(LIPO[:2]) + "\n  CAPACITY=" + "9" * 990_000 + "\n" + "\n".join(LIPO[2:])
    t0 = time.perf_counter()
    codes = [d.code for d in compile_source(big_number).diagnostics if d.is_error]
    print(f"CAPACITY= with 990 000 digits: {codes} after {(time.perf_counter() - t0) * 1000:.1f} ms")


if __name__ == "__main__":
    main()
