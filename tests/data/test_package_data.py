"""The run-time data inside the package: read through one module, and a missing or broken file is a
loud error naming it, never a weaker check (issue 10)."""
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import zuml_studio
import zuml_studio.macros
import zuml_studio.resources
from zuml_studio import data
from zuml_studio.data import DataFileError

DANGEROUS = Path(__file__).with_name("LiPo-4V5.zuml")


def test_the_data_is_read_through_the_package():
    """resources/ and macros/ of the source tree are the package's zuml_studio.resources and
    zuml_studio.macros (mapped at build time; an editable install maps them the same way)."""
    assert Path(data.location("chemistries/LiPo.toml")).is_relative_to(Path(zuml_studio.resources.__file__).parent)
    assert data.standard_macros_dir() == Path(zuml_studio.macros.__file__).parent
    assert {"NiMh", "LiPo", "NiMh-dV"} <= {p.stem for p in data.standard_macros()}
    assert "imax_b6" in data.names("chargers")
    assert "LiPo" in data.read_toml("templates.toml")


def test_a_missing_data_file_is_an_error_naming_it():
    with pytest.raises(DataFileError, match=r"chemistries[/\\]NoSuch\.toml is missing"):
        data.read_text("chemistries/NoSuch.toml")
    with pytest.raises(DataFileError, match="no_such_folder is missing"):
        data.names("no_such_folder")


def test_a_standard_macro_is_recognised_and_a_user_file_is_not(tmp_path):
    assert data.is_standard_macro(data.standard_macros()[0])
    assert not data.is_standard_macro(tmp_path / "NiMh.zuml")


def _package_copy(tmp_path: Path) -> Path:
    """A copy of the package laid out as installed (its data folders inside it) to break; returns
    the directory to put on PYTHONPATH."""
    root = tmp_path / "site"
    ignore = shutil.ignore_patterns("__pycache__")
    shutil.copytree(Path(zuml_studio.__file__).parent, root / "zuml_studio", ignore=ignore)
    for folder in (zuml_studio.resources, zuml_studio.macros):
        shutil.copytree(Path(folder.__file__).parent, root / "zuml_studio" / folder.__name__.split(".")[-1],
                        ignore=ignore, dirs_exist_ok=True)
    return root


def _zuml(site: Path, *args: str) -> subprocess.CompletedProcess:
    # Run from the copy's own directory so the source tree's package cannot be imported instead.
    return subprocess.run([sys.executable, "-m", "zuml_studio.cli.main", *args], cwd=site, capture_output=True,
                          text=True, timeout=60, env={"PYTHONPATH": str(site), "PATH": "/usr/bin:/bin"})


def test_the_dangerous_macro_fails_the_check_in_an_intact_copy(tmp_path):
    site = _package_copy(tmp_path)
    proc = _zuml(site, "check", str(DANGEROUS))
    assert proc.returncode == 1, proc.stderr
    assert "[E303]" in proc.stdout


def test_zuml_check_fails_loudly_when_a_chemistry_file_is_missing(tmp_path):
    site = _package_copy(tmp_path)
    missing = site / "zuml_studio" / "resources" / "chemistries" / "LiPo.toml"
    missing.unlink()
    proc = _zuml(site, "check", str(DANGEROUS))
    assert proc.returncode == 2, proc.stdout
    assert f"zuml: error: data file {missing} is missing" in proc.stderr
    assert "Traceback" not in proc.stderr


def test_zuml_check_fails_loudly_when_a_chemistry_file_is_broken(tmp_path):
    site = _package_copy(tmp_path)
    broken = site / "zuml_studio" / "resources" / "chemistries" / "LiPo.toml"
    broken.write_text(broken.read_text().replace("[thermal]", "[thermal_gone]"))
    proc = _zuml(site, "check", str(DANGEROUS))
    assert proc.returncode == 2
    assert f"zuml: error: data file {broken}: missing [thermal] table" in proc.stderr
