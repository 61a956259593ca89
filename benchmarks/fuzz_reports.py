"""Fuzz the commands that report on a curve or a log (issue 27): `zuml fit`, `zuml compare`,
`zuml log info` (its summary, as text and `--json`), `zuml log export`, and `zuml pack import` (into
a pack of a logbook in a temporary data folder).

Inputs are real charges and logs (tests/data) with one hostile change, as the independent campaign
of issue 27 made them: one value swapped for a hostile number (NaN, 1e308, -1e308, a 40-digit
number…), the current's sign flipped (a discharge only), the voltage running backwards (falling all
the way), one time sent back, repeated or made huge, two rows swapped, the file cut short; plus
byte mutations. Each command runs in-process (``cli.main``) under fuzz_common's limits: LIMIT_S for
log info and export, FIT_LIMIT_S for fit and compare (a fit or a simulation takes seconds; inputs
over LIMIT_S are counted as slow).

What must hold, else the input is a finding: the command exits 0, or non-zero with exactly one line
``zuml: error: …`` on stderr and no traceback; every ``--json`` output parses as strict JSON (no
NaN, no Infinity); a summary's duration is not negative and its figures are finite or null.

Run from the repository root:  python benchmarks/fuzz_reports.py [N [SEED [COMMAND ...]]]
(N inputs for log info and export, default 20000; fit and compare get N // 100, pack import N).
"""
from __future__ import annotations

import contextlib
import io
import json
import math
import os
import random
import re
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(Path(__file__).resolve().parent))

from fuzz_common import HOSTILE_NUMBERS, LIMIT_S, Campaign, mutate_bytes, number_swap
from zuml_studio.cli.main import main as zuml

DATA = ROOT / "tests" / "data"
FIT_LIMIT_S = 20.0
CURVES = [p.read_text() for p in sorted((DATA / "curves").glob("*.csv"))]
LOGS = [p.read_bytes() for p in sorted((DATA / "logs").iterdir())] + \
       [p.read_bytes() for p in sorted((DATA / "realdata").glob("*.txt"))]
MACROS = sorted((ROOT / "macros").glob("*.zuml"))
CHEMISTRIES = ["NiMh", "NiCd", "LiPo", "LiIon", "LiFe", "Pb"]
NUMBERS = HOSTILE_NUMBERS + ["1e308", "-1e308", "1e12", "-1e12", "0", "-0.0", "1e-300", "-5", "99999"]
assert CURVES and LOGS and MACROS, "the fuzzer's seeds moved"


class Finding(AssertionError):
    """The command broke its contract on this input."""


def _strict(text: str):
    def refuse(constant):
        raise Finding(f"--json printed {constant}, which is not JSON")
    return json.loads(text, parse_constant=refuse)


def run(*argv: str) -> tuple[int, str, str]:
    """The command line in-process; what it printed. A traceback escapes as the exception itself."""
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            code = zuml(list(argv))
        except SystemExit as exc:          # argparse refusing an option's value: its usage and one error line
            code = exc.code
    return code, out.getvalue(), err.getvalue()


def one_line_or_ok(code: int, err: str) -> None:
    if code == 0:
        return
    lines = err.rstrip("\n").splitlines()
    if not lines or not re.match(r"zuml( [\w-]+)*: error: ", lines[-1]):
        raise Finding(f"exit {code} without a 'zuml: error:' line: {err[-300:]!r}")
    if "Traceback" in err or len(lines[-1]) > 2000:
        raise Finding(f"exit {code}: {err[-300:]!r}")


# -- hostile curves ---------------------------------------------------------------------------
def _rows(text: str) -> tuple[list[str], list[list[str]]]:
    head = [ln for ln in text.splitlines() if ln.startswith("#") or ln.startswith("time_s")]
    rows = [ln.split(",") for ln in text.splitlines() if ln and not ln.startswith(("#", "time_s"))]
    return head, rows


def hostile_curve(rng: random.Random) -> bytes:
    text = rng.choice(CURVES)
    head, rows = _rows(text)
    kind = rng.randrange(8)
    if kind == 0:                                          # one value
        row = rng.choice(rows)
        row[rng.randrange(len(row))] = rng.choice(NUMBERS)
    elif kind == 1:                                        # a discharge only
        for row in rows:
            row[2] = str(-float(row[2]))
    elif kind == 2:                                        # the voltage falling all the way
        volts = [row[1] for row in rows][::-1]
        for row, v in zip(rows, volts):
            row[1] = v
    elif kind == 3:                                        # one time back, repeated or huge
        k = rng.randrange(1, len(rows))
        rows[k][0] = rng.choice([rows[k - 1][0], "0", rows[rng.randrange(k)][0], "1e12", "-1"])
    elif kind == 4:                                        # two rows swapped
        a, b = rng.randrange(len(rows)), rng.randrange(len(rows))
        rows[a], rows[b] = rows[b], rows[a]
    elif kind == 5:                                        # cut short
        rows = rows[:rng.randrange(len(rows) + 1)]
    elif kind == 6:
        return number_swap(rng, text).encode()
    else:
        return mutate_bytes(rng, text.encode())
    return ("\n".join(head + [",".join(r) for r in rows]) + "\n").encode()


def hostile_log(rng: random.Random) -> bytes:
    data = rng.choice(LOGS)
    kind = rng.randrange(4)
    if kind == 0:
        return mutate_bytes(rng, data)
    lines = data.split(b"\n")
    if kind == 1 and len(lines) > 2:                       # two records swapped: time goes back
        a, b = rng.randrange(len(lines)), rng.randrange(len(lines))
        lines[a], lines[b] = lines[b], lines[a]
        return b"\n".join(lines)
    if kind == 2:                                          # a record repeated further on
        k = rng.randrange(len(lines))
        lines.insert(rng.randrange(len(lines) + 1), lines[k])
        return b"\n".join(lines)
    return number_swap(rng, data.decode("latin-1")).encode("latin-1", "replace")


# -- the checks -------------------------------------------------------------------------------
class Place:
    def __init__(self, root: Path):
        self.root = root

    def file(self, data: bytes, name: str) -> str:
        path = self.root / name
        path.write_bytes(data)
        return str(path)


def check_summary(info: dict) -> None:
    if info["duration_s"] < 0:
        raise Finding(f"a negative duration, {info['duration_s']} s")
    for key in ("v_min", "v_max", "i_max_a", "charge_in_mah", "charge_out_mah", "t_min_c", "t_max_c"):
        value = info.get(key)
        if value is not None and not math.isfinite(value):
            raise Finding(f"{key} {value}")


def main() -> int:
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 20000
    seed = int(sys.argv[2]) if len(sys.argv) > 2 else 1
    wanted = set(sys.argv[3:])
    c = Campaign(seed)
    tmp = Path(tempfile.mkdtemp(prefix="zuml-fuzz-reports-"))
    place = Place(tmp)
    os.environ["ZUML_STUDIO_CONFIG_DIR"] = str(tmp / "config")
    total = 0

    def want(name: str) -> bool:
        return not wanted or name in wanted

    def fit(item):
        data, chemistry, cells = item
        args = ["fit", place.file(data, "curve.csv"), "--json"]
        args += ["--chemistry", chemistry] if chemistry else []
        args += ["--cells", cells] if cells else []
        code, out, err = run(*args)
        one_line_or_ok(code, err)
        if code == 0:
            figures = _strict(out)
            if not all(math.isfinite(v) for v in figures["params"].values()):
                raise Finding(f"a fitted parameter is not finite: {figures['params']}")

    def fit_input(rng):
        return (hostile_curve(rng), rng.choice(CHEMISTRIES + [""]),
                rng.choice(["", "", "", "1", "4", "0", "300", "nan"]))

    if want("fit"):
        total += c.run("fit", max(20, n // 100), fit_input, fit, (), FIT_LIMIT_S)

    def compare(item):
        data, macro, capacity = item
        args = ["compare", place.file(data, "curve.csv"), str(macro), "--json"]
        args += ["--capacity", capacity] if capacity else []
        code, out, err = run(*args)
        one_line_or_ok(code, err)
        if code == 0:
            _strict(out)

    def compare_input(rng):
        return hostile_curve(rng), rng.choice(MACROS), rng.choice(["", "", "2000", "inf", "nan", "-1", "1e400"])

    if want("compare"):
        total += c.run("compare", max(20, n // 100), compare_input, compare, (), FIT_LIMIT_S)

    def log_info(item):
        path = place.file(item, "log.txt")
        code, out, err = run("log", "info", path, "--json")
        one_line_or_ok(code, err)
        if code == 0:
            check_summary(_strict(out))
            code, _out, err = run("log", "info", path)
            one_line_or_ok(code, err)

    if want("log info"):
        total += c.run("log info", n, hostile_log, log_info, (), LIMIT_S)

    def log_export(item):
        code, _out, err = run("log", "export", place.file(item, "log.txt"), "-o", str(tmp / "export.csv"))
        one_line_or_ok(code, err)

    if want("log export"):
        total += c.run("log export", n, hostile_log, log_export, (), LIMIT_S)

    if want("pack import"):
        os.environ["ZUML_STUDIO_DATA_DIR"] = str(tmp / "logbook")
        assert run("pack", "add", "F", "--chemistry", "LiPo", "--cells", "4", "--capacity", "1500")[0] == 0

        def pack_import(item):
            code, _out, err = run("pack", "import", place.file(item, "pack.txt"), "--pack", "F")
            one_line_or_ok(code, err)

        total += c.run("pack import", n, lambda rng: (hostile_log if rng.random() < 0.5 else hostile_curve)(rng),
                       pack_import, (), LIMIT_S)

    c.table()
    print(f"total findings: {total}")
    return 1 if total else 0


if __name__ == "__main__":
    sys.exit(main())
