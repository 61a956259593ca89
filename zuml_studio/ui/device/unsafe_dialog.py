"""The GUI's override of the safety check: a warning that names each danger and asks before
bytes the check refuses go to (or start on) a charger. Cancel is the default."""
from __future__ import annotations

from PySide6.QtWidgets import QMessageBox, QWidget

from ...i18n import _, ngettext


def unsafe_dialog(parent: QWidget | None, action: str, problems: list[str]) -> QMessageBox:
    """The dialog, not yet shown (``action``: the translated verb, "Flash"); ``box.go_ahead`` is the
    button that overrides."""
    box = QMessageBox(QMessageBox.Icon.Warning, _("Unsafe for the battery"),
                      ngettext("{action}: the safety check found {n} danger to the battery.",
                               "{action}: the safety check found {n} dangers to the battery.",
                               len(problems)).format(action=action, n=len(problems)), parent=parent)
    box.setInformativeText("\n".join(f"• {line}" for line in problems) + "\n\n"
                           + _("A battery pushed past its limits can overheat, swell or catch fire. "
                               "Go ahead only if you know the battery takes it."))
    box.go_ahead = box.addButton(_("{action} anyway").format(action=action), QMessageBox.ButtonRole.DestructiveRole)
    cancel = box.addButton(QMessageBox.StandardButton.Cancel)
    box.setDefaultButton(cancel)
    box.setEscapeButton(cancel)
    return box


def confirm_unsafe(parent: QWidget | None, action: str, problems: list[str]) -> bool:
    """Ask; True only when the user chose to go ahead."""
    box = unsafe_dialog(parent, action, problems)
    box.exec()
    return box.clickedButton() is box.go_ahead
