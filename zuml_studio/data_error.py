"""The one error of a broken installation, in a module of its own: both `data` and `i18n` raise it,
and `data` itself translates its messages, so neither may own it."""

from .errors import ZumlError


class DataFileError(ZumlError):
    """A data file of the installation is missing, unreadable or malformed.

    Deliberately not an OSError or ValueError: handlers written for a user's bad input must not
    swallow a broken installation."""
