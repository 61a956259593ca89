"""Fuzz the command line: every command that runs without a charger, with random options, hostile
numbers (NaN, inf, huge, malformed) and files that are real, mutated, empty, missing, a folder or
a device, in English and in Russian. A command must end with its exit status (a precise one-line
error at worst) within its time limit; anything it raises is a crash, a slower run a hang.

Run from the repository root:  python benchmarks/fuzz_cli.py [N [SEED [COMMAND ...]]]
(N inputs for the fast commands, default 20000; simulate gets N // 10, fit and compare N // 100:
they simulate or fit for up to seconds an input).
"""
from __future__ import annotations

import contextlib
import io
import os
import random
import shutil
import stat
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(Path(__file__).resolve().parent))

from fuzz_common import HOSTILE_NUMBERS, Campaign, mutate_bytes
from zuml_studio.cli.main import main as zuml
from zuml_studio.lang.compiler import compile_source
from zuml_studio.lang.eeprom import pack

DATA = ROOT / "tests" / "data"
MACRO_FILES = sorted((ROOT / "macros").glob("*.zuml"))
NUMBERS = HOSTILE_NUMBERS + ["0", "1", "2", "4", "16", "17", "255", "256", "2000", "0.5", "1.5", "-1", "65535",
                             "1e6", "25", "60", "0.05", "1C", "2,5", ""]
SANE = ["1", "2", "3", "4", "1000", "2000", "0.5", "25"]
WORDS = ["LiPo", "NiMh", "NiCd", "Pb", "LiIon", "LiFe", "lipo", "X", "", "Ni\u00adMh", "../../etc/passwd",
         "imax_b6", "Pack A", "charge", "discharge", "train", "\x00", "a" * 300]


LINK = Path()                     # the pool's link to /dev/full, checked after every input


class Pool:
    """Files to hand the commands: real, mutated (rewritten per input), and no files at all."""

    def __init__(self, root: Path):
        self.root = root
        records = [compile_source(p.read_text("utf-8")).record for p in MACRO_FILES[:4]]
        (root / "rec.bin").write_bytes(records[0])
        (root / "img.bin").write_bytes(pack(records, 1024))
        (root / "folder").mkdir()
        self.seeds = {"zuml": [p.read_bytes() for p in MACRO_FILES],
                      "bin": [*records, pack(records, 1024)],
                      "csv": [p.read_bytes() for p in sorted((DATA / "curves").glob("*.csv"))],
                      "log": [p.read_bytes()[:20000] for p in sorted((DATA / "logs").iterdir())]}
        # Copies, never the repository's files: `zuml compile FILE` writes FILE's .bin beside it.
        real = root / "real"
        real.mkdir()
        for p in [*MACRO_FILES, *sorted((DATA / "curves").glob("*.csv"))[:3], *sorted((DATA / "logs").iterdir())[:4]]:
            shutil.copyfile(p, real / p.name)
        self.real = sorted(str(p) for p in real.iterdir()) + [str(root / "rec.bin"), str(root / "img.bin")]
        self.none = [str(root / "missing.zuml"), str(root / "folder"), "/dev/zero", "", "-", str(root / "empty.zuml")]
        (root / "empty.zuml").write_bytes(b"")
        # A device as an output, through a link of our own: a writer that renamed over /dev/full
        # itself replaced the device node (as root); here it would replace only the link.
        (root / "full").symlink_to("/dev/full")

    def file(self, rng: random.Random, kind: str | None = None) -> str:
        pick = rng.random()
        if pick < 0.3:
            return rng.choice(self.real)
        if pick < 0.4:
            return rng.choice(self.none)
        kind = kind or rng.choice(list(self.seeds))
        path = self.root / f"m{rng.randrange(4)}.{kind}"
        path.write_bytes(mutate_bytes(rng, rng.choice(self.seeds[kind])))
        return str(path)

    def output(self, rng: random.Random) -> str:
        return rng.choice([str(self.root / "out.bin"), str(self.root / "out.csv"), str(self.root / "folder"),
                           str(self.root / "no dir" / "x.bin"), str(self.root / "full")])


def number(rng: random.Random) -> str:
    """Mostly a value a command takes, so that the code past the option checks is reached too."""
    return rng.choice(NUMBERS if rng.random() < rng.hostility else SANE)


def value(*sane: str):
    """A maker of an option's value: one of ``sane`` but as often as the input's hostility a hostile number."""
    return lambda rng: rng.choice(NUMBERS if rng.random() < rng.hostility else sane)


def options(rng: random.Random, pool: Pool, table: dict) -> list[str]:
    rng.hostility = rng.choice([0.0, 0.05, 0.5])
    out: list[str] = []
    for name, value in table.items():
        if rng.random() < 0.6:
            out.append(name)
            if value is not None:
                out.append(value(rng))
    return out


def commands(pool: Pool) -> dict[str, tuple]:
    """command: (argv maker, share of N, time limit in s)."""
    num, word = number, lambda rng: rng.choice(WORDS)
    out = pool.output
    task = lambda rng: rng.choice(["charge", "discharge", "train"] * 8 + ["x", ""])
    port = ["--port", "socket://127.0.0.1:9", "--timeout", "0.05"]
    start = {"--task": task, "--cycles": value("1", "2"), "--capacity": value("500", "2000"),
             "--current": value("0.5", "2"), "--voltage": value("4.2", "8.4"), "--series": value("1", "3", "4")}
    return {
        "check": (lambda r: ["check", *[pool.file(r, "zuml") for _ in range(r.randint(1, 3))],
                             *options(r, pool, {"--no-hints": None, "--charger": word})], 1, 2.0),
        "compile": (lambda r: ["compile", pool.file(r, "zuml"),
                               *options(r, pool, {"-o": out, "--hex": None, "--listing": None})], 1, 2.0),
        "decompile": (lambda r: ["decompile", pool.file(r, "bin")], 1, 2.0),
        "image": (lambda r: ["image", *[pool.file(r, r.choice(["zuml", "bin"])) for _ in range(r.randint(1, 3))],
                             *options(r, pool, {"-o": out, "--size": num, "--list": None, "--extract": num,
                                                "--force-unsafe": None})], 1, 2.0),
        "log info": (lambda r: ["log", "info", pool.file(r, "log"), *options(r, pool, {"--json": None})], 1, 2.0),
        "log export": (lambda r: ["log", "export", pool.file(r, "log"), *options(r, pool, {"-o": out})], 1, 2.0),
        "new": (lambda r: ["new", *options(r, pool, {"--chemistry": word, "--series": num, "--capacity": num,
                                                     "--rate": num, "--sensor": None, "-o": out})], 1, 2.0),
        "slots": (lambda r: ["slots", "--port", r.choice([str(pool.root / "ttyUSB7"), "socket://127.0.0.1:9",
                                                            "socket://127.0.0.1:99999", "COM3", ""]),
                             *options(r, pool, {"--timeout": value("0.05", "1"), "--baud": value("9600", "0")})],
                  1, 2.0),
        "templates set": (lambda r: ["templates", "set", r.choice(NUMBERS), *port, *options(r, pool, start)], 1, 2.0),
        "simulate": (lambda r: ["simulate", pool.file(r, r.choice(["zuml", "bin"])), *options(r, pool, {
            **start, "--template": value("1", "16"), "--soc": value("0", "0.5", "1"), "--ambient": value("0", "25"),
            "--no-sensor": None, "--model": word, "--tick": value("1", "10"), "--noise": value("0", "5"),
            "--adc-lsb": value("0", "10"), "--seed": num, "--json": None})],
            10, 60.0),
        "fit": (lambda r: ["fit", pool.file(r, r.choice(["csv", "log"])),
                           *options(r, pool, {"--chemistry": word, "--cells": value("1", "4"), "--json": None})],
                100, 30.0),
        "compare": (lambda r: ["compare", pool.file(r, r.choice(["csv", "log"])), pool.file(r, "zuml"),
                               *options(r, pool, {"--chemistry": word, "--battery": word, "--cells": value("1", "4"),
                                                  "--capacity": value("2000"), "--json": None})], 100, 30.0),
    }


def run_zuml(argv: list[str]) -> None:
    os.environ["ZUML_LANG"] = "ru" if hash(tuple(argv)) % 3 == 0 else "en"
    err = io.StringIO()
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(err):
        try:
            code = zuml(argv)
        except SystemExit as exc:                 # argparse: a usage error, exit 2
            code = exc.code
    assert isinstance(code, int) and code in (0, 1, 2, 130), f"exit status {code!r}"
    assert "Traceback" not in err.getvalue(), err.getvalue()[-300:]
    assert stat.S_ISCHR(os.stat("/dev/full").st_mode) and LINK.is_symlink(), "a device node or a link was replaced"


def main() -> int:
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 20000
    seed = int(sys.argv[2]) if len(sys.argv) > 2 else 1
    wanted = sys.argv[3:]
    tmp = Path(tempfile.mkdtemp(prefix="zuml-fuzz-cli-"))
    os.environ["ZUML_STUDIO_CONFIG_DIR"] = str(tmp / "config")
    pool = Pool(tmp)
    global LINK
    LINK = tmp / "full"
    c = Campaign(seed)
    total = 0
    for name, (make, share, limit) in commands(pool).items():
        if not wanted or name in wanted:
            total += c.run(f"zuml {name}", max(20, n // share), make, run_zuml, (), limit)
    c.table()
    print(f"total findings: {total}")
    return 1 if total else 0


if __name__ == "__main__":
    sys.exit(main())
