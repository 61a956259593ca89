"""Preferences: font size, theme and language, kept in the settings file."""
from PySide6.QtCore import QSettings

from zuml_studio.ui.window.preferences import Preferences, PreferencesDialog


def test_preferences_round_trip_and_bad_values_read_as_defaults(tmp_path):
    settings = QSettings(str(tmp_path / "s.ini"), QSettings.Format.IniFormat)
    Preferences(14, "dark", "ru").save(settings)
    assert Preferences.load(settings) == Preferences(14, "dark", "ru")
    settings.setValue("editor/fontSize", "huge")
    settings.setValue("appearance/theme", "purple")
    settings.setValue("appearance/language", "xx")
    assert Preferences.load(settings) == Preferences()


def test_the_dialog_offers_size_theme_and_the_languages(qtbot):
    dialog = PreferencesDialog(Preferences(0, "light"), 10)
    qtbot.addWidget(dialog)
    assert dialog.font_size.value() == 10
    assert [dialog.theme.itemData(i) for i in range(dialog.theme.count())] == ["system", "light", "dark"]
    assert dialog.theme.currentData() == "light"
    assert [dialog.language.itemData(i) for i in range(dialog.language.count())] == ["", "en", "ru"]
    assert [dialog.language.itemText(i) for i in range(1, 3)] == ["English", "Русский"]     # each in its own
    assert dialog.language.currentData() == ""            # as the system
    dialog.font_size.setValue(15)
    dialog.theme.setCurrentIndex(2)
    dialog.language.setCurrentIndex(2)
    assert dialog.chosen() == Preferences(15, "dark", "ru")
