"""./dev, the first thing a new user runs: a wrong PYTHON is said as it is."""
import os
import subprocess

from helpers import ROOT


def test_a_python_that_is_not_there_is_named_not_called_too_old():
    proc = subprocess.run(["bash", str(ROOT / "dev"), "zuml", "--help"], capture_output=True, text=True,
                          env=dict(os.environ, PYTHON="/nonexistent/python3"), timeout=30)
    assert proc.returncode == 2
    assert proc.stderr == "/nonexistent/python3 not found: install Python 3.11 or newer, or set " \
                          "PYTHON=/path/to/python3.11\n"
