"""One root for the package's errors (issue 36 §4): every exception class ZUML Studio defines is a
ZumlError, and keeps the base it had, so an ``except ValueError`` still catches what it caught."""
import importlib
import pkgutil

import zuml_studio
from zuml_studio.protocol.passport import PassportError
from zuml_studio.errors import ZumlError, error_text
from zuml_studio.logs.model import LogFormatError


def _exception_classes() -> list[type]:
    for info in pkgutil.walk_packages(zuml_studio.__path__, "zuml_studio."):
        importlib.import_module(info.name)
    found, todo = [], [BaseException]
    while todo:
        for sub in todo.pop().__subclasses__():
            todo.append(sub)
            if sub.__module__.startswith("zuml_studio."):
                found.append(sub)
    return found


def test_every_exception_of_the_package_is_a_zuml_error():
    classes = _exception_classes()
    assert len(classes) > 40
    assert [f"{c.__module__}.{c.__qualname__}" for c in classes if not issubclass(c, ZumlError)] == []


def test_an_error_keeps_its_old_base():
    assert issubclass(LogFormatError, ValueError) and issubclass(PassportError, ValueError)


def test_an_error_says_its_message_or_its_name():
    assert ZumlError("a file: no such file").words() == "a file: no such file"
    assert ZumlError().words("flash") == "ZumlError"
    assert error_text(ValueError("  spaced  ")) == "spaced"
