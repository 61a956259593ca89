"""The root of every error ZUML Studio raises on purpose, and how such an error says itself.

Each package's exception class derives from `ZumlError` beside the base it had (``ValueError``,
``Exception``), so an ``except`` written for that base still means what it meant, and one
``except ZumlError`` catches any failure a user can act on, as opposed to a bug. An error carries its
own words (`ZumlError.words`): the class that knows what went wrong says it, and the one function
that words any error for a user, ``error_words.describe_error``, needs to know no class of them."""
from __future__ import annotations


def error_text(exc: BaseException) -> str:
    """An exception's own message, or its class's name when it has none."""
    return str(exc).strip() or type(exc).__name__


class ZumlError(Exception):
    """A failure a user can act on (a bad file, a charger that refused, a lost link), never a bug."""

    def words(self, action: str = "") -> str:
        """What the user reads about this error while doing ``action`` (connect, flash, restore, backup,
        start, stop, passport, slots; "" for none), in the message's own case: the window capitalises it,
        the command line prints it after ``zuml: error:``. By default, the message itself; a class whose
        failure means more while doing an action says so by overriding this."""
        return error_text(self)
