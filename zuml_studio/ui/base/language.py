"""The window's language, installed once before any window is built: ours (gettext, through
`zuml_studio.i18n`) and Qt's own (the buttons of QFileDialog and QMessageBox, from the
``qtbase_XX.qm`` PySide6 ships). A language chosen later applies at the next start."""
from __future__ import annotations

from pathlib import Path

from PySide6.QtCore import QCoreApplication, QLibraryInfo, QSettings, QTranslator

from ... import i18n
from ...data import DataFileError

SETTINGS_FILE = "settings.ini"
LANGUAGE_KEY = "appearance/language"
SYSTEM = ""                 # the preference "as the system"

_qt_translator: QTranslator | None = None      # kept alive: Qt holds only a pointer to it


def saved_preference(config: Path) -> str:
    """The language the user chose in Preferences ('' for the system's), read from the
    settings file the main window keeps in ``config``."""
    settings = QSettings(str(config / SETTINGS_FILE), QSettings.Format.IniFormat)
    value = str(settings.value(LANGUAGE_KEY, SYSTEM) or SYSTEM)
    return value if value in i18n.LANGUAGES else SYSTEM


def qt_catalogue_dir() -> str:
    return QLibraryInfo.path(QLibraryInfo.LibraryPath.TranslationsPath)


def install_language(preference: str = SYSTEM) -> str:
    """Choose (``ZUML_LANG``, then ``preference``, then the system locale) and install the
    language of our texts; returns its code. A missing catalogue is `DataFileError`."""
    language = i18n.choose_language(preference or None)
    i18n.install(language)
    return language


def install_qt_catalogue(language: str) -> None:
    """Qt's own texts (standard buttons, file dialogs) in ``language``; needs the application.
    Qt's catalogue missing from a non-English installation is a broken one (`DataFileError`)."""
    global _qt_translator
    app = QCoreApplication.instance()
    if _qt_translator is not None:
        app.removeTranslator(_qt_translator)
        _qt_translator = None
    if language == i18n.SOURCE_LANGUAGE:
        return
    translator = QTranslator(app)
    if not translator.load(f"qtbase_{language}", qt_catalogue_dir()):
        raise DataFileError(f"Qt's catalogue qtbase_{language}.qm is missing from {qt_catalogue_dir()}: "
                            "the installation is incomplete, reinstall ZUML Studio")
    app.installTranslator(translator)
    _qt_translator = translator


def reinstall(config: Path) -> str:
    """At a restart in this process: the language the user now chose, ours and Qt's; its code."""
    language = install_language(saved_preference(config))
    install_qt_catalogue(language)
    return language
