"""The interface's language: which one is chosen, and the one gettext catalogue that answers.

Every visible text of the package goes through `_` (or `ngettext` where a count decides the form,
Russian has three: 1 / 2 / 5 and 21 again like 1). Texts defined at import time (tables, class
attributes) are marked with `N_` and translated where they are shown, so a language installed after
the import still applies. ZUML keywords, opcode names, units, file formats and diagnostic codes
(E303) are never put through `_`: they are the same in every language.

The chosen language: ``ZUML_LANG``, else the user's preference, else the system locale
(the first set of ``LC_ALL``, ``LC_MESSAGES``, ``LANG``), else English. English is the source language and needs no
catalogue; any other supported language must have its compiled catalogue in the package, and a
missing one is a broken installation (`DataFileError`), not a silent fall-back to English.
"""
from __future__ import annotations

import gettext
import io
import os
from importlib import resources

from . import resources as catalogues_package    # imported, not named: a frozen bundle then holds it
from .data_error import DataFileError

DOMAIN = "zuml_studio"
SOURCE_LANGUAGE = "en"
LANGUAGES: dict[str, str] = {"en": "English", "ru": "Русский"}   # each in its own language

_translation: gettext.NullTranslations = gettext.NullTranslations()
_language = SOURCE_LANGUAGE


def _(message: str) -> str:
    """``message`` in the installed language."""
    return _translation.gettext(message)


def ngettext(singular: str, plural: str, n: int) -> str:
    """The form of ``singular``/``plural`` that the installed language uses for ``n``."""
    return _translation.ngettext(singular, plural, n)


def N_(message: str) -> str:  # noqa: N802 - gettext's marker, the name pybabel -k N_ looks for
    """Marks ``message`` for the catalogue without translating it yet (translate it with `_` where
    it is shown)."""
    return message


def _supported(tag: str | None) -> str | None:
    """``ru_RU.UTF-8`` -> ``ru``; None for an unset, C/POSIX or unsupported locale."""
    if not tag:
        return None
    code = tag.split(":")[0].split(".")[0].split("@")[0].split("_")[0].split("-")[0].lower()
    return code if code in LANGUAGES else None


def choose_language(preference: str | None = None) -> str:
    """The language to use: ``ZUML_LANG``, then ``preference`` (the user's choice, None or "" for
    "as the system"), then the system locale, then English. The system locale is the first of
    ``LC_ALL``, ``LC_MESSAGES``, ``LANG`` that is set, as POSIX has it: ``LC_ALL=C`` means English
    even when ``LANG`` is Russian."""
    for tag in (os.environ.get("ZUML_LANG"), preference):
        code = _supported(tag)
        if code:
            return code
    system = next((os.environ[name] for name in ("LC_ALL", "LC_MESSAGES", "LANG") if os.environ.get(name)), None)
    return _supported(system) or SOURCE_LANGUAGE


def catalogue_path(language: str) -> str:
    """Where ``language``'s compiled catalogue lives inside the package."""
    return str(resources.files(catalogues_package).joinpath("locale", language, "LC_MESSAGES", DOMAIN + ".mo"))


def catalogue_source_path(language: str) -> str:
    """Where ``language``'s catalogue source (``.po``) is, in a source checkout or an editable install."""
    return str(resources.files(catalogues_package).joinpath("locale", language, "LC_MESSAGES", DOMAIN + ".po"))


def _compiled_from_source(language: str) -> gettext.GNUTranslations | None:
    """``language``'s catalogue compiled in memory from its ``.po``, where only the source is
    there: an editable install (``pip install -e .``) has no build step to compile it. A wheel and
    the frozen bundle ship the ``.mo`` and never come here."""
    try:
        po = open(catalogue_source_path(language), "rb")
    except OSError:
        return None
    from babel.messages.mofile import write_mo   # only a source checkout needs Babel at run time
    from babel.messages.pofile import read_po

    with po as fh:
        catalog = read_po(fh)
    compiled = io.BytesIO()
    write_mo(compiled, catalog, use_fuzzy=False)
    compiled.seek(0)
    return gettext.GNUTranslations(compiled)


def install(language: str) -> None:
    """Make ``language`` the one `_` answers in, for the whole process."""
    global _translation, _language
    if language not in LANGUAGES:
        raise ValueError(_("unsupported language {language!r}; supported: {supported}").format(
            language=language, supported=", ".join(LANGUAGES)))
    if language == SOURCE_LANGUAGE:
        _translation, _language = gettext.NullTranslations(), language
        return
    path = catalogue_path(language)
    try:
        with open(path, "rb") as fp:
            _translation = gettext.GNUTranslations(fp)
    except FileNotFoundError:
        from_source = _compiled_from_source(language)
        if from_source is None:
            raise DataFileError(_("translation catalogue {path} is missing: the installation is incomplete, "
                                  "reinstall ZUML Studio").format(path=path)) from None
        _translation = from_source
    except OSError as exc:
        raise DataFileError(_("translation catalogue {path} is unreadable ({error}): reinstall ZUML Studio").format(
            path=path, error=exc)) from None
    _language = language


# argparse's own words, which it puts through its module's `_` (gettext's global domain, which
# this package never installs): listed here so that extraction puts them in our catalogue, and
# `translate_argparse` routes argparse to it. The msgids are CPython's, letter for letter.
ARGPARSE_TEXTS = (
    N_("usage: "), N_("positional arguments"), N_("options"), N_("show this help message and exit"),
    N_("%(prog)s: error: %(message)s\n"), N_("argument %(argument_name)s: %(message)s"),
    N_("the following arguments are required: %s"), N_("unrecognized arguments: %s"),
    N_("invalid choice: %(value)r (choose from %(choices)s)"), N_("invalid %(type)s value: %(value)r"),
    N_("expected one argument"), N_("expected at most one argument"), N_("expected at least one argument"),
    N_("ambiguous option: %(option)s could match %(matches)s"), N_("not allowed with argument %s"),
    N_("one of the arguments %s is required"), N_("ignored explicit argument %r"),
    N_("unexpected option string: %s"), N_("can't open '%(filename)s': %(error)s"),
)


def translate_argparse() -> None:
    """Make argparse's usage, section titles and error messages answer in the installed language."""
    import argparse

    argparse._ = _
    argparse.ngettext = ngettext


def current_language() -> str:
    """The installed language's code (``en``, ``ru``)."""
    return _language
