"""Questions before a device action that cannot be undone: Restore over the charger's macros,
and closing ZUML Studio while a charge runs. Cancel is the default of each."""
from __future__ import annotations

from PySide6.QtCore import QStandardPaths
from PySide6.QtWidgets import QMessageBox, QWidget

STOP, LEAVE, CANCEL = "stop", "leave", "cancel"


def documents_folder() -> str:
    """Where Backup and Restore start: the user's documents, never the current directory."""
    return QStandardPaths.writableLocation(QStandardPaths.StandardLocation.DocumentsLocation)


def restore_text(file_name: str, on_charger: list[str], in_image: list[str] | None) -> str:
    """What Restore will replace, and which macros on the charger it will lose."""
    if not on_charger:
        head = f"Write {file_name} over the charger's EEPROM?"
    else:
        head = (f"Write {file_name} over the charger's EEPROM? It replaces the {len(on_charger)} macro(s) "
                f"on the charger: {', '.join(on_charger)}.")
    if in_image is None:
        return head
    lost = [name for name in on_charger if name not in in_image]
    return head + (f"\nLost (not in the image): {', '.join(lost)}." if lost
                   else "\nEvery macro on the charger is also in the image.") + \
        f"\nThe image holds {len(in_image)} macro(s){': ' + ', '.join(in_image) if in_image else ''}."


def confirm_restore(parent: QWidget | None, text: str) -> bool:
    box = QMessageBox(QMessageBox.Icon.Warning, "Restore the charger's EEPROM", text, parent=parent)
    go = box.addButton("Restore", QMessageBox.ButtonRole.DestructiveRole)
    cancel = box.addButton(QMessageBox.StandardButton.Cancel)
    box.setDefaultButton(cancel)
    box.setEscapeButton(cancel)
    box.exec()
    return box.clickedButton() is go


def ask_close_during_run(parent: QWidget | None, run: str, virtual: bool) -> str:
    """STOP, LEAVE or CANCEL."""
    text = f"{run or 'A macro'} is running on the charger."
    if virtual:
        text += "\nThe built-in virtual charger ends with ZUML Studio either way."
    box = QMessageBox(QMessageBox.Icon.Question, "A charge is running", text, parent=parent)
    box.setInformativeText("Stop the charger before closing, or leave it running on its own?")
    stop = box.addButton("Stop the charger", QMessageBox.ButtonRole.DestructiveRole)
    leave = box.addButton("Leave it running", QMessageBox.ButtonRole.AcceptRole)
    cancel = box.addButton(QMessageBox.StandardButton.Cancel)
    box.setDefaultButton(cancel)
    box.setEscapeButton(cancel)
    box.exec()
    return {id(stop): STOP, id(leave): LEAVE}.get(id(box.clickedButton()), CANCEL)
