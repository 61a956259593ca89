"""Edit > Preferences: the editor's font size and the theme, kept in the settings file.
The language row is there, with English only, for the translation to come."""
from __future__ import annotations

from dataclasses import dataclass

from PySide6.QtCore import QSettings
from PySide6.QtWidgets import QComboBox, QDialog, QDialogButtonBox, QFormLayout, QSpinBox, QWidget

from .editor.code_editor import MAX_FONT_PT, MIN_FONT_PT
from .theme import THEMES

THEME_NAMES = {"system": "Follow the system", "light": "Light", "dark": "Dark"}
LANGUAGES = {"en": "English"}


@dataclass
class Preferences:
    font_size: int = 0          # points; 0: the system's fixed-width font size
    theme: str = "system"
    language: str = "en"

    @classmethod
    def load(cls, settings: QSettings) -> "Preferences":
        """What the settings file holds; a value out of range or unknown reads as the default."""
        default = cls()
        try:
            size = int(settings.value("editor/fontSize", default.font_size))
        except (TypeError, ValueError):
            size = default.font_size
        if size and not MIN_FONT_PT <= size <= MAX_FONT_PT:
            size = default.font_size
        theme = str(settings.value("appearance/theme", default.theme))
        language = str(settings.value("appearance/language", default.language))
        return cls(size, theme if theme in THEMES else default.theme,
                   language if language in LANGUAGES else default.language)

    def save(self, settings: QSettings) -> None:
        settings.setValue("editor/fontSize", self.font_size)
        settings.setValue("appearance/theme", self.theme)
        settings.setValue("appearance/language", self.language)


class PreferencesDialog(QDialog):
    def __init__(self, prefs: Preferences, current_font_size: int, parent: QWidget | None = None):
        super().__init__(parent)
        self.setObjectName("preferencesDialog")
        self.setWindowTitle("Preferences")
        self.font_size = QSpinBox()
        self.font_size.setObjectName("prefFontSize")
        self.font_size.setRange(MIN_FONT_PT, MAX_FONT_PT)
        self.font_size.setSuffix(" pt")
        self.font_size.setValue(prefs.font_size or current_font_size)
        self.theme = QComboBox()
        self.theme.setObjectName("prefTheme")
        for key in THEMES:
            self.theme.addItem(THEME_NAMES[key], key)
        self.theme.setCurrentIndex(THEMES.index(prefs.theme))
        self.language = QComboBox()
        self.language.setObjectName("prefLanguage")
        for key, name in LANGUAGES.items():
            self.language.addItem(name, key)
        self.language.setEnabled(len(LANGUAGES) > 1)
        buttons = QDialogButtonBox(QDialogButtonBox.StandardButton.Ok | QDialogButtonBox.StandardButton.Cancel)
        buttons.accepted.connect(self.accept)
        buttons.rejected.connect(self.reject)
        form = QFormLayout(self)
        form.addRow("Editor font size", self.font_size)
        form.addRow("Theme", self.theme)
        form.addRow("Language", self.language)
        form.addRow(buttons)

    def chosen(self) -> Preferences:
        return Preferences(self.font_size.value(), self.theme.currentData(), self.language.currentData())
