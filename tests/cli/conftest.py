"""Command-line fixtures."""
import pytest

from zuml_studio.cli.main import main


@pytest.fixture
def zuml(capsys, monkeypatch, tmp_path):
    """zuml(*args) -> (exit code, stdout, stderr): the command line in-process (fast); tests that
    must run it as a user would use ``tests_cli_util.run_zuml`` (a subprocess). Each test has its own
    config folder: a battery one test saves is not in every later window's battery lists."""
    monkeypatch.setenv("ZUML_STUDIO_CONFIG_DIR", str(tmp_path / "zuml-config"))

    def run(*args):
        capsys.readouterr()
        code = main(list(args))
        captured = capsys.readouterr()
        return code, captured.out, captured.err
    return run
