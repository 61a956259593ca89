"""Edit > Preferences: the editor's font size, the theme and the language, kept in the settings
file. The language applies at the next start (every text is translated where it is built)."""
from __future__ import annotations

from dataclasses import dataclass

from PySide6.QtCore import QSettings
from PySide6.QtWidgets import QComboBox, QDialog, QDialogButtonBox, QFormLayout, QSpinBox, QWidget

from ... import i18n
from ...i18n import N_, _
from ..editor.code_editor import MAX_FONT_PT, MIN_FONT_PT
from ..base.language import LANGUAGE_KEY, SYSTEM
from ..base.theme import THEMES

THEME_NAMES = {"system": N_("Follow the system"), "light": N_("Light"), "dark": N_("Dark")}
# Each language by its own name, whatever the window's language is now.
LANGUAGES = {SYSTEM: N_("Follow the system"), **i18n.LANGUAGES}


@dataclass
class Preferences:
    font_size: int = 0          # points; 0: the system's fixed-width font size
    theme: str = "system"
    language: str = SYSTEM

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
        language = str(settings.value(LANGUAGE_KEY, default.language) or SYSTEM)
        return cls(size, theme if theme in THEMES else default.theme,
                   language if language in LANGUAGES else default.language)

    def save(self, settings: QSettings) -> None:
        settings.setValue("editor/fontSize", self.font_size)
        settings.setValue("appearance/theme", self.theme)
        settings.setValue(LANGUAGE_KEY, self.language)


class PreferencesDialog(QDialog):
    def __init__(self, prefs: Preferences, current_font_size: int, parent: QWidget | None = None):
        super().__init__(parent)
        self.setObjectName("preferencesDialog")
        self.setWindowTitle(_("Preferences"))
        self.font_size = QSpinBox()
        self.font_size.setObjectName("prefFontSize")
        self.font_size.setRange(MIN_FONT_PT, MAX_FONT_PT)
        self.font_size.setSuffix(" pt")
        self.font_size.setValue(prefs.font_size or current_font_size)
        self.theme = QComboBox()
        self.theme.setObjectName("prefTheme")
        for key in THEMES:
            self.theme.addItem(_(THEME_NAMES[key]), key)
        self.theme.setCurrentIndex(THEMES.index(prefs.theme))
        self.language = QComboBox()
        self.language.setObjectName("prefLanguage")
        for key, name in LANGUAGES.items():
            self.language.addItem(_(name) if key == SYSTEM else name, key)
        self.language.setCurrentIndex(max(0, self.language.findData(prefs.language)))
        self.language.setToolTip(_("The language of the window; a change applies when ZUML Studio starts again"))
        buttons = QDialogButtonBox(QDialogButtonBox.StandardButton.Ok | QDialogButtonBox.StandardButton.Cancel)
        buttons.accepted.connect(self.accept)
        buttons.rejected.connect(self.reject)
        form = QFormLayout(self)
        form.addRow(_("Editor font size"), self.font_size)
        form.addRow(_("Theme"), self.theme)
        form.addRow(_("Language"), self.language)
        form.addRow(buttons)

    def chosen(self) -> Preferences:
        return Preferences(self.font_size.value(), self.theme.currentData(), self.language.currentData())
