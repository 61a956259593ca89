"""The CSV reader's cost (issue 33 §1): the column guess on a long header field (linear and
bounded: a name is read up to csv_import.MAX_NAME characters), and a large CSV's reading time
and peak memory against the target of 4x the file.

Run: python benchmarks/bench_csv_guess.py [MB ...]   (default 100)
Prints per header field length N the guess's time, then per size the file's MB, rows, seconds and
the reading process's peak resident memory (a fresh process per size, so the peak is its own).

Measured (2 shared cores, issue 33 §1): a 100.1 MB CSV of 1 490 000 rows read in 19 s (7.4 s of CPU: the
rest is the other engineers' load) with a peak of 308 MB = 3.1x the file (the interpreter and numpy alone:
30 MB); before the Log held numpy columns (a Telemetry per row) it took 2.26 GB = 22x."""
from __future__ import annotations

import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from zuml_studio.logs import csv_import

ROWS = [f"{i * 10};{7.4 + i * 0.004:.3f};2,0".replace(".", ",") + ";1" for i in range(200)]


def guess_times() -> None:
    for label, field in (("'(' x N", lambda n: "(" * n), ("'cell' + N spaces + 'x'", lambda n: "cell" + " " * n + "x"),
                         ("'_a' x N", lambda n: "_a" * n)):
        for n in (2_000, 16_000, 50_000, 1_000_000):
            data = ("\n".join(["Zeit [s];Spannung [V];Strom [A];" + field(n)] + ROWS) + "\n").encode()
            t = time.perf_counter()
            try:
                csv_import.guess(data)
                said = ""
            except csv_import.LogFormatError as exc:       # a header past GUESS_BYTES: refused, in bounded time
                said = f"  (refused: {exc})"
            print(f"guess {label:24s} N={n:8d}: {time.perf_counter() - t:7.3f} s{said}", flush=True)


def write_csv(path: Path, megabytes: float) -> int:
    """A DataExplorer-like export: time, pack V, A, mAh, 6 cells, ';' with decimal commas."""
    rows = 0
    with path.open("w") as fh:
        fh.write("Zeit [s];Spannung [V];Strom [A];Ladung [mAh];" +
                 ";".join(f"Zelle {k} [V]" for k in range(1, 7)) + "\n")
        while fh.tell() < megabytes * 1e6:
            lines = []
            for i in range(rows, rows + 10_000):
                cells = ";".join(f"{3.7 + (i % 500) * 0.001:.3f}" for _ in range(6))
                lines.append(f"{i:.1f};{22.2 + (i % 500) * 0.006:.3f};2,500;{i * 2500 / 3600:.1f};{cells}"
                             .replace(".", ","))
            fh.write("\n".join(lines) + "\n")
            rows += 10_000
    return rows


def read_once(path: str) -> None:
    from zuml_studio.logs import read_log
    t, cpu = time.perf_counter(), time.process_time()
    log = read_log(Path(path).read_bytes(), Path(path).name)
    seconds, cpu = time.perf_counter() - t, time.process_time() - cpu
    peak_mb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    print(f"{len(log.samples)} {seconds:.2f} {peak_mb:.0f} {cpu:.2f}")


def main(sizes: list[float]) -> None:
    guess_times()
    with tempfile.TemporaryDirectory() as tmp:
        for mb in sizes:
            path = Path(tmp) / f"big{mb:g}.csv"
            rows = write_csv(path, mb)
            size = path.stat().st_size / 1e6
            out = subprocess.run([sys.executable, __file__, "--read", str(path)], capture_output=True, text=True)
            if out.returncode:
                print(out.stderr.strip().splitlines()[-1])
                continue
            samples, seconds, peak, cpu = out.stdout.split()
            print(f"read {size:6.1f} MB, {rows} rows -> {samples} samples: {float(seconds):6.1f} s "
                  f"({float(cpu):.1f} s CPU), "
                  f"peak {float(peak):6.0f} MB = {float(peak) / size:4.1f}x the file (target 4x)", flush=True)


if __name__ == "__main__":
    if sys.argv[1:2] == ["--read"]:
        read_once(sys.argv[2])
    else:
        main([float(a) for a in sys.argv[1:]] or [100.0])
