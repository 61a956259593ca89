"""The frozen bundle, built the way a release is (packaging/pyinstaller/build.sh, what `./dev package`
runs), works on its own: its zuml fails the dangerous macro, its zuml-studio renders the window
offscreen, Qt's Russian translation and ours are inside, and install.sh installs it (issue 10). Slow: it builds
a clean venv and freezes it (a few minutes on a loaded 2-core machine); `-m 'not slow'` skips it."""
import json
import os
import re
import struct
import subprocess
import sys

import pytest

from helpers import ROOT

pytestmark = pytest.mark.slow
DANGEROUS = ROOT / "tests" / "data" / "LiPo-4V5.zuml"


@pytest.fixture(scope="module")
def built(tmp_path_factory):
    """(bundle folder, the build's stdout)."""
    tmp = tmp_path_factory.mktemp("bundle")
    proc = subprocess.run(["bash", str(ROOT / "packaging" / "pyinstaller" / "build.sh"), str(tmp / "dist")],
                          env=dict(os.environ, PYTHON=sys.executable), capture_output=True, text=True, timeout=1500)
    assert proc.returncode == 0, proc.stderr[-4000:]
    tarball = proc.stdout.strip().splitlines()[-1]
    assert re.fullmatch(r".*/zuml-studio-[\d.]+-linux-\w+\.tar\.gz", tarball), proc.stdout
    subprocess.run(["tar", "-C", str(tmp), "-xzf", tarball], check=True)
    return tmp / os.path.basename(tarball)[: -len(".tar.gz")], proc.stdout


def _run(*cmd, cwd, timeout=180):
    env = dict(os.environ, QT_QPA_PLATFORM="offscreen")
    env.pop("PYTHONPATH", None)
    return subprocess.run([str(c) for c in cmd], cwd=cwd, env=env, capture_output=True, text=True, timeout=timeout)


def test_the_build_says_which_glibc_the_bundle_needs(built):
    _, out = built
    assert re.search(r"^highest GLIBC symbol version needed: GLIBC_2\.\d+ \(by .+\)", out, flags=re.M), out


def test_the_bundles_zuml_fails_the_dangerous_macro(built, tmp_path):
    bundle, _ = built
    proc = _run(bundle / "zuml", "check", DANGEROUS, cwd=tmp_path)
    assert proc.returncode == 1, proc.stdout + proc.stderr
    assert proc.stdout.count("[E303]") == 2


def test_the_bundles_zuml_simulates_with_the_c_engine(built, tmp_path):
    bundle, _ = built
    macro = bundle / "_internal" / "zuml_studio" / "macros" / "NiMh-dV.zuml"
    proc = _run(bundle / "zuml", "simulate", macro, "--capacity", "2000", "--series", "4", "--current", "2",
                "--engine", "c", "--json", cwd=tmp_path)
    assert proc.returncode == 0, proc.stderr
    assert json.loads(proc.stdout)["engine"] == "c"


def test_the_bundles_zuml_studio_renders_a_1600x1000_screenshot(built, tmp_path):
    bundle, _ = built
    macro = bundle / "_internal" / "zuml_studio" / "macros" / "NiMh-dV.zuml"
    proc = _run(bundle / "zuml-studio", macro, "--screenshot", tmp_path / "shot.png", cwd=tmp_path)
    # The picture shows a simulation: it ran in a child of the frozen executable (freeze_support).
    assert proc.returncode == 0 and "simulat" not in proc.stderr, proc.stderr
    head = (tmp_path / "shot.png").read_bytes()[:24]
    assert head[:8] == b"\x89PNG\r\n\x1a\n" and struct.unpack(">II", head[16:24]) == (1600, 1000)


def test_qts_russian_translation_is_in_the_bundle(built):
    bundle, _ = built
    assert any(bundle.rglob("qtbase_ru.qm"))


def test_the_bundles_zuml_speaks_russian_from_its_own_catalogue(built, tmp_path):
    bundle, _ = built
    assert (bundle / "_internal" / "zuml_studio" / "resources" / "locale" / "ru" / "LC_MESSAGES" / "zuml_studio.mo").is_file()
    env = {k: v for k, v in os.environ.items() if k not in ("PYTHONPATH", "ZUML_LANG", "LC_ALL", "LC_MESSAGES")}
    env["LANG"] = "ru_RU.UTF-8"
    proc = subprocess.run([str(bundle / "zuml"), "check", str(DANGEROUS)], cwd=tmp_path, env=env,
                          capture_output=True, text=True, timeout=180)
    assert proc.returncode == 1 and proc.stdout.count("[E303]") == 2, proc.stdout + proc.stderr
    assert "ошибка" in proc.stdout and "подсказка" in proc.stdout, proc.stdout


def test_install_sh_installs_the_bundle_that_then_runs(built, tmp_path):
    bundle, _ = built
    prefix = tmp_path / ".local"
    proc = subprocess.run(["bash", str(bundle / "linux" / "install.sh")], env=dict(os.environ, PREFIX=str(prefix)),
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr
    proc = _run(prefix / "bin" / "zuml", "check", DANGEROUS, cwd=tmp_path)
    assert proc.returncode == 1 and "[E303]" in proc.stdout, proc.stderr
