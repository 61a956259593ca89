"""The visual macro editor (phase cards over the same text) and the new-macro wizard dialog.
Imports only ui.base."""
from .visual_editor import VisualEditor

__all__ = ["VisualEditor", "NewMacroWizard"]


def __getattr__(name: str):
    if name == "NewMacroWizard":
        from .wizard_dialog import NewMacroWizard
        return NewMacroWizard
    raise AttributeError(name)
