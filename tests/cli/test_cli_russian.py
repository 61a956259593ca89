"""The command line in Russian (issue 17): chosen from LANG like any program, the same
diagnostic codes as in English, argparse's own words too."""
import os
import re
import subprocess
import sys

import pytest

from helpers import ROOT, seed_text

CYRILLIC = re.compile("[а-яА-ЯёЁ]")
DANGEROUS = ROOT / "tests" / "data" / "LiPo-4V5.zuml"


def zuml(*args: str, lang: str) -> subprocess.CompletedProcess:
    """The real command line in a child process with the system locale ``lang`` (and no ZUML_LANG)."""
    env = {k: v for k, v in os.environ.items() if k not in ("ZUML_LANG", "LC_ALL", "LC_MESSAGES", "LANGUAGE")}
    env["LANG"] = lang
    return subprocess.run([sys.executable, "-m", "zuml_studio.cli.main", *args], capture_output=True, text=True,
                          env=env, timeout=60)


def _codes(text: str) -> list[str]:
    return re.findall(r"\[([EW]\d{3})\]", text)


def test_check_speaks_russian_under_a_russian_locale_with_the_same_codes(tmp_path):
    bad = tmp_path / "bad.zuml"
    bad.write_text(seed_text("LiPo").replace("CONSTANT_I=1C", "CONSTANT_I=1"), encoding="utf-8")
    for path in (bad, DANGEROUS):
        english = zuml("check", str(path), lang="en_US.UTF-8")
        russian = zuml("check", str(path), lang="ru_RU.UTF-8")
        assert english.returncode == russian.returncode == 1
        assert _codes(russian.stdout) == _codes(english.stdout) != []
        for line in russian.stdout.splitlines():
            assert CYRILLIC.search(line), line
        assert not CYRILLIC.search(english.stdout + english.stderr)
    russian = zuml("check", str(bad), lang="ru_RU.UTF-8")
    assert f"{bad}:5:16: ошибка: CONSTANT_I: нужна единица: 2A или 0.5C [E201]" in russian.stdout
    assert "подсказка:" in russian.stdout


def test_the_count_of_diagnostics_uses_russian_plural_forms():
    proc = zuml("check", str(DANGEROUS), lang="ru_RU.UTF-8")
    assert proc.stderr.strip().endswith(f"{DANGEROUS}: 2 ошибки, 2 предупреждения")


def test_c_locale_overrides_a_russian_lang():
    env_lang = zuml("check", str(DANGEROUS), lang="ru_RU.UTF-8")
    assert CYRILLIC.search(env_lang.stdout)
    env = {k: v for k, v in os.environ.items() if k != "ZUML_LANG"} | {"LANG": "ru_RU.UTF-8", "LC_ALL": "C"}
    proc = subprocess.run([sys.executable, "-m", "zuml_studio.cli.main", "check", str(DANGEROUS)],
                          capture_output=True, text=True, env=env, timeout=60)
    assert not CYRILLIC.search(proc.stdout) and "[E303]" in proc.stdout


def test_help_is_russian_argparse_words_included():
    proc = zuml("--help", lang="ru_RU.UTF-8")
    assert proc.returncode == 0
    assert proc.stdout.startswith("использование: zuml")
    assert "позиционные аргументы" in proc.stdout and "параметры:" in proc.stdout
    assert "показать эту справку и выйти" in proc.stdout
    assert "проверить макросы и вывести их ошибки и предупреждения" in proc.stdout
    assert "options" not in proc.stdout and "usage" not in proc.stdout


@pytest.mark.parametrize("command", ["check", "compile", "simulate", "flash", "monitor", "new", "log", "templates",
                                     "virtual-charger", "fit"])
def test_every_subcommand_help_line_is_russian(command):
    proc = zuml(command, "--help", lang="ru_RU.UTF-8")
    assert proc.returncode == 0, proc.stderr
    help_lines = [line for line in proc.stdout.splitlines()
                  if line.startswith("  ") and re.search(r"[a-z]{4,} [a-z]{4,}", line)
                  and not re.search(r"[a-z]+ [A-Z_]{2,}$|^\s+-", line)]
    english = [line for line in help_lines if not CYRILLIC.search(line)]
    assert not english, english
    assert "использование:" in proc.stdout


def test_argparse_errors_are_russian():
    proc = zuml("check", lang="ru_RU.UTF-8")
    assert proc.returncode == 2
    assert "zuml check: ошибка: нужны следующие аргументы: FILE" in proc.stderr
    proc = zuml("nosuch", lang="ru_RU.UTF-8")
    assert proc.returncode == 2 and "неверный выбор" in proc.stderr


def test_cli_errors_are_russian(tmp_path):
    proc = zuml("check", str(tmp_path / "missing.zuml"), lang="ru_RU.UTF-8")
    assert proc.returncode == 2
    assert proc.stderr.startswith("zuml: ошибка: ") and "нет такого файла" in proc.stderr



def test_compare_speaks_russian_every_line_but_the_macros_own_condition():
    curve = ROOT / "tests" / "data" / "curves" / "nimh_4s_estation_1c.csv"
    russian = zuml("compare", str(curve), str(ROOT / "macros" / "NiMh-dV.zuml"),
                   lang="ru_RU.UTF-8")
    assert russian.returncode == 0, russian.stderr
    for line in russian.stdout.splitlines():
        assert CYRILLIC.search(line), line
    assert "ниже пика (-dV)" in russian.stdout
