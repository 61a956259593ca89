"""The window's language (issue 17): ZUML_LANG, then the Preferences choice, then the system
locale; ours and Qt's own catalogue installed before any window is built; a change in
Preferences applies at the next start, which is offered."""
import pytest
from PySide6.QtCore import QCoreApplication, QSettings

from zuml_studio import i18n
from zuml_studio.data import DataFileError
from zuml_studio.ui.base import language
from zuml_studio.ui.window.preferences import Preferences


@pytest.fixture(autouse=True)
def english_after(qapp):
    yield
    i18n.install("en")
    language.install_qt_catalogue("en")


def _qt_cancel() -> str:
    return QCoreApplication.translate("QPlatformTheme", "Cancel")


def test_zuml_lang_then_the_preference_then_the_system_locale(monkeypatch):
    for name in ("ZUML_LANG", "LC_ALL", "LC_MESSAGES"):
        monkeypatch.delenv(name, raising=False)
    monkeypatch.setenv("LANG", "ru_RU.UTF-8")
    assert language.install_language("") == "ru" and i18n.current_language() == "ru"
    assert language.install_language("en") == "en"
    monkeypatch.setenv("ZUML_LANG", "ru")
    assert language.install_language("en") == "ru"
    assert i18n._("&File") == "&Файл"


def test_the_preference_is_read_from_the_window_settings_file(tmp_path):
    assert language.saved_preference(tmp_path) == ""
    settings = QSettings(str(tmp_path / language.SETTINGS_FILE), QSettings.Format.IniFormat)
    Preferences(0, "system", "ru").save(settings)
    settings.sync()
    assert language.saved_preference(tmp_path) == "ru"
    settings.setValue(language.LANGUAGE_KEY, "xx")
    settings.sync()
    assert language.saved_preference(tmp_path) == ""          # unknown: as the system


def test_qt_own_texts_follow_the_language():
    language.install_qt_catalogue("ru")
    assert _qt_cancel() == "Отмена"
    language.install_qt_catalogue("en")
    assert _qt_cancel() == "Cancel"


def test_a_missing_qt_catalogue_is_a_broken_installation(monkeypatch, tmp_path):
    monkeypatch.setattr(language, "qt_catalogue_dir", lambda: str(tmp_path))
    with pytest.raises(DataFileError, match="qtbase_ru.qm"):
        language.install_qt_catalogue("ru")


def test_the_application_installs_the_language_before_the_window(monkeypatch, tmp_path):
    from zuml_studio.ui import app

    class Built(Exception):
        """Stops main() where the window would be built."""

    def build(path):
        raise Built(i18n.current_language(), _qt_cancel())
    monkeypatch.setenv("ZUML_LANG", "ru")
    monkeypatch.setattr("zuml_studio.ui.create_main_window", build)
    with pytest.raises(Built) as built:
        app.main(["--screenshot", str(tmp_path / "x.png")])
    assert built.value.args == ("ru", "Отмена")


def test_the_command_line_help_is_all_in_the_language(monkeypatch, capsys):
    from zuml_studio.ui import app
    monkeypatch.setenv("ZUML_LANG", "ru")
    with pytest.raises(SystemExit):
        app.main(["--help"])
    shown = capsys.readouterr().out
    assert shown.startswith("использование: zuml-studio") and "показать эту справку и выйти" in shown
    assert "options" not in shown and "usage" not in shown


def test_a_new_language_in_preferences_offers_a_restart(make_window, monkeypatch):
    w = make_window()
    asked, restarted = [], []
    w.ask_restart = lambda: asked.append(True) or True
    w.restart = lambda: restarted.append(True)
    w.set_preferences(Preferences(w.prefs.font_size, w.prefs.theme, w.prefs.language))
    assert not asked                                  # nothing that needs a restart changed
    w.set_preferences(Preferences(w.prefs.font_size, "dark", "ru"))
    assert asked and restarted
    assert language.saved_preference(w.config) == "ru"
    assert i18n.current_language() == "en"            # this window stays as it was built


def test_restart_closes_the_window_asking_to_be_built_again(make_window):
    w = make_window()
    assert w.restart()
    assert w.restart_wanted and not w.isVisible()


def test_a_window_kept_open_by_its_unsaved_work_is_not_restarted(make_window):
    w = make_window()
    w.editor.insertPlainText("// unsaved\n")
    w.ask_unsaved = lambda: "cancel"
    assert not w.restart()
    assert not w.restart_wanted and w.isVisible()


def test_the_application_builds_the_window_again_in_this_process_after_restart_now(monkeypatch):
    """No new process: the loop runs again with a new window (the same file), in the new language."""
    from zuml_studio.ui.app import run_windows

    class Window:
        def __init__(self, path, restart):
            self.path, self.restart_wanted = path, restart

    class App:
        runs = 0

        def exec(self):
            self.runs += 1
            return 0

    built = []

    def rebuild(path):
        built.append(path)
        return Window(path, restart=len(built) < 2)     # restarted twice, then closed for good
    app = App()
    assert run_windows(app, Window("/m/a.zuml", restart=True), rebuild) == 0
    assert built == ["/m/a.zuml", "/m/a.zuml"] and app.runs == 3


def test_reinstall_installs_the_language_now_chosen(tmp_path, monkeypatch):
    from PySide6.QtCore import QSettings
    monkeypatch.delenv("ZUML_LANG", raising=False)      # it would outrank the choice, as at a start
    settings = QSettings(str(tmp_path / language.SETTINGS_FILE), QSettings.Format.IniFormat)
    settings.setValue(language.LANGUAGE_KEY, "ru")
    settings.sync()
    try:
        assert language.reinstall(tmp_path) == "ru"
        assert i18n.current_language() == "ru" and _qt_cancel() == "Отмена"
    finally:
        language.install_language("en")
        language.install_qt_catalogue("en")
