"""Device-panel fixtures: a shown panel whose editor holds a compiled seed macro (virtual
chargers served beside it: ``make_charger``, in ``tests/conftest.py``)."""
import pytest

from device_helpers import Editor


@pytest.fixture(autouse=True)
def no_unexpected_unsafe_dialog(monkeypatch):
    """A modal dialog would block an offscreen test forever: a test that expects the safety
    dialog replaces ``confirm_unsafe`` itself; anywhere else it fails the test at once."""
    from zuml_studio.ui.device import device_panel

    def unexpected(parent, action, problems):
        raise AssertionError(f"unexpected safety dialog ({action}): {problems}")
    monkeypatch.setattr(device_panel, "confirm_unsafe", unexpected)


@pytest.fixture
def editor():
    return Editor()


@pytest.fixture
def make_panel(qtbot, tmp_path, editor):
    """make_panel(size=(1400, 380)) -> a shown DevicePanel at 1400x380 (session CSVs in tmp_path/sessions)."""
    from zuml_studio.ui.device import DevicePanel

    made = []

    def make(size=(1400, 380)):
        panel = DevicePanel(editor, tmp_path / "sessions", port_lister=lambda: [])
        qtbot.addWidget(panel)
        panel.resize(*size)
        panel.show()
        made.append(panel)
        return panel

    yield make
    for panel in made:
        panel.shutdown()
