"""The window's side of the safety policy (docs/safety.md): what ``safety.judge`` refuses never
goes to a charger from here, and is said in words; its warnings are asked about once per macro
while connected, Cancel the default."""
from __future__ import annotations

from PySide6.QtWidgets import QMessageBox, QWidget

from ...i18n import _, ngettext


def refusal_text(what: str, errors: list[str] | tuple[str, ...]) -> str:
    """Why an action did not happen (``what``: "Not flashed"), each danger on its own line."""
    return (_("{what}: the safety check refused it:").format(what=what) + "\n"
            + "\n".join(f"• {line}" for line in errors) + "\n"
            + _("ZUML Studio never sends what fails the safety check to a charger: fix the macro (only the "
                "command line's --force-unsafe overrides it, for a bench)."))


def warnings_dialog(parent: QWidget | None, action: str, warnings: list[str]) -> QMessageBox:
    """The question, not yet shown (``action``: the translated verb, "Flash"); ``box.go_ahead`` is
    the button that goes ahead."""
    box = QMessageBox(QMessageBox.Icon.Warning, _("Warnings about the battery"),
                      ngettext("{action}: the safety check has {n} warning about this macro.",
                               "{action}: the safety check has {n} warnings about this macro.",
                               len(warnings)).format(action=action, n=len(warnings)), parent=parent)
    box.setInformativeText("\n".join(f"• {line}" for line in warnings) + "\n\n"
                           + _("Go ahead only if you know the battery takes it; you are asked once for this "
                               "macro while connected."))
    box.go_ahead = box.addButton(action, QMessageBox.ButtonRole.AcceptRole)
    cancel = box.addButton(QMessageBox.StandardButton.Cancel)
    box.setDefaultButton(cancel)
    box.setEscapeButton(cancel)
    return box


def confirm_warnings(parent: QWidget | None, action: str, warnings: list[str]) -> bool:
    """Ask; True only when the user chose to go ahead."""
    box = warnings_dialog(parent, action, warnings)
    box.exec()
    return box.clickedButton() is box.go_ahead


def upload_refusal(errors) -> str:
    """What the Device tab says when Upload stops at the macro's errors (``errors``: the compile
    result's error diagnostics): the safety check's in its words, else where to look."""
    unsafe = [f"{d.code}: {d.message}" for d in errors if d.code.startswith("E3")]
    if unsafe:
        return refusal_text(_("Not uploaded"), unsafe)
    return ngettext("Not uploaded: the macro has {n} error (see Problems); fix it, then Upload.",
                    "Not uploaded: the macro has {n} errors (see Problems); fix them, then Upload.",
                    len(errors)).format(n=len(errors))
