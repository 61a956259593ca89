"""Questions before a device action that cannot be undone: Restore over the charger's macros,
and closing ZUML Studio while a charge runs. Cancel is the default of each."""
from __future__ import annotations

from pathlib import Path

from PySide6.QtCore import QStandardPaths
from PySide6.QtWidgets import QMessageBox, QWidget

from ...i18n import _, ngettext

STOP, LEAVE, CANCEL = "stop", "leave", "cancel"


def documents_folder() -> str:
    """Where Backup and Restore start: the user's documents, never the current directory (nor a
    folder that does not exist, where the dialog would pick one itself): the home folder without them."""
    found = QStandardPaths.writableLocation(QStandardPaths.StandardLocation.DocumentsLocation)
    return found if found and Path(found).is_dir() else str(Path.home())


def restore_text(file_name: str, on_charger: list[str], in_image: list[str] | None) -> str:
    """What Restore will replace, and which macros on the charger it will lose."""
    head = _("Write {file} over the charger's EEPROM?").format(file=file_name)
    if on_charger:
        head += " " + ngettext("It replaces the {n} macro on the charger: {names}.",
                               "It replaces the {n} macros on the charger: {names}.",
                               len(on_charger)).format(n=len(on_charger), names=", ".join(on_charger))
    if in_image is None:
        return head
    lost = [name for name in on_charger if name not in in_image]
    head += "\n" + (_("Lost (not in the image): {names}.").format(names=", ".join(lost)) if lost
                    else _("Every macro on the charger is also in the image."))
    if not in_image:
        return head + "\n" + _("The image holds no macro.")
    return head + "\n" + ngettext("The image holds {n} macro: {names}.", "The image holds {n} macros: {names}.",
                                  len(in_image)).format(n=len(in_image), names=", ".join(in_image))


def confirm_restore(parent: QWidget | None, text: str) -> bool:
    return ask_warning(parent, _("Restore the charger's EEPROM"), text, "", _("Restore"))


def ask_warning(parent: QWidget | None, title: str, text: str, question: str, go_text: str,
                role: QMessageBox.ButtonRole = QMessageBox.ButtonRole.DestructiveRole) -> bool:
    """A warning with one button that goes ahead (``go_text``) and Cancel, the default: True if it goes ahead."""
    box = QMessageBox(QMessageBox.Icon.Warning, title, text, parent=parent)
    if question:
        box.setInformativeText(question)
    go = box.addButton(go_text, role)
    cancel = box.addButton(QMessageBox.StandardButton.Cancel)
    box.setDefaultButton(cancel)
    box.setEscapeButton(cancel)
    box.exec()
    return box.clickedButton() is go


def ask_close_during_run(parent: QWidget | None, run: str, virtual: bool) -> str:
    """STOP, LEAVE or CANCEL."""
    text = _("{name} is running on the charger.").format(name=run or _("A macro"))
    if virtual:
        text += "\n" + _("The built-in virtual charger ends with ZUML Studio either way.")
    box = QMessageBox(QMessageBox.Icon.Question, _("A charge is running"), text, parent=parent)
    box.setInformativeText(_("Stop the charger before closing, or leave it running on its own?"))
    stop = box.addButton(_("Stop the charger"), QMessageBox.ButtonRole.DestructiveRole)
    leave = box.addButton(_("Leave it running"), QMessageBox.ButtonRole.AcceptRole)
    cancel = box.addButton(QMessageBox.StandardButton.Cancel)
    box.setDefaultButton(cancel)
    box.setEscapeButton(cancel)
    box.exec()
    return {id(stop): STOP, id(leave): LEAVE}.get(id(box.clickedButton()), CANCEL)


def confirm_programmer(parent: QWidget | None) -> bool:
    """Before the window reaches a B6 through its ISP programmer: the battery must be off the charger."""
    from ...device.install.isp_store import disconnect_warning
    return ask_warning(parent, _("iMAX B6 through the programmer"), disconnect_warning(),
                       _("Every read and write through the programmer resets the charger. Is the battery "
                         "disconnected?"), _("The battery is disconnected"), QMessageBox.ButtonRole.AcceptRole)
