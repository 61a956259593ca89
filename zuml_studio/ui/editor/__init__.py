"""Writing a macro as text: the ZUML code editor widget (``EditorWithFind``, editor and find
bar, is what the main window places; ``CodeEditor`` is the text widget itself; ``indent`` holds
the plain-Python indentation and comment rules) and the Write mode's panels beside it: the
compiled bytes (``hex_view``), the problems list, the macro library, the command reference
(``help_browser``) and the check as the user types (``validation``). Imports only ui.base;
importing it (or ``indent``) does not load Qt."""
from __future__ import annotations

__all__ = ["CodeEditor", "EditorWithFind", "FindBar"]


def __getattr__(name: str):
    if name in ("CodeEditor", "EditorWithFind"):
        from . import code_editor
        return getattr(code_editor, name)
    if name == "FindBar":
        from .find_bar import FindBar
        return FindBar
    raise AttributeError(name)
