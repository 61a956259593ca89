"""Main-window fixtures: each test gets its own window and config folder."""
import pytest


@pytest.fixture(scope="session", autouse=True)
def gc_on_the_gui_thread(qapp):
    """As the application does (ui/base/gui_thread_gc.py): a worker thread must never collect a
    previous test's widgets."""
    import gc

    from zuml_studio.ui.base.gui_thread_gc import collect_on_gui_thread

    collector = collect_on_gui_thread()
    yield collector
    collector.timer.stop()
    gc.enable()


@pytest.fixture(autouse=True)
def collect_between_tests(gc_on_the_gui_thread):
    """The timer only fires while a test spins the event loop: catch up after each test."""
    yield
    gc_on_the_gui_thread.check()


@pytest.fixture
def make_window(qtbot, tmp_path):
    from zuml_studio.ui import create_main_window

    made = []

    def make(path=None, config=None):
        window = create_main_window(path, config or tmp_path / "config")
        window.ask_unsaved = lambda: "discard"      # never a modal dialog in a test
        window.ask_recover = lambda found: False
        window.ask_close_run = lambda: "leave"      # a test that closes during a run replaces this
        qtbot.addWidget(window)
        window.resize(1400, 900)
        window.show()
        made.append(window)
        return window

    yield make
    for window in made:
        window.sim_panel.cancel()
        window.device_panel.shutdown()


@pytest.fixture(autouse=True)
def warnings_asked(monkeypatch):
    """A modal dialog would block an offscreen test forever: the safety check's question about
    warnings (asked once per macro, docs/safety.md) is answered "go ahead" and recorded here as
    (action, warnings); a test that cancels replaces ``confirm_warnings`` itself."""
    from zuml_studio.ui.device import unsafe_dialog

    asked = []

    def answer(parent, action, warnings):
        asked.append((action, list(warnings)))
        return True
    monkeypatch.setattr(unsafe_dialog, "confirm_warnings", answer)
    return asked


@pytest.fixture(autouse=True)
def no_unexpected_restore_question(monkeypatch):
    """The Restore question fails a test that did not expect it (a test that does replaces it)."""
    from zuml_studio.ui.device import confirm_dialogs

    def unexpected_restore(parent, text):
        raise AssertionError(f"unexpected Restore question: {text}")
    monkeypatch.setattr(confirm_dialogs, "confirm_restore", unexpected_restore)


@pytest.fixture
def system_theme():
    """Give the application back the desktop's palette after a test chose one."""
    from zuml_studio.ui.base import theme

    yield
    theme.apply_theme("system")
