"""CPU time of short command-line runs, each in a fresh process (median of N; issue 16):
``zuml check FILE`` and ``zuml --help`` (in English, and in Russian: the catalogue load, issue 17) against the floor, a process that only imports the
compiler and checks the same file with it (targets: <= 1.3 x the floor).
Run: python benchmarks/bench_startup.py [N]"""
from __future__ import annotations

import os
import resource
import statistics
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
MACRO = ROOT / "macros" / "NiMh.zuml"
FLOOR = ("import sys; from zuml_studio.lang.compiler import compile_source; "
         "sys.exit(not compile_source(open(sys.argv[1], encoding='utf-8').read()).ok)")
CLI = "import sys; from zuml_studio.cli.main import main; sys.exit(main())"


def cpu_seconds(args: list[str], language: str = "en") -> float:
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    subprocess.run([sys.executable, *args], check=True, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                   env=os.environ | {"LC_ALL": "C", "ZUML_LANG": language})
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)


def median_ms(args: list[str], n: int, language: str = "en") -> float:
    cpu_seconds(args, language)            # warm: .pyc files and caches written once
    return statistics.median(cpu_seconds(args, language) for _ in range(n)) * 1000.0


def main() -> None:
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 9
    floor = median_ms(["-c", FLOOR, str(MACRO)], n)
    print(f"floor (import the compiler, check the file): {floor:.0f} ms CPU")
    for label, args in (("zuml check FILE", ["-c", CLI, "check", str(MACRO)]), ("zuml --help", ["-c", CLI, "--help"])):
        for language in ("en", "ru"):
            ms = median_ms(args, n, language)
            print(f"{label} [{language}]: {ms:.0f} ms CPU = {ms / floor:.2f} x the floor (target <= 1.3 x)")


if __name__ == "__main__":
    main()
