"""What is on the charger: its macros (the slot table and free bytes), Compile & Flash with
its target slot and progress, Backup and Restore. It owns the last EEPROM image read, the slot
flashed last and a write whose end the link lost (settled by the next image read)."""
from __future__ import annotations

import re
from datetime import date
from pathlib import Path
from typing import Callable

from PySide6.QtCore import Qt, Signal
from PySide6.QtWidgets import (QAbstractItemView, QComboBox, QFileDialog, QHBoxLayout, QHeaderView, QLabel,
                               QProgressBar, QPushButton, QTableWidget, QTableWidgetItem, QToolButton, QVBoxLayout,
                               QWidget)

from ...device.errors import CommitUncertain, CommitUnverified, ImageTooLarge
from ...device.zuml.flashing import merge_record
from ...file_errors import FileReadError, read_file_bytes
from ...i18n import N_, _, ngettext
from ...lang.eeprom import ImageError, Slot, slots, used_bytes
from ...safety import Verdict, judge, judge_image, judge_slots, named_template
from . import confirm_dialogs, unsafe_dialog
from .connection import DeviceConnection, describe_error
from .connection_bar import record_chemistry
from .device_style import ElidedCombo, colour, heading_row, tint

FLASH_TIP = N_("Write the editor's macro to the charger, verify it (Ctrl+Shift+F)")
STAGES = {"read": N_("reading {done} of {total} bytes"), "write": N_("writing {done} of {total} bytes"),
          "verify": N_("verifying {done} of {total} bytes")}


def backup_name(model: str, day: date) -> str:
    """A backup's file name: the charger's model and the day, ``iMAX-B6-2026-12-03.bin`` (a file per
    charger and day, sorted by both; characters a file system may refuse become "-")."""
    safe = re.sub(r"[^A-Za-z0-9._-]+", "-", model).strip("-.") or "charger"
    return f"{safe}-{day.isoformat()}.bin"


class Unsafe:
    """What a job hands back instead of writing: the safety check's verdict (refused when it has
    errors, else warnings to ask about) and the bytes it judged."""

    def __init__(self, verdict: Verdict, record: bytes):
        self.verdict = verdict
        self.record = record


def checked_image(client, image: bytes) -> tuple[bytes, list[Verdict | None]]:
    """``image`` with the safety check of each of its slots (on the worker thread: it asks the
    charger for the battery's passport and the start templates the macros name)."""
    try:
        return image, judge_slots(client, slots(image))
    except ImageError:      # a broken record list: show_image says so
        return image, []


def check_text(verdict: Verdict | None) -> str:
    """The slot list's Check column."""
    if verdict is None:
        return _("BAD")
    return verdict.check()


class SlotTable(QTableWidget):
    """The slot list. Its preferred height is small (a header and three rows): the column's
    layout gives it whatever room is left, and a preferred height of its own would make the
    controls scroll in a 380 px dock."""

    def sizeHint(self):  # noqa: N802
        hint = super().sizeHint()
        rows = self.verticalHeader().defaultSectionSize()
        hint.setHeight(self.horizontalHeader().sizeHint().height() + 3 * rows + 2 * self.frameWidth())
        return hint


class ChargerSlots(QWidget):
    message = Signal(str, str)                  # text, kind ("info", "ok", "warn", "error")
    flashFinished = Signal(bool, str)
    operationFinished = Signal(str, bool, str)  # "backup" | "restore" | "slots", ok, message
    imageShown = Signal()                       # a new image is shown (``slots``, ``flashed_slot``)
    slotChosen = Signal(int)                    # the user selected this slot in the table
    changed = Signal()                          # what may be enabled changed

    def __init__(self, connection: DeviceConnection, get_record: Callable[[], tuple[bytes, str] | None],
                 parent: QWidget | None = None):
        super().__init__(parent)
        self.setObjectName("deviceColumn")
        self.connection = connection
        self._get_record = get_record
        self.image: bytes | None = None
        self.slots: list[Slot] = []
        self.verdicts: list[Verdict | None] = []    # the safety check of each slot, from the bytes read back
        self.flashed_slot: int | None = None
        # (slot, name) of the macro running now, None when none runs (the panel sets it from the run)
        self.running_macro: Callable[[], tuple[int | None, str] | None] = lambda: None
        self.charger_info = None            # the connected charger's DeviceInfo (a backup's name, a settle's check)
        self._unsettled: tuple[str, CommitUncertain | CommitUnverified] | None = None   # (what, error)
        self.table = SlotTable(0, 5)
        self.table.setObjectName("slotTable")
        self.table.setHorizontalHeaderLabels(["#", _("Macro"), _("Bytes"), _("Type"), _("Check")])
        self.table.verticalHeader().setVisible(False)
        self.table.verticalHeader().setDefaultSectionSize(self.fontMetrics().height() + 6)
        self.table.setEditTriggers(QAbstractItemView.EditTrigger.NoEditTriggers)
        self.table.setSelectionBehavior(QAbstractItemView.SelectionBehavior.SelectRows)
        self.table.setSelectionMode(QAbstractItemView.SelectionMode.SingleSelection)
        self.table.setAlternatingRowColors(True)
        self.table.setShowGrid(False)
        header = self.table.horizontalHeader()
        header.setSectionResizeMode(QHeaderView.ResizeMode.ResizeToContents)
        header.setSectionResizeMode(1, QHeaderView.ResizeMode.Stretch)
        header.setHighlightSections(False)
        self.table.setMinimumHeight(2 * self.table.verticalHeader().defaultSectionSize() + 26)
        self.table.setToolTip(_("The macros in the charger's EEPROM, in slot order; select one to run it"))
        self.free_label = QLabel("")
        self.free_label.setObjectName("freeLabel")
        self.flash_slot = ElidedCombo()
        self.flash_slot.setObjectName("flashSlot")
        self.flash_slot.addItem(_("By name"), None)
        self.flash_slot.setSizeAdjustPolicy(QComboBox.SizeAdjustPolicy.AdjustToMinimumContentsLengthWithIcon)
        self.flash_slot.setMinimumContentsLength(9)         # a long choice elides (ElidedCombo)
        self.flash_slot.setToolTip(_("Where Compile & Flash puts the macro: over the one of the same name "
                                     "(else appended), or into a slot you pick"))
        self.flash_button = QPushButton(_("Compile && Flash"))
        self.flash_button.setObjectName("flashButton")
        self.flash_button.setToolTip(_(FLASH_TIP))
        self.progress = QProgressBar()
        self.progress.setObjectName("flashProgress")
        self.progress.setTextVisible(False)
        self.progress.setFixedHeight(6)
        self.progress.setRange(0, 1)
        self.progress.setValue(0)
        self.result_label = QLabel("")
        self.result_label.setObjectName("flashResult")
        self.result_label.setWordWrap(True)
        self.result_label.setTextInteractionFlags(Qt.TextInteractionFlag.TextSelectableByMouse)
        self.backup_button = QPushButton(_("Backup…"))
        self.backup_button.setToolTip(_("Save the charger's whole EEPROM to a file"))
        self.restore_button = QPushButton(_("Restore…"))
        self.restore_button.setToolTip(_("Write a saved EEPROM image back (every record is checked first)"))
        self.reload_button = QToolButton()
        self.reload_button.setText("⟳")
        self.reload_button.setToolTip(_("Read the macros on the charger again"))

        a = QVBoxLayout(self)
        a.setContentsMargins(0, 0, 0, 0)
        a.setSpacing(3)
        a.addLayout(heading_row(_("Macros on the charger"), self.reload_button))
        a.addWidget(self.table, 1)
        a.addWidget(self.free_label)
        flash_row = QHBoxLayout()
        flash_row.setSpacing(4)
        flash_row.addWidget(self.flash_slot, 1)
        flash_row.addWidget(self.flash_button)
        a.addLayout(flash_row)
        a.addWidget(self.progress)
        a.addWidget(self.result_label)
        file_row = QHBoxLayout()
        file_row.setSpacing(4)
        file_row.addWidget(self.backup_button)
        file_row.addWidget(self.restore_button)
        file_row.addStretch(1)
        a.addLayout(file_row)

        self.flash_button.clicked.connect(lambda: self.flash())
        self.backup_button.clicked.connect(self._backup_clicked)
        self.restore_button.clicked.connect(self._restore_clicked)
        self.reload_button.clicked.connect(self.refresh_slots)
        self.table.itemSelectionChanged.connect(self._table_selected)
        connection.progress.connect(self.on_progress)

    def set_enabled(self, idle: bool, monitor_reason: str = "") -> None:
        """``idle``: connected to a ZUML charger that does nothing else; ``monitor_reason``: why a
        monitor-only charger cannot flash (then everything is off)."""
        for w in (self.flash_button, self.backup_button, self.restore_button, self.reload_button, self.flash_slot):
            w.setEnabled(idle and not monitor_reason)
        self.flash_button.setToolTip(monitor_reason or _(FLASH_TIP))
        if monitor_reason:
            self.result_label.setText(f"<span style='color:{colour(self, 'warn')};'>{monitor_reason}.</span>")
            self.result_label.setProperty("monitorReason", True)
        elif self.result_label.property("monitorReason"):
            self.result_label.setText("")
            self.result_label.setProperty("monitorReason", False)

    # -- progress -----------------------------------------------------------------------------
    def progress_busy(self) -> None:
        self.progress.setRange(0, 0)

    def on_progress(self, stage: str, done: int, total: int) -> None:
        self.progress.setRange(0, max(1, total))
        self.progress.setValue(min(done, total))
        text = STAGES.get(stage)
        self.progress.setToolTip(_(text).format(done=done, total=total) if text else f"{stage} {done}/{total}")

    def progress_complete(self, tip: str) -> None:
        """A flash went through: the bar stays full (until the next operation) and says what."""
        self.progress.setRange(0, 1)
        self.progress.setValue(1)
        self.progress.setToolTip(tip)

    def progress_done(self) -> None:
        self.progress.setRange(0, 1)
        self.progress.setValue(0)

    # -- the image ----------------------------------------------------------------------------
    def show_image(self, image: bytes, verdicts: list[Verdict | None] | None = None) -> list[Slot]:
        """Show the macros in ``image`` with the safety check of each (``checked_image``; None: judged
        here without the charger's passport and templates); returns them (and says so with ``imageShown``)."""
        self.image = bytes(image)
        try:
            found = slots(self.image)
            used = used_bytes(self.image)
            broken = ""
        except Exception as exc:   # noqa: BLE001 - a broken record list
            found, used, broken = [], 0, str(exc)
        self.slots = found
        if verdicts is None or len(verdicts) != len(found):
            verdicts = [judge(s.record) if s.ok else None for s in found]
        self.verdicts = verdicts
        self.table.setRowCount(len(found))
        for row, (s, verdict) in enumerate(zip(found, verdicts)):
            values = (str(s.index), s.name, str(len(s.record)), record_chemistry(s.record) if s.ok else "?",
                      check_text(verdict))
            for col, value in enumerate(values):
                item = QTableWidgetItem(value)
                if col in (0, 2):
                    item.setTextAlignment(Qt.AlignmentFlag.AlignRight | Qt.AlignmentFlag.AlignVCenter)
                if col == 4 and (verdict is None or not verdict.safe):
                    item.setForeground(Qt.GlobalColor.red)
                    item.setToolTip(str(s.error.message if s.error else "") if verdict is None
                                    else "\n".join(verdict.errors))
                self.table.setItem(row, col, item)
        size = len(self.image)
        if broken:
            self.free_label.setText(f"<span style='color:{colour(self, 'error')};'>"
                                    + _("broken record list: {error}").format(error=broken) + "</span>")
        else:
            self.free_label.setText(ngettext("{free} of {size} bytes free · {n} macro",
                                             "{free} of {size} bytes free · {n} macros", len(found))
                                    .format(free=size - used, size=size, n=len(found)))
        keep_flash = self.flash_slot.currentData()
        self.flash_slot.clear()
        self.flash_slot.addItem(_("By name"), None)
        for s in found:
            self.flash_slot.addItem(_("Replace slot {index} ({name})").format(index=s.index, name=s.name), s.index)
        self.flash_slot.addItem(_("Append as slot {index}").format(index=len(found)), len(found))
        k = self.flash_slot.findData(keep_flash)
        self.flash_slot.setCurrentIndex(k if k >= 0 and keep_flash is not None and keep_flash < len(found) else 0)
        self.imageShown.emit()
        return found

    def forget(self) -> None:
        """Another device: no image, no macros, nothing flashed (a replay after a charger)."""
        self.image = None
        self.slots = []
        self.flashed_slot = None
        self.table.setRowCount(0)
        self.free_label.setText("")
        self.flash_slot.clear()
        self.flash_slot.addItem(_("By name"), None)

    def _table_selected(self) -> None:
        rows = self.table.selectionModel().selectedRows()
        if rows:
            self.slotChosen.emit(rows[0].row())

    def slot_names(self) -> list[str]:
        return [s.name for s in self.slots]

    # -- Compile & Flash ----------------------------------------------------------------------
    def flash(self) -> None:
        """Compile & Flash: the editor's record into the charger (same name replaced, else appended,
        or the slot chosen), written, verified; ``flashFinished(ok, message)``. The safety check
        runs first: what it refuses is not written; its warnings are asked about once."""
        if not self.connection.is_connected():
            self._flash_done(False, _("Connect to a charger first, then Compile & Flash."))
            return
        got = self._get_record()
        if got is None:
            self._flash_done(False, _("The macro has errors: fix them (see Problems), then Compile & Flash."))
            return
        record, name = bytes(got[0]), got[1]
        slot = self.flash_slot.currentData()
        self.result_label.setText("")
        self.message.emit(_("Flashing {name}…").format(name=name), "info")
        self.progress_busy()

        warned = record in self.connection.warned

        def job(client, progress):
            templates = client.templates_named([named_template(record)])
            verdict = judge(record, client.passport_if_any(), templates=templates,
                            charger_max_a=client.info.max_charge_a)
            if verdict.errors or (verdict.warnings and not warned):
                return Unsafe(verdict, record)
            current = client.read_image(progress)
            merged = merge_record(current, record, slot)
            result = client.write_image(merged.image, progress, current=current)
            return merged, result, checked_image(client, merged.image)[1]

        self.connection.call(job, self._flashed, self._flash_failed)
        self.changed.emit()

    def _flashed(self, answer) -> None:
        if isinstance(answer, Unsafe):
            self.progress_done()
            if answer.verdict.errors:
                self._flash_done(False, unsafe_dialog.refusal_text(_("Not flashed"), answer.verdict.errors))
            elif unsafe_dialog.confirm_warnings(self, _("Flash"), list(answer.verdict.warnings)):
                self.connection.warned.add(answer.record)
                self.flash()
            else:
                self._flash_done(False, _("Not flashed: cancelled at the safety check's warnings."))
            return
        merged, result, verdicts = answer
        self.progress_complete(_("flashed {name}: {size} bytes, verified").format(name=merged.name, size=merged.size))
        self.flashed_slot = merged.index
        self.show_image(merged.image, verdicts)
        if result.changed:
            text = _("Flashed {name} into slot {index}: {size} bytes, {changed} bytes changed, verified").format(
                name=merged.name, index=merged.index, size=merged.size, changed=result.changed)
        else:
            text = _("{name} is already in slot {index} ({size} bytes): nothing to write").format(
                name=merged.name, index=merged.index, size=merged.size)
        if merged.replaced is not None and merged.replaced != merged.name:
            text += " " + _("(it replaced {name})").format(name=merged.replaced)
        text += "."
        running = self.running_macro()
        if result.changed and running is not None and (merged.index == running[0] or merged.replaced == running[1]):
            # The charger runs the copy it read at START: the new bytes take effect from the next one.
            text += " " + _("The charge running now continues with the copy of {name} it started with; the new "
                            "one runs from the next Start.").format(name=running[1] or merged.replaced)
        self._flash_done(True, text)

    def _flash_failed(self, exc) -> None:
        self.progress_done()
        self._note_unsettled("flash", exc)
        self._flash_done(False, describe_error(exc, "flash"))
        if self.connection.is_connected():
            self.refresh_slots()

    def _flash_done(self, ok: bool, text: str) -> None:
        # A refusal's reasons are the message line's (under the plot, the panel's width): here only its
        # first line, so a five-line refusal does not push Backup, Restore and the progress out of view.
        first = text.split("\n", 1)[0]
        self.result_label.setText(first)
        self.result_label.setToolTip(text if first != text else "")
        tint(self.result_label, "ok" if ok else "error")
        self.message.emit(text, "ok" if ok else "error")
        self.changed.emit()
        self.flashFinished.emit(ok, text)

    # -- Backup, Restore, the slot list -------------------------------------------------------
    def backup(self, path: str | Path) -> None:
        """Save the charger's whole EEPROM to ``path``; ``operationFinished("backup", ok, message)``."""
        if not self.connection.is_connected():
            self._failed("backup", _("Connect to a charger first."))
            return
        path = Path(path)

        def job(client, progress):
            image = client.read_image(progress)
            path.write_bytes(image)
            return checked_image(client, image)

        def done(checked):
            image = checked[0]
            self.show_image(*checked)
            try:
                count = len(slots(image))
                text = ngettext("Saved the charger's EEPROM ({size} bytes, {n} macro) to {path}.",
                                "Saved the charger's EEPROM ({size} bytes, {n} macros) to {path}.", count)
            except Exception:   # noqa: BLE001
                count, text = 0, _("Saved the charger's EEPROM ({size} bytes, a broken record list) to {path}.")
            text = text.format(size=len(image), n=count, path=path)
            self.progress_done()
            self.message.emit(text, "ok")
            self.operationFinished.emit("backup", True, text)

        self.progress_busy()
        self.connection.call(job, done, lambda exc: self._failed("backup", exc))

    def restore(self, path: str | Path) -> None:
        """Write a saved image back (checked first, then written and verified): an image with a record
        the safety check refuses is not written; its warnings are asked about once."""
        if not self.connection.is_connected():
            self._failed("restore", _("Connect to a charger first."))
            return
        path = Path(path)

        def job(client, progress):
            from ...device.zuml.client import check_image
            image = read_file_bytes(path)
            check_image(image)
            if len(image) > client.info.eeprom_size:
                raise ImageTooLarge(len(image), client.info.eeprom_size)
            templates = client.templates_named(named_template(s.record) for s in slots(image) if s.ok)
            verdict = judge_image(image, client.passport_if_any(), templates=templates,
                                  charger_max_a=client.info.max_charge_a)
            if verdict.errors or (verdict.warnings and image not in self.connection.warned):
                return Unsafe(verdict, image)
            result = client.write_image(image, progress, validate=False)
            return checked_image(client, image + b"\xff" * (client.info.eeprom_size - len(image))), result

        def done(answer):
            if isinstance(answer, Unsafe):
                self.progress_done()
                if answer.verdict.errors:
                    self._failed("restore", unsafe_dialog.refusal_text(_("Not restored"), answer.verdict.errors))
                elif unsafe_dialog.confirm_warnings(self, _("Restore"), list(answer.verdict.warnings)):
                    self.connection.warned.add(answer.record)
                    self.restore(path)
                else:
                    self._failed("restore", _("Not restored: cancelled at the safety check's warnings."))
                return
            (image, verdicts), result = answer
            self.show_image(image, verdicts)
            text = _("Restored {file}: {changed} bytes changed, verified.").format(file=path.name,
                                                                                   changed=result.changed)
            self.progress_done()
            self.message.emit(text, "ok")
            self.operationFinished.emit("restore", True, text)

        self.progress_busy()
        self.connection.call(job, done, lambda exc: self._failed("restore", exc))

    def refresh_slots(self) -> None:
        """Read the slot list again (it settles a write whose end the link lost)."""
        if not self.connection.is_connected():
            return

        lost = self._unsettled[1] if self._unsettled is not None else None

        def job(client, progress):
            # Asked before the read: a write still staged there is dropped, never committed late.
            same = client.committed(lost) if lost is not None else None
            return checked_image(client, client.read_image()), same

        def done(result):
            checked, same = result
            self.show_image(*checked)
            self._settle(checked[0], same)
            self.operationFinished.emit("slots", True, "")

        self.connection.call(job, done, lambda exc: self._failed("slots", exc))

    def _note_unsettled(self, what: str, exc) -> None:
        if isinstance(exc, (CommitUncertain, CommitUnverified)):
            self._unsettled = (what, exc, self.charger_info)

    def _settle(self, image: bytes, same: bool | None) -> None:
        """The first image read after a write whose end was lost tells what the charger holds, when
        the charger read is the one written to: IDENTIFY tells another model, the write's token
        (``same``, from ``ChargerClient.committed``) another unit of the same model."""
        if self._unsettled is None:
            return
        (what, exc, written_to), self._unsettled = self._unsettled, None
        if written_to is not None and self.charger_info is not None and self.charger_info != written_to:
            self.message.emit(_("Another device answers on this port now ({now}, not the {was} written to): nothing "
                                "is known about the lost write; check that charger's macros when it is back.").format(
                                    now=f"{self.charger_info.model} {self.charger_info.firmware}",
                                    was=f"{written_to.model} {written_to.firmware}"), "warn")
            return
        verdict = exc.settle(image)
        flash = what == "flash"
        if verdict == "new" and not same:
            self.message.emit(_("Read back after the lost link: this charger holds the new image, but it is not "
                                "verified to be the one written to (it does not know that write: another charger "
                                "of the same model, or it restarted). Check the charger you meant to write."),
                              "warn")
        elif verdict == "new":
            self.message.emit(_("Read back after the lost link: the flash is on the charger, verified.") if flash
                              else _("Read back after the lost link: the restored image is on the charger, "
                                     "verified."), "ok")
        elif verdict == "previous":
            self.message.emit(_("Read back after the lost link: the charger kept its previous image; the flash "
                                "was not written. Do it again.") if flash
                              else _("Read back after the lost link: the charger kept its previous image; the "
                                     "restore was not written. Do it again."), "warn")
        else:
            self.message.emit(_("Read back after the lost link: the charger holds neither the new image nor the "
                                "previous one (changed since by another program?). Check its macros."), "warn")

    def _failed(self, op: str, exc) -> None:
        self.progress_done()
        self._note_unsettled(op, exc)
        text = exc if isinstance(exc, str) else describe_error(exc, op)
        self.message.emit(text, "error")
        self.changed.emit()
        self.operationFinished.emit(op, False, text)

    def _backup_clicked(self) -> None:
        suggested = Path(confirm_dialogs.documents_folder()) / backup_name(self.charger_info.model if self.charger_info else "", date.today())
        path, _filter = QFileDialog.getSaveFileName(self, _("Back up the charger's EEPROM"), str(suggested),
                                                    _("EEPROM images (*.bin);;All files (*)"))
        if path:
            self.backup(path)

    def _restore_clicked(self) -> None:
        path, _filter = QFileDialog.getOpenFileName(self, _("Restore an EEPROM image"),
                                                    confirm_dialogs.documents_folder(),
                                                    _("EEPROM images (*.bin);;All files (*)"))
        if not path:
            return
        try:
            in_image = [s.name for s in slots(read_file_bytes(path))]
        except (FileReadError, ImageError):     # restore() says precisely why
            in_image = None
        text = confirm_dialogs.restore_text(Path(path).name, self.slot_names(), in_image)
        if confirm_dialogs.confirm_restore(self, text):
            self.restore(path)
        else:
            self.message.emit(_("Not restored: {file} was not written.").format(file=Path(path).name), "info")
