"""Attach live runs to packs: when a macro starts on a charger, the pack on it is asked for once per
passport serial (a battery with a passport is known wherever it is plugged in) or else per port, and
remembered; the run's telemetry is then recorded and imported into that pack when the run ends."""
from __future__ import annotations

from collections.abc import Callable

from PySide6.QtCore import QObject, Signal
from PySide6.QtWidgets import QInputDialog, QWidget

from ...packs.db import Logbook, LogbookError
from ...packs.live import RunCollector, record_run
from ...packs.register import Pack, attach, attachment, attachment_key, list_packs
from ...packs.sessions import ImportResult
from ...i18n import _
from ..base.background import BackgroundCall

CANCELLED = object()        # ask_pack's answer when the user closed the question: neither attach nor remember


def ask_pack(parent: QWidget, packs: list[Pack], where: str):
    """The pack on the charger at ``where`` (a Pack), None for "record no pack here", or CANCELLED.
    ``packs`` are those that match the run (``LiveAttach.matching``), the first offered first."""
    none = _("No pack: do not record runs here")
    names = [p.name for p in packs] + [none]
    name, ok = QInputDialog.getItem(parent, _("Which Pack Is This?"), _(
            "Record this run in a pack's logbook? Asked once for {where}; the answer is remembered (the Packs "
            "dock lists the packs).").format(where=where), names, 0, False)
    if not ok:
        return CANCELLED
    return next((p for p in packs if p.name == name), None)


class LiveAttach(QObject):
    recorded = Signal(object)                 # the ImportResult of a run that ended
    statusMessage = Signal(str)

    def __init__(self, device_panel, parent: QObject | None = None,
                 book_factory: Callable[[], Logbook] = Logbook):
        super().__init__(parent)
        self.device = device_panel
        self.book_factory = book_factory
        self.ask: Callable[[QWidget, list[Pack], str], object] = ask_pack   # a test answers instead
        self.collector = RunCollector()
        self._passport = None
        self._pack: Pack | None = None
        self._jobs: set[BackgroundCall] = set()    # runs being recorded
        device_panel.telemetry_taps.append(self.collector.add)
        device_panel.run.passportRead.connect(self._passport_read)
        device_panel.startFinished.connect(self._started)
        device_panel.runSeen.connect(self._seen)
        device_panel.runEnded.connect(self._ended)

    def _passport_read(self, passport) -> None:
        self._passport = passport

    def run_battery(self) -> tuple[str | None, int]:
        """The run's chemistry (the virtual charger's battery; a real charger's is not known at START)
        and cells in series (0: not entered, or a run only listened to)."""
        opened = self.device.connection.opened
        if opened is None:                  # a monitor-only link or a replay: the panel's START fields are not its
            return None, 0
        chemistry = self.device.v_chem.currentData() if opened.virtual else None
        return chemistry, int(self.device.series_spin.value())

    def matching(self, packs: list[Pack]) -> list[Pack]:
        """The packs this run can be: the same cells, the same chemistry where the run's is known, and
        the passport's serial where the battery and the pack have one."""
        chemistry, cells = self.run_battery()
        serial = getattr(self._passport, "serial", "") or None
        return [p for p in packs if (not cells or p.cells == cells) and (chemistry is None or p.chemistry == chemistry)
                and (serial is None or p.serial is None or p.serial == serial)]

    def _where(self) -> tuple[str, str]:
        opened = self.device.connection.opened
        link = self.device.monitor.link            # a charger only listened to (its runs start on it)
        port = link.port if opened is None and link is not None else (
            "virtual" if opened is None or opened.virtual else opened.url)
        serial = getattr(self._passport, "serial", "") or None
        key = attachment_key(port, serial)
        where = _("the battery with serial {serial}").format(serial=serial) if serial else _("port {port}").format(
                port=port)
        return key, where

    def _seen(self) -> None:
        """A run started on the charger's own buttons (a B6 heard on its TX): as if started here."""
        if not self.collector.collecting:
            self._started(True)

    def _started(self, ok: bool, _text: str = "") -> None:
        self._pack = None
        if not ok:
            return
        try:
            book = self.book_factory()
        except LogbookError as exc:
            self.statusMessage.emit(str(exc))
            return
        try:
            key, where = self._where()
            known, pack = attachment(book, key)
            if not known:
                packs = list_packs(book)
                if not packs:
                    return                    # nothing to attach to yet: ask once there is a pack
                packs = self.matching(packs)
                if not packs:                 # never offer a NiMH pack for a LiPo run: not recorded, asked again
                    chemistry, cells = self.run_battery()
                    self.statusMessage.emit(_("No pack in the logbook matches this run ({chemistry}, {cells} cells): "
                                              "not recorded.").format(chemistry=chemistry or _("chemistry not known"),
                                                                      cells=cells or "–"))
                    return
                answer = self.ask(self.device, packs, where)
                if answer is CANCELLED:
                    return
                pack = answer
                attach(book, key, pack)
            self._pack = pack
            if pack is not None:
                self.collector.start()
                self.statusMessage.emit(_("Recording this run in pack '{name}'.").format(name=pack.name))
        finally:
            book.close()

    def _ended(self) -> None:
        if self._pack is None or not self.collector.collecting:
            return
        samples = self.collector.take()
        opened = self.device.connection.opened
        device = opened.info.model if opened is not None else _("charger")
        passport = ((self._passport.err, self._passport.crit) if self._passport is not None else (None, None))
        pack, self._pack = self._pack, None

        def job() -> ImportResult:
            # Off the GUI thread: a day at 10 Hz is most of a million samples to sum and write.
            book = self.book_factory()
            try:
                return record_run(book, pack, samples, device, passport=passport)
            finally:
                book.close()

        def done(result: ImportResult) -> None:
            self._jobs.discard(call)
            self.statusMessage.emit(_("Run recorded in pack '{name}'.").format(name=pack.name)
                                    if result.status == "added" else result.message)
            self.recorded.emit(result)

        def failed(exc: Exception) -> None:
            self._jobs.discard(call)
            self.statusMessage.emit(str(exc))

        call = BackgroundCall(job)
        self._jobs.add(call)            # kept until it has reported
        call.done.connect(done)
        call.failed.connect(failed)
        call.start()
