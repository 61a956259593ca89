"""Median time to check + compile the largest legal macro (it runs on every keystroke).

Target: under 2 ms. Run: ./dev zuml ... is not needed; `python benchmarks/bench_compile.py`.
"""
from __future__ import annotations

import statistics
import time

from zuml_studio.lang.compiler import compile_source


def largest_macro() -> str:
    """As many phases with conditions as fit in 255 bytes: the worst case for the checker."""
    head = ["MACRO Largest-Macro1", "  AKK_TYPE=NiMh", "  SERIES=4", "  CAPACITY=2000",
            "  IF(Tc>70) PAUSE_MACRO", "  IF(Tc<60) CONTINUE_MACRO", "  IF(tm>10h) STOP_MACRO",
            "  DISCHARGE_SECTION", "    FAZE", "      CONSTANT_I=1C", "      IF(V<1S) STOP_FAZE", "    END_FAZE",
            "  END_SECTION", "  CHARGE_SECTION", "    CYCLE(3)"]
    phase = ["      FAZE", "        CHARGE_EX(30, 1C, 1, 0.1C, 2)", "        IF(DELTA_PEAK>0.005S) STOP_FAZE",
             "        IF(T>45) STOP_FAZE", "        IF(tf>90min) STOP_FAZE", "      END_FAZE"]
    tail = ["    END_CYCLE", "  END_SECTION", "  MUSIC(STOP)", "END_MACRO"]
    best = ""
    for n in range(1, 40):
        text = "\n".join(head + phase * n + tail) + "\n"
        if not compile_source(text).ok:
            break
        best = text
    return best


def _median_ms(texts: list[str]) -> tuple[float, float]:
    times = []
    for text in texts:
        t0 = time.perf_counter()
        compile_source(text)
        times.append(time.perf_counter() - t0)
    times.sort()
    return statistics.median(times) * 1000, times[int(len(times) * 0.9)] * 1000


def main() -> None:
    text = largest_macro()
    result = compile_source(text)
    assert result.ok
    lines = text.split("\n")
    print(f"largest legal macro: {len(result.record)} bytes, {len(lines) - 1} lines")
    # As in the editor: each run sees the text with one line changed (a keystroke), so the
    # parser's line cache holds every other line.
    at = lines.index("        IF(T>45) STOP_FAZE")
    keystrokes = ["\n".join(lines[:at] + [f"        IF(T>{40 + i % 20}) STOP_FAZE"] + lines[at + 1:])
                  for i in range(400)]
    med, p90 = _median_ms(keystrokes)
    print(f"check + compile per keystroke: median {med:.3f} ms, p90 {p90:.3f} ms (target < 2 ms)")
    # Cold: every line new to the parser (opening a file).
    cold = ["\n".join(f"{line} // {i}" if line.strip() else line for line in lines) for i in range(100)]
    med, p90 = _median_ms(cold)
    print(f"check + compile cold (file opened): median {med:.3f} ms, p90 {p90:.3f} ms")


if __name__ == "__main__":
    main()
