"""The ZUML code editor widget: ``EditorWithFind`` (editor + find bar) is what the main
window places; ``CodeEditor`` is the text widget itself. ``indent`` holds the plain-Python
indentation and comment rules; importing it (or this package) does not load Qt."""
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
