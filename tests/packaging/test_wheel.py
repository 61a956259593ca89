"""The built wheel is the whole application: installed away from the source tree, its commands find
their data, the safety lint still fails a dangerous macro, and the GUI renders (issue 10)."""
import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

from helpers import ROOT

DANGEROUS = ROOT / "tests" / "data" / "LiPo-4V5.zuml"
SOURCES = ("pyproject.toml", "setup.py", "README.md", "LICENSE", "zuml_studio", "resources", "macros", "firmware")


def _run(*cmd, cwd, env=None, timeout=180) -> subprocess.CompletedProcess:
    return subprocess.run([str(c) for c in cmd], cwd=cwd, env=env, capture_output=True, text=True, timeout=timeout)


@pytest.fixture(scope="module")
def installed(tmp_path_factory):
    """(site, bin, outside): the wheel installed into ``site``; ``outside`` is a directory far from
    the repository to run it from."""
    tmp = tmp_path_factory.mktemp("wheel")
    # Build from a copy: an in-tree build/ would leave stale modules in later wheels.
    src = tmp / "src"
    for name in SOURCES:
        if (ROOT / name).is_dir():
            # No .mo from ./dev: the wheel's own build step must compile the catalogues.
            # Nor the engine's library or the firmware's build/: the wheel's build step compiles the engine.
            shutil.copytree(ROOT / name, src / name, ignore=shutil.ignore_patterns("__pycache__", "*.mo", "_engine",
                                                                                   "build"))
        else:
            src.mkdir(exist_ok=True)
            shutil.copy2(ROOT / name, src / name)
    proc = _run(sys.executable, "-m", "pip", "wheel", "--no-deps", "--quiet", src, "-w", tmp / "dist", cwd=tmp)
    assert proc.returncode == 0, proc.stderr
    wheel = next((tmp / "dist").glob("zuml_studio-*.whl"))
    site = tmp / "site"
    proc = _run(sys.executable, "-m", "pip", "install", "--no-deps", "--quiet", "--target", site, wheel, cwd=tmp)
    assert proc.returncode == 0, proc.stderr
    outside = tmp / "elsewhere"
    outside.mkdir()
    return site, site / "bin", outside


def _env(site: Path) -> dict:
    # The wheel's copy first; the dependencies come from this interpreter's environment.
    env = {k: v for k, v in os.environ.items() if k != "PYTHONPATH"}
    env.update(PYTHONPATH=str(site), QT_QPA_PLATFORM="offscreen")
    return env


def test_the_wheel_carries_the_data_and_the_licence(installed):
    site, _, _ = installed
    data = site / "zuml_studio" / "resources"
    assert {p.name for p in (data / "chemistries").glob("*.toml")} == {
        "Pb.toml", "NiCd.toml", "NiMh.toml", "LiPo.toml", "LiIon.toml", "LiFe.toml"}
    assert (data / "chargers" / "imax_b6.toml").is_file() and (data / "templates.toml").is_file()
    assert (site / "zuml_studio" / "macros" / "NiMh.zuml").is_file()
    assert any(site.glob("zuml_studio-*.dist-info/**/LICENSE*"))


def test_the_installed_package_is_the_one_that_runs(installed):
    site, _, outside = installed
    proc = _run(sys.executable, "-c", "import zuml_studio; print(zuml_studio.__file__)", cwd=outside, env=_env(site))
    assert Path(proc.stdout.strip()).is_relative_to(site), proc.stdout + proc.stderr


def test_installed_zuml_check_fails_the_dangerous_macro(installed):
    site, bin_, outside = installed
    proc = _run(bin_ / "zuml", "check", DANGEROUS, cwd=outside, env=_env(site))
    assert proc.returncode == 1, proc.stdout + proc.stderr
    assert proc.stdout.count("[E303]") == 2


def test_installed_zuml_speaks_russian_under_a_russian_locale(installed):
    site, bin_, outside = installed
    assert (site / "zuml_studio" / "resources" / "locale" / "ru" / "LC_MESSAGES" / "zuml_studio.mo").is_file()
    env = {k: v for k, v in _env(site).items() if k not in ("ZUML_LANG", "LC_ALL", "LC_MESSAGES")}
    env["LANG"] = "ru_RU.UTF-8"
    proc = _run(bin_ / "zuml", "check", DANGEROUS, cwd=outside, env=env)
    assert proc.returncode == 1, proc.stdout + proc.stderr
    assert proc.stdout.count("[E303]") == 2
    assert "ошибка" in proc.stdout and "на элемент" in proc.stdout, proc.stdout


def test_installed_zuml_simulates_and_writes_a_new_macro(installed):
    site, bin_, outside = installed
    nimh = site / "zuml_studio" / "macros" / "NiMh.zuml"
    proc = _run(bin_ / "zuml", "simulate", nimh, "--capacity", "2000", "--series", "4", "--current", "2",
                cwd=outside, env=_env(site))
    assert proc.returncode == 0, proc.stderr
    assert "NiMh" in proc.stdout
    assert (site / "zuml_studio" / "sim" / "_engine" / "libzuml_engine.so").is_file()
    proc = _run(bin_ / "zuml", "simulate", nimh, "--capacity", "2000", "--series", "4", "--current", "2", "--json",
                "--engine", "c", cwd=outside, env=_env(site))
    assert proc.returncode == 0, proc.stderr
    assert json.loads(proc.stdout)["engine"] == "c"
    proc = _run(bin_ / "zuml", "new", "--chemistry", "LiPo", "--series", "3", "--capacity", "2200",
                "-o", "mine.zuml", cwd=outside, env=_env(site))
    assert proc.returncode == 0, proc.stderr
    assert "AKK_TYPE=LiPo" in (outside / "mine.zuml").read_text()


def test_installed_zuml_studio_renders_a_screenshot(installed):
    site, bin_, outside = installed
    nimh = site / "zuml_studio" / "macros" / "NiMh.zuml"
    proc = _run(bin_ / "zuml-studio", nimh, "--screenshot", "shot.png", cwd=outside, env=_env(site))
    assert proc.returncode == 0, proc.stderr
    assert (outside / "shot.png").stat().st_size > 20000
