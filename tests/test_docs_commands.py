"""The docs' command lines against the real argument parsers, so that they cannot drift apart:
every `zuml …` and `zuml-studio …` example in the README and docs/ (code blocks and inline code,
synopses included) names commands and options that exist, with values their choices allow, and
a whole example without placeholders parses; docs/cli.md lists every option of every command;
the files the docs name exist. Nothing is run: the parsers are built and asked."""
import argparse
import re

import pytest

from helpers import ROOT
from zuml_studio.cli.main import AREAS, build_parser
from zuml_studio.ui.app import build_parser as build_studio_parser

PAGES = [ROOT / "README.md", *sorted((ROOT / "docs").rglob("*.md"))]
CLI_PAGE = ROOT / "docs" / "cli.md"
FENCE = re.compile(r"^```[^\n]*\n(.*?)^```", re.M | re.S)
SPAN = re.compile(r"`([^`\n]+(?:\n[^`\n]+)?)`")       # inline code, at most across one line break
PROGRAM = re.compile(r"(?<![\w/.~-])(zuml-studio|zuml)(?=[ \t]|$)")
PLACEHOLDER = re.compile(r"[A-Z][A-Z0-9_]*(\.[a-z]+)?(\.\.\.|…)?")   # FILE, N, OUT.csv, FILE...
OMITTED = ("…", "...")
READ_SUFFIXES = (".zuml", ".bin", ".txt", ".lov", ".osd", ".csv")


def _subparsers(parser: argparse.ArgumentParser) -> dict[str, argparse.ArgumentParser]:
    actions = [a for a in parser._actions if isinstance(a, argparse._SubParsersAction)]
    return dict(actions[0].choices) if actions else {}


def _options(parser: argparse.ArgumentParser) -> dict[str, argparse.Action]:
    return {s: a for a in parser._actions for s in a.option_strings}


def _leaves(parser: argparse.ArgumentParser, path: tuple[str, ...] = ()):
    """(command path, parser) of every command that runs something."""
    children = _subparsers(parser)
    if not children:
        yield path, parser
    for name, child in children.items():
        yield from _leaves(child, path + (name,))


ZUML = build_parser()
STUDIO = build_studio_parser()


def _command_in(text: str) -> str | None:
    """The command line in a line or span of the docs, from its program on, without a comment;
    None when it does not start one (``./dev``, ``$`` and VAR=value may come first)."""
    m = PROGRAM.search(text)
    if not m or not all(w in ("./dev", "$") or re.fullmatch(r"[A-Z_]+=\S*", w) for w in text[:m.start()].split()):
        return None
    return re.split(r"\s#\s", text[m.start():].replace("\n", " "))[0]


def _examples() -> list[tuple[str, str, bool]]:
    """(where, the command line, whether it is a whole line of a code block)."""
    found = []
    for page in PAGES:
        text = page.read_text(encoding="utf-8")
        where = page.relative_to(ROOT)
        for block in FENCE.findall(text):
            lines = block.splitlines()
            for i, line in enumerate(lines):
                command = _command_in(line)
                if command is None:
                    continue
                for more in lines[i + 1:]:          # a synopsis goes on below: indented options in brackets
                    if not re.match(r"\s+\[", more):
                        break
                    command += " " + more.strip()
                found.append((f"{where}: {line.strip()}", command, True))
        for span in SPAN.findall(FENCE.sub("", text)):
            command = _command_in(span)
            if command is not None:
                found.append((f"{where}: `{span}`", command, False))
    return found


EXAMPLES = _examples()


def _tokens(command: str) -> list[str]:
    return command.replace("\\|", "|").replace("[", " ").replace("]", " ").split()


def _check(command: str) -> list[str]:
    """What in one example does not match the parser ([] when all does)."""
    program, *words = _tokens(command)
    parsers = [("zuml-studio", STUDIO)] if program == "zuml-studio" else [("zuml", ZUML)]
    rest = words
    # the command path: words that pick subcommands; `a|b` and `a/b` name alternatives
    while rest and _subparsers(parsers[0][1]):
        word = rest[0]
        if word.startswith("-") or word in OMITTED or PLACEHOLDER.fullmatch(word):
            break
        picked = []
        for name, parser in parsers:
            children = _subparsers(parser)
            # `list|get N|set N`: the alternatives after a placeholder are in the words that follow
            later = [piece for w in rest[1:] if not w.startswith("-")
                     for piece in w.split("|")[1:] if piece in children]
            for alternative in [*filter(None, re.split(r"[|/]", word)), *later]:
                if alternative not in children:
                    return [f"{name} has no command {alternative!r}"]
                picked.append((f"{name} {alternative}", children[alternative]))
        parsers, rest = picked, rest[1:]
    problems = []
    for i, word in enumerate(rest):
        if not word.startswith("-") or word in ("-", "--") or re.fullmatch(r"-[\d.]+", word):
            continue
        flag = word.split("=")[0].rstrip(",.;:)")
        known = [(name, _options(parser)[flag]) for name, parser in parsers if flag in _options(parser)]
        if not known:
            problems.append(f"{' / '.join(n for n, _ in parsers)} has no option {flag}")
            continue
        value = word.split("=", 1)[1] if "=" in word else (rest[i + 1] if i + 1 < len(rest) else "")
        for name, action in known:
            if action.choices and action.nargs != 0 and value and not value.startswith("-"):
                for choice in value.split("|"):
                    if not PLACEHOLDER.fullmatch(choice) and choice not in OMITTED and choice not in action.choices:
                        problems.append(f"{name} {flag}: {choice!r} is not one of {sorted(action.choices)}")
    return problems


@pytest.mark.parametrize("where,command,whole", EXAMPLES, ids=[e[0][:90] for e in EXAMPLES])
def test_every_documented_command_line_names_real_commands_and_options(where, command, whole):
    assert _check(command) == [], where


def test_a_whole_example_without_placeholders_parses():
    literal = [(where, command) for where, command, whole in EXAMPLES
               if whole and not any(c in command for c in "[]|…") and "..." not in command
               and not any(PLACEHOLDER.fullmatch(w) for w in command.split())]
    assert len(literal) >= 3                                  # the README's replay and monitor at least
    for where, command in literal:
        program, *words = command.split()
        parser = STUDIO if program == "zuml-studio" else ZUML
        try:
            parser.parse_args(words)
        except SystemExit:
            pytest.fail(f"{where}: does not parse")
        # a macro or a path the reader is to use as it is (not one an earlier step wrote, eeprom.bin)
        inputs = [w for i, w in enumerate(words) if (w.endswith(".zuml") or "/" in w and w.endswith(READ_SUFFIXES))
                  and words[i - 1] not in ("-o", "--output", "--csv")]
        assert all((ROOT / w).is_file() for w in inputs), f"{where}: run from the checkout, it names no such file"


def test_the_examples_are_found_and_wrong_ones_are_caught():
    assert len(EXAMPLES) > 60
    assert _check("zuml device serve") == ["zuml has no command 'device'"]
    assert _check("zuml simulate FILE [--cycles N] [--flux F]") == ["zuml simulate has no option --flux"]
    assert _check("zuml run --task charge|fly") == ["zuml run --task: 'fly' is not one of "
                                                    "['charge', 'discharge', 'train']"]
    assert _check("zuml templates list|get N|set N --port P [--task T --capacity MAH]") == []
    assert _check("zuml slots/flash/run/stop/monitor/ backup/restore --port PTY") == []


def _sections(text: str) -> dict[str, str]:
    """docs/cli.md's text under each heading that names a command (`### `zuml log info``)."""
    parts = re.split(r"^#+ (.*)$", text, flags=re.M)
    return {heading: body for heading, body in zip(parts[1::2], parts[2::2])}


def _names(title: str, path: tuple[str, ...]) -> bool:
    """Whether a heading is the section of a command: `zuml log info`, or one of
    `zuml templates list`, `get`, `set`."""
    if title.startswith(f"`{' '.join(path)}`"):
        return True
    return len(path) == 3 and title.startswith(f"`{' '.join(path[:2])} ") and f"`{path[2]}`" in title


def test_the_command_line_page_has_every_command_and_every_option():
    sections = _sections(CLI_PAGE.read_text(encoding="utf-8"))
    leaves = [(("zuml",) + path, parser) for path, parser in _leaves(ZUML)] + [(("zuml-studio",), STUDIO)]
    assert {cmd for cmds in AREAS.values() for cmd in cmds} == {path[1] for path, _ in leaves if len(path) > 1}
    missing = []
    for path, parser in leaves:
        heading = " ".join(path)
        body = next((body for title, body in sections.items() if _names(title, path)), None)
        if body is None:
            missing.append(f"no section for {heading}")
            continue
        for action in parser._actions:
            flags = [s for s in action.option_strings if s not in ("-h", "--help")]
            if flags and not any(re.search(rf"(?<![\w-]){re.escape(f)}(?![\w-])", body) for f in flags):
                missing.append(f"{heading} {flags[-1]}")
    assert missing == []


# Named in the docs but outside the checkout: the shared data (and validation.md's paths inside its
# samples/), what a build makes, and the frozen bundle's insides.
ELSEWHERE = ("../shared/", "shared/", "realdata/", "dataexplorer/", "icharger/", "curves/", "imaxb6_serial/",
             "skyrc_hid/", "build/", "_internal/", "zuml-studio-VERSION")
LOOKED_UP_FROM = [ROOT, ROOT / "zuml_studio", ROOT / "resources", ROOT / "firmware", ROOT / "packaging",
                  ROOT / "docs", ROOT / "tests"]


# Pages copied unchanged from outside the repository (each says so in its first lines): their paths name
# the sources they were read from, not files of this checkout.
COPIES = [ROOT / "docs" / "zuml-2.0.md",
          *(page for page in sorted((ROOT / "docs" / "formats").glob("*.md")) if page.name != "README.md")]


def test_the_files_the_docs_name_exist():
    """A path in inline code (`sim/program.py`, `data/start_templates.toml`) names a file or folder
    of the checkout, from its root, the package, the firmware, packaging/, docs/ or tests/."""
    missing = []
    for page in PAGES:
        if page in COPIES:
            continue
        for token in re.findall(r"`([^`\s]+)`", page.read_text(encoding="utf-8")):
            path = token.rstrip(".,:;")
            if ("/" not in path or "://" in path or path.startswith(("/", "~", "$", "<", "hid:") + ELSEWHERE)
                    or any(c in path for c in "*…{")
                    or not re.search(r"\.(py|md|toml|zuml|c|h|sh|txt|csv|rules|spec|svg|lark|png|lov|osd|json)$|/$",
                                     path)):
                continue
            if not any((base / path).exists() for base in LOOKED_UP_FROM + [page.parent]):
                missing.append(f"{page.relative_to(ROOT)}: {path}")
    assert missing == []
