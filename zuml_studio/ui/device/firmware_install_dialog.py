"""Device ▸ Install Firmware on an iMAX B6…: the warnings a user must read, then the same steps as
`zuml firmware install` (device/avr_install.py) off the GUI thread, each step shown as it happens, with the
same rules: a new backup folder each time, a locked original said before anything is written (installed over
only after the user says yes to "no way back"), the fuses checked and set only when asked; Restore puts a
saved backup back."""
from __future__ import annotations

from pathlib import Path

from PySide6.QtCore import Qt, Signal
from PySide6.QtWidgets import (QCheckBox, QComboBox, QDialog, QDialogButtonBox, QFileDialog, QFormLayout,
                               QHBoxLayout, QLabel, QLineEdit, QPlainTextEdit, QPushButton, QVBoxLayout, QWidget)

from ...device import avr_install
from ...device.avrdude import Programmer
from ...i18n import _
from ..base.background import BackgroundCall
from .confirm_dialogs import ask_warning

PROGRAMMERS = ("usbasp", "stk500v1", "avrisp", "arduino", "usbtiny")


def ask_no_way_back(parent: QWidget | None, reason: str) -> bool:
    """The original cannot be read: install anyway? Cancel is the default."""
    return ask_warning(parent, _("No way back to the original firmware"), reason,
                       _("Install the ZUML firmware anyway, knowing that the charger's own firmware is then lost for "
                         "good?"), _("Install, there is no way back"))


class FirmwareInstallDialog(QDialog):
    said = Signal(str)          # a step's line, from the worker thread

    def __init__(self, parent: QWidget | None = None):
        super().__init__(parent)
        self.setObjectName("firmwareInstallDialog")
        self.setWindowTitle(_("Install Firmware on an iMAX B6"))
        self._call: BackgroundCall | None = None
        layout = QVBoxLayout(self)
        warning = QLabel("<b>" + _("Read this first") + "</b><ul>" +
                         "".join(f"<li>{line}</li>" for line in avr_install.warnings()) + "</ul>")
        warning.setWordWrap(True)
        warning.setTextFormat(Qt.TextFormat.RichText)
        layout.addWidget(warning)

        form = QFormLayout()
        self.programmer = QComboBox()
        self.programmer.setEditable(True)
        self.programmer.addItems(PROGRAMMERS)
        form.addRow(_("Programmer (avrdude -c):"), self.programmer)
        self.port = QLineEdit()
        self.port.setPlaceholderText(_("only for serial programmers, e.g. /dev/ttyUSB0"))
        form.addRow(_("Port:"), self.port)
        self.image = QLineEdit()
        self.image.setPlaceholderText(_("the imaxb6 image, built ({path})").format(path=avr_install.IMAGE))
        form.addRow(_("Image:"), self._with_browse(self.image, self._choose_image))
        self.backup = QLineEdit(str(avr_install.default_backup_folder()))
        form.addRow(_("Save the original in:"), self.backup)
        self.fix_fuses = QCheckBox(_("Set the fuses the B6 needs where they differ: brown-out at 4.0 V, the 16 MHz "
                                     "crystal, JTAG off"))
        form.addRow("", self.fix_fuses)
        layout.addLayout(form)

        self.read_it = QCheckBox(_("I have read the warnings above"))
        layout.addWidget(self.read_it)
        self.log = QPlainTextEdit()
        self.log.setReadOnly(True)
        self.log.setObjectName("firmwareInstallLog")
        layout.addWidget(self.log, 1)

        buttons = QDialogButtonBox(QDialogButtonBox.StandardButton.Close)
        self.install_button = buttons.addButton(_("&Install"), QDialogButtonBox.ButtonRole.ActionRole)
        self.restore_button = buttons.addButton(_("&Restore an Original…"), QDialogButtonBox.ButtonRole.ActionRole)
        buttons.rejected.connect(self.reject)
        self.install_button.clicked.connect(self.install)
        self.restore_button.clicked.connect(self._choose_restore)
        layout.addWidget(buttons)
        self.read_it.toggled.connect(self._update_enabled)
        self.said.connect(self.log.appendPlainText)
        self._update_enabled()
        self.resize(720, 620)

    def _with_browse(self, edit: QLineEdit, choose) -> QWidget:
        row = QWidget()
        box = QHBoxLayout(row)
        box.setContentsMargins(0, 0, 0, 0)
        box.addWidget(edit, 1)
        browse = QPushButton(_("Browse…"))
        browse.clicked.connect(choose)
        box.addWidget(browse)
        return row

    def _choose_image(self) -> None:
        path, _filter = QFileDialog.getOpenFileName(self, _("Firmware Image"), "",
                                                    _("Firmware images (*.elf *.hex *.bin)"))
        if path:
            self.image.setText(path)

    def _choose_restore(self) -> None:
        folder = QFileDialog.getExistingDirectory(self, _("The Backup Folder"),
                                                  str(avr_install.default_backup_folder().parent))
        if folder:
            self.restore(Path(folder))

    def programmer_choice(self) -> Programmer:
        return Programmer(self.programmer.currentText().strip() or "usbasp", self.port.text().strip() or None)

    def busy(self) -> bool:
        return self._call is not None

    def _update_enabled(self) -> None:
        idle = not self.busy()
        self.install_button.setEnabled(idle and self.read_it.isChecked())
        self.restore_button.setEnabled(idle)

    def install(self, no_way_back: bool = False) -> None:
        """``no_way_back``: the user accepted that an original which cannot be read is lost."""
        programmer, folder, fix = self.programmer_choice(), Path(self.backup.text().strip()), self.fix_fuses.isChecked()
        image = Path(self.image.text().strip()) if self.image.text().strip() else None

        def work():
            chosen = image or avr_install.build_image()
            avr_install.install(programmer, chosen, folder, fix, self.said.emit, no_way_back)
            return _("Done. To put the backup back: Restore an Original…, folder {folder}").format(folder=folder)
        self._run(work)

    def restore(self, folder: Path) -> None:
        programmer = self.programmer_choice()

        def work():
            avr_install.restore(programmer, folder, self.said.emit)
            return _("Done.")
        self._run(work)

    def _run(self, work) -> None:
        self.log.clear()
        self._call = BackgroundCall(work, self)
        self._call.done.connect(lambda text: self._finished(str(text)))
        self._call.failed.connect(self._failed)
        self._update_enabled()
        self._call.start()

    def _finished(self, line: str) -> None:
        self.log.appendPlainText(line)
        self._call.wait()
        self._call = None
        folder = Path(self.backup.text().strip())
        if folder.exists():         # used now: the next install saves into a new folder (never over a backup)
            self.backup.setText(str(avr_install.fresh_folder(folder)))
        self._update_enabled()

    def _failed(self, exc: BaseException) -> None:
        self._finished(_("Stopped: {reason}").format(reason=exc))
        if isinstance(exc, avr_install.OriginalUnreadable) and ask_no_way_back(self, str(exc)):
            self.install(no_way_back=True)

    def reject(self) -> None:
        if not self.busy():         # avrdude writing the chip is not stopped halfway by a Close
            super().reject()
