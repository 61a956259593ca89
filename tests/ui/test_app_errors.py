"""The app's own error paths (issue 10). A windowed Windows build starts with sys.stdout and
sys.stderr set to None: the app writes to a log beside its settings instead of crashing on its first
warning. A broken installation's DataFileError raised in a slot is shown, not only printed."""
import sys

from zuml_studio.user_dirs import config_dir
from zuml_studio.ui.app import _ensure_streams


def test_missing_streams_go_to_a_log_in_the_config_folder(monkeypatch):
    monkeypatch.setattr(sys, "stdout", None)
    monkeypatch.setattr(sys, "stderr", None)
    _ensure_streams()
    sys.stderr.write("a warning nobody sees\n")
    sys.stdout.write("and a print\n")
    sys.stderr.close()         # one file for both
    log = (config_dir() / "zuml-studio.log").read_text(encoding="utf-8")
    assert "a warning nobody sees\n" in log and "and a print\n" in log


def test_present_streams_are_left_alone(monkeypatch):
    stderr = sys.stderr
    _ensure_streams()
    assert sys.stderr is stderr


def test_a_data_error_raised_in_a_slot_is_shown_in_a_dialog(qapp, monkeypatch):
    from PySide6.QtWidgets import QMessageBox

    from zuml_studio.data import DataFileError
    from zuml_studio.ui.app import data_errors_shown

    shown, passed = [], []
    monkeypatch.setattr(QMessageBox, "critical", lambda parent, title, text: shown.append(text))
    hook = data_errors_shown(lambda *a: passed.append(a[1]))
    broken = DataFileError("data file /x/LiPo.toml is missing")
    hook(DataFileError, broken, None)
    hook(ValueError, ValueError("other"), None)
    assert shown == ["data file /x/LiPo.toml is missing"] and len(passed) == 2
