"""Mutation testing of the iMAX B6 firmware's protections (docs/firmware.md, *Mutation testing*).

    .venv/bin/python tools/mutate_firmware.py [--jobs N] [--only FILE[:FIRST-LAST]]... [--kind KIND]...
                                              [--skip TEXT]... [--list] [--workdir DIR] [--timeout S]

Each mutant changes one thing in firmware/boards/imaxb6/{protect.c,protect.h,adc.c,stage.c,calib.c} or in
board.c's limits: a comparison (`>` <-> `>=`, `<` <-> `<=`, or negated), a limit constant (a #define: x2, /2,
and +-1 for the thresholds compared with readings), a number in a function (x2, /2; not an index, a shift, a
bit or a case label), a switch-off or protection call removed, an `if` that guards a limit never taken. Sites are found by tokenizing the C (comments and strings skipped, functions tracked),
never by line numbers, so the tool runs on whatever the code is today. A mutant is built as the B6 image,
its simulator and the host build of the protections, then judged by the tests that can kill it (SELECTION,
the fast host tests first, pytest -x): killed when a test fails, survived when all pass, not viable when it
does not compile. Workers run in parallel, each on its own copy of firmware/ whose build directory it keeps
(only the mutated file's objects and the link are redone). Exit status 0 when every mutant of a comparison or
a limit constant was killed, 1 otherwise."""
from __future__ import annotations

import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
BOARD = "boards/imaxb6"
HOST_TESTS = ["tests/firmware/test_fw_b6_protect.py", "tests/firmware/test_fw_b6_start_check.py",
              "tests/firmware/test_fw_b6_calib.py"]
# the simulated B6's tests of limits and faults; of its runs to a macro's end the two the balancer's hold ends, not
# `zuml calibrate`'s
ACCEPTANCE = "tests/firmware/test_fw_b6_acceptance.py::test_a_"
SIM_TESTS = ["tests/firmware/test_fw_b6_limits.py", "tests/firmware/test_fw_b6_set_points.py",
             "tests/firmware/test_fw_b6_cells.py",
             ACCEPTANCE + "fault_switches_the_output_off_within_100_ms_and_ends_the_run_with_its_reason",
             ACCEPTANCE + "hang_switches_the_output_off_within_100_ms_and_the_watchdog_reports_it",
             ACCEPTANCE + "3s_lipo_60_mv_apart_ends_its_cv_with_the_cells_within_10_mv",        # the balancer's
             ACCEPTANCE + "3s_pack_200_mv_apart_ends_normally_with_its_highest_cell_held_at_the_ceiling"]  # hold
HOST = (["build/host/libzuml_b6_logic.so"], HOST_TESTS)
BALANCE_HOST = (["build/host/libzuml_b6_logic.so"], ["tests/firmware/test_fw_b6_balance.py"])
SIM = (["imaxb6", "simavr-imaxb6"], SIM_TESTS)
# The tests that can kill a mutant of each file, in steps, fastest first: (make targets, tests). The host build
# holds protect.c, calib.c, duty.c and balance.c and takes a second; the others need the B6 image and its simulator.
SELECTION = {
    "protect.c": [HOST, SIM],
    "protect.h": [HOST, SIM],
    "calib.c": [HOST, SIM],
    "duty.c": [HOST, SIM],
    "balance.c": [BALANCE_HOST, SIM],
    "adc.c": [SIM],
    "stage.c": [SIM],
    "board.c": [SIM],
}
# board.c is mostly the protocol and the panel: only its limits are mutated.
FUNCTIONS = {"board.c": {"slow_limits", "hal_run_start", "watch", "hal_output"}}
DEFINES = {"board.c": re.compile(r"LIMIT|CAPACITY|CAL_OUTPUT|SLOW_MS|SINK")}
# thresholds compared with readings: an LSB matters, so they get +-1 too
LSB_DEFINES = re.compile(r"^(TRIP_|CELL_|PROBE_|PROTECT_DEBOUNCE)")
REMOVABLE_CALLS = {"stage_off", "protect_raise", "condition", "condition_after", "counted", "cells", "cell"}
KILLERS_FIRST = 4        # at most this many of a file's earlier killers run first
KINDS = ("compare", "constant", "literal", "call", "guard")
TARGET_KINDS = ("compare", "constant", "literal")     # every one of these should be killed
BOUNDARY = {">": ">=", ">=": ">", "<": "<=", "<=": "<"}
NEGATION = {">": "<=", ">=": "<", "<": ">=", "<=": ">", "==": "!=", "!=": "=="}

TOKEN = re.compile(r"""
    (?P<space>\s+) | (?P<comment>/\*.*?\*/|//[^\n]*) | (?P<string>"(?:\\.|[^"\\\n])*"|'(?:\\.|[^'\\\n])*')
  | (?P<number>0[xX][0-9a-fA-F]+[uUlL]*|\d+[uUlL]*) | (?P<name>[A-Za-z_]\w*)
  | (?P<op><<=|>>=|->|\+\+|--|<<|>>|<=|>=|==|!=|&&|\|\||[-+*/%&|^!~<>=?:;,.(){}\[\]#\\])
""", re.S | re.X)


@dataclass(frozen=True)
class Token:
    kind: str
    text: str
    start: int


@dataclass(frozen=True)
class Mutant:
    file: str          # under firmware/boards/imaxb6
    line: int
    function: str      # the function, or "#define NAME"
    kind: str          # one of KINDS
    start: int         # the replaced span of the file's text
    end: int
    original: str
    replacement: str

    def apply(self, text: str) -> str:
        return text[:self.start] + self.replacement + text[self.end:]

    def describe(self) -> str:
        original, replacement = (" ".join(s.split()) for s in (self.original, self.replacement))
        return f"{self.file}:{self.line} {self.function}: {self.kind} `{original}` -> `{replacement}`"


def tokenize(text: str) -> list[Token]:
    """The C tokens of `text` without spaces and comments; preprocessor lines keep their `#`."""
    tokens, at = [], 0
    while at < len(text):
        m = TOKEN.match(text, at)
        if not m:
            raise ValueError(f"cannot tokenize at offset {at}: {text[at:at + 20]!r}")
        if m.lastgroup not in ("space", "comment"):
            tokens.append(Token(m.lastgroup, m.group(), at))
        at = m.end()
    return tokens


def _line_of(text: str, offset: int) -> int:
    return text.count("\n", 0, offset) + 1


def _define_mutants(file: str, text: str, start: int, end: int) -> list[Mutant]:
    """`#define NAME VALUE` with VALUE an integer or a parenthesized integer product: x2, /2 (+-1)."""
    m = re.match(r"#\s*define\s+(\w+)[ \t]+(\(?[0-9][0-9A-Za-z\s*()+]*\)?)[ \t]*(?=/\*|//|$)", text[start:end])
    if not m or not re.search(r"\d", m.group(2)):
        return []
    name, value = m.group(1), m.group(2).strip()
    pattern = DEFINES.get(file)
    if pattern and not pattern.search(name):
        return []
    at = start + m.start(2)
    out = [f"(({value}) * 2)", f"(({value}) / 2)"]
    if LSB_DEFINES.match(name) and re.fullmatch(r"\d+[uUlL]*", value):
        out += [f"({value} + 1)", f"({value} - 1)"]
    return [Mutant(file, _line_of(text, at), f"#define {name}", "constant", at, at + len(value), value, r)
            for r in out]


def _if_condition_end(tokens: list[Token], k: int) -> int:
    """The index of the `)` closing the `(` at tokens[k]."""
    depth = 0
    for j in range(k, len(tokens)):
        depth += tokens[j].text == "("
        depth -= tokens[j].text == ")"
        if depth == 0:
            return j
    raise ValueError("unbalanced parentheses")


def mutants_of(file: str, text: str) -> list[Mutant]:
    """Every mutant of one source file's text, in the order of the text."""
    tokens = tokenize(text)
    allowed = FUNCTIONS.get(file)
    out: list[Mutant] = []
    depth, function, candidate, k, brackets = 0, "", "", 0, 0
    while k < len(tokens):
        t = tokens[k]
        if t.text == "#":                                  # a preprocessor line, to its (unescaped) end
            end = t.start
            while True:
                end = text.find("\n", end)
                end = len(text) if end < 0 else end
                if text[end - 1] != "\\":
                    break
                end += 1
            out += _define_mutants(file, text, t.start, end)
            while k < len(tokens) and tokens[k].start < end:
                k += 1
            continue
        if t.text == "{":
            if depth == 0:                                 # a function's body, or a table's initializer
                function = candidate if k and tokens[k - 1].text == ")" else ""
            depth += 1
        elif t.text == "}":
            depth -= 1
        elif depth == 0 and t.kind == "name" and k + 1 < len(tokens) and tokens[k + 1].text == "(":
            candidate = t.text
        brackets += (t.text == "[") - (t.text == "]")
        inside = depth > 0 and function != "" and (allowed is None or function in allowed)
        before = tokens[k - 1].text if k else ""
        if inside and t.kind == "number" and not brackets and before not in ("<<", ">>", "case", "_BV") \
                and int(re.match(r"0[xX][0-9a-fA-F]+|\d+", t.text).group(), 0) >= 2 \
                and not (before == "(" and k > 1 and tokens[k - 2].text == "_BV"):
            line = _line_of(text, t.start)
            for r in (f"({t.text} * 2)", f"({t.text} / 2)"):
                out.append(Mutant(file, line, function, "literal", t.start, t.start + len(t.text), t.text, r))
        if inside and t.kind == "op" and t.text in NEGATION:
            line = _line_of(text, t.start)
            for r in dict.fromkeys([BOUNDARY.get(t.text), NEGATION[t.text]]):
                if r:
                    out.append(Mutant(file, line, function, "compare", t.start, t.start + len(t.text), t.text, r))
        elif inside and t.kind == "name" and t.text in REMOVABLE_CALLS and k + 1 < len(tokens) \
                and tokens[k + 1].text == "(" and (k == 0 or tokens[k - 1].text in (";", "{", "}", ")", "else")):
            close = _if_condition_end(tokens, k + 1)
            if close + 1 < len(tokens) and tokens[close + 1].text == ";":
                end = tokens[close].start + 1
                out.append(Mutant(file, _line_of(text, t.start), function, "call", t.start, end,
                                  text[t.start:end], "(void)0"))
        elif inside and t.text == "if" and k + 1 < len(tokens) and tokens[k + 1].text == "(":
            close = _if_condition_end(tokens, k + 1)
            a, b = tokens[k + 1].start, tokens[close].start + 1
            out.append(Mutant(file, _line_of(text, t.start), function, "guard", a, b, text[a:b],
                              f"(0 && {text[a:b]})"))
        k += 1
    return out


def all_mutants(firmware: Path, only: list[str] | None = None, kinds: tuple[str, ...] = KINDS) -> list[Mutant]:
    """The mutants of every file in SELECTION, restricted to `only` (FILE or FILE:FIRST-LAST) and `kinds`."""
    ranges: dict[str, list[tuple[int, int]]] = {}
    for item in only or []:
        name, _, lines = item.partition(":")
        if name not in SELECTION:
            raise SystemExit(f"mutate_firmware: {name}: not one of {', '.join(SELECTION)}")
        first, _, last = lines.partition("-")
        ranges.setdefault(name, []).append((int(first or 1), int(last or first or 10 ** 9)))
    out = []
    for name in SELECTION:
        if ranges and name not in ranges:
            continue
        spans = ranges.get(name, [(1, 10 ** 9)])
        text = (firmware / BOARD / name).read_text()
        out += [m for m in mutants_of(name, text)
                if m.kind in kinds and any(first <= m.line <= last for first, last in spans)]
    return out


def first_tests(killers: list[str], tests: list[str]) -> list[str]:
    """The tests that killed earlier mutants of the same file, most recent first, that belong to this step's tests:
    a mutant is most often killed by what killed its neighbours, so these run before the step's whole set."""
    return [k for k in killers if any(k.startswith(t) if "::" in t else k.split("::")[0] == t for t in tests)]


class Worker:
    """A copy of firmware/ with its own build directory, kept across mutants."""

    def __init__(self, root: Path, timeout_s: float, killers: dict[str, list[str]] | None = None):
        self.firmware = root / "firmware"
        self.timeout_s = timeout_s
        self.killers = killers if killers is not None else {}    # per file, shared by the workers
        if not self.firmware.exists():
            shutil.copytree(ROOT / "firmware", self.firmware, ignore=shutil.ignore_patterns("build"))
        else:                      # a kept work directory: the sources as they are now, the build kept
            for src in (ROOT / "firmware").rglob("*"):
                rel = src.relative_to(ROOT / "firmware")
                if src.is_file() and rel.parts[0] != "build" and (
                        not (self.firmware / rel).exists() or (self.firmware / rel).read_bytes() != src.read_bytes()):
                    (self.firmware / rel).parent.mkdir(parents=True, exist_ok=True)
                    shutil.copy2(src, self.firmware / rel)

    def build(self, targets: list[str]) -> bool:
        done = subprocess.run(["make", "-s", "-C", str(self.firmware), *targets], capture_output=True, text=True)
        return done.returncode == 0

    def tests(self, files: list[str]) -> tuple[str, str]:
        """("killed"|"survived"|"error", the first failing test) for the test files, stopping at the first failure."""
        env = dict(os.environ, ZUML_TEST_FIRMWARE=str(self.firmware))
        try:
            done = subprocess.run([sys.executable, "-m", "pytest", "-x", "-q", "-rf", "-p", "no:cacheprovider",
                                   "-n", "0", *files], cwd=ROOT, env=env, capture_output=True, text=True,
                                  timeout=self.timeout_s)
        except subprocess.TimeoutExpired:
            return "killed", f"timeout after {self.timeout_s:.0f} s"
        failed = re.search(r"^FAILED (\S+)", done.stdout, re.M)
        if done.returncode == 0:
            return "survived", ""
        if done.returncode == 1:
            return "killed", failed.group(1) if failed else "a test failed"
        if done.returncode < 0 or "Segmentation fault" in done.stderr:
            return "killed", "the tests crashed"      # the host build of the mutant wrote out of bounds
        return "error", done.stdout[-400:] + done.stderr[-400:]

    def judge(self, mutant: Mutant) -> tuple[str, str, float]:
        started = time.monotonic()
        path = self.firmware / BOARD / mutant.file
        original = (ROOT / "firmware" / BOARD / mutant.file).read_text()
        path.write_text(mutant.apply(original))
        try:
            verdict, why = "survived", ""
            for targets, tests in SELECTION[mutant.file]:
                if not self.build(targets):
                    return "not viable", "does not compile", time.monotonic() - started
                first = first_tests(self.killers.get(mutant.file, []), tests)[:KILLERS_FIRST]
                verdict, why = self.tests(first) if first else ("survived", "")
                if verdict == "survived":
                    verdict, why = self.tests(tests + [f"--deselect={k}" for k in first])
                if verdict == "killed" and "::" in why:
                    # The test function, all its cases: a case's id may hold spaces, which `FAILED (\S+)` cuts.
                    killer = why.split("[")[0]
                    known = self.killers.setdefault(mutant.file, [])
                    if killer in known:
                        known.remove(killer)
                    known.insert(0, killer)
                if verdict != "survived":
                    break
            return verdict, why, time.monotonic() - started
        finally:
            path.write_text(original)


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--jobs", type=int, default=os.cpu_count() or 1, help="mutants judged at once (default: cores)")
    p.add_argument("--only", action="append", metavar="FILE[:FIRST-LAST]",
                   help=f"only this file (one of {', '.join(SELECTION)}), or these lines of it; repeatable")
    p.add_argument("--kind", action="append", choices=KINDS, help="only this kind of mutant; repeatable")
    p.add_argument("--skip", action="append", metavar="TEXT", default=[],
                   help="leave out the mutants whose description (as --list prints it) holds TEXT, e.g. ones judged "
                        "equivalent by reading (docs/firmware.md says which); repeatable")
    p.add_argument("--list", action="store_true", help="list the mutants and stop")
    p.add_argument("--workdir", type=Path, help="keep the workers' copies here (default: a temporary directory)")
    p.add_argument("--timeout", type=float, default=600, help="a mutant's tests longer than this count as killed")
    args = p.parse_args(argv)
    mutants = [m for m in all_mutants(ROOT / "firmware", args.only, tuple(args.kind or KINDS))
               if not any(text in m.describe() for text in args.skip)]
    if args.list:
        for m in mutants:
            print(m.describe())
        print(f"{len(mutants)} mutants")
        return 0
    workdir = args.workdir or Path(tempfile.mkdtemp(prefix="zuml-mutants-"))
    jobs = max(1, min(args.jobs, len(mutants)))
    killers: dict[str, list[str]] = {}
    workers = [Worker(workdir / f"w{n}", args.timeout, killers) for n in range(jobs)]
    print(f"{len(mutants)} mutants, {jobs} workers in {workdir}", flush=True)
    steps = (HOST, SIM)
    every = sorted({t for targets, tests in steps for t in tests})
    if not all(w.build(targets) for w in workers for targets, _ in steps):
        print("mutate_firmware: the unmutated firmware does not build: fix that first")
        return 2
    verdict, why = workers[0].tests(every)
    if verdict != "survived":
        print(f"mutate_firmware: the tests fail on the unmutated firmware ({why.strip()}): fix that first")
        return 2
    free = list(workers)
    results: list[tuple[Mutant, str, str, float]] = []

    def judge(m: Mutant) -> None:
        w = free.pop()
        try:
            verdict, why, seconds = w.judge(m)
        finally:
            free.append(w)
        results.append((m, verdict, why, seconds))
        print(f"[{len(results)}/{len(mutants)}] {verdict:10} {seconds:5.1f} s  {m.describe()}"
              + (f"  ({why})" if why and verdict != "survived" else ""), flush=True)

    with ThreadPoolExecutor(jobs) as pool:
        list(pool.map(judge, mutants))
    print("\nsurvivors:")
    for m, verdict, why, _ in sorted(results, key=lambda r: (r[0].file, r[0].start)):
        if verdict in ("survived", "error"):
            print(f"  {verdict}: {m.describe()}" + (f" {why}" if verdict == "error" else ""))
    print("\nkind       killed / judged (not viable)")
    failing = False
    for kind in KINDS:
        judged = [r for r in results if r[0].kind == kind and r[1] != "not viable"]
        killed = sum(r[1] == "killed" for r in judged)
        viable = sum(1 for r in results if r[0].kind == kind) - len(judged)
        if judged:
            print(f"{kind:10} {killed:4} / {len(judged):<4} ({viable})")
        failing |= kind in TARGET_KINDS and killed < len(judged)
    seconds = [r[3] for r in results if r[1] != "not viable"]
    if seconds:
        print(f"per mutant: {sum(seconds) / len(seconds):.1f} s mean, {max(seconds):.1f} s at most")
    return 1 if failing else 0


if __name__ == "__main__":
    sys.exit(main())
