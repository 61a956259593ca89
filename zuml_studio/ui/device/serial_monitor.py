"""The raw serial monitor (Device ▸ Serial Monitor): a terminal view of a port, what comes in as
text or hex, and a line to send. It opens the port the Device panel shows, at its baud rate;
while the Device panel is connected its protocol owns the port, and the monitor is off, saying
so. Reading polls the open port on the GUI thread (a few bytes a tick, never blocking)."""
from __future__ import annotations

import time
from collections.abc import Callable

from PySide6.QtCore import Qt, QTimer
from PySide6.QtGui import QFontDatabase, QTextCursor
from PySide6.QtWidgets import (QButtonGroup, QCheckBox, QComboBox, QDialog, QHBoxLayout, QLabel, QLineEdit, QPlainTextEdit,
                               QPushButton, QRadioButton, QVBoxLayout, QWidget)

from ...device.links.serial_port import open_serial
from ...device.errors import DeviceLinkError
from ...device.links.ports import VIRTUAL
from ...device.links.serial_lines import MonitorLines
from ...device.links.serial_text import SendLineError, parse_send
from ...i18n import _, ngettext
from ...safety import RawSendGuard

POLL_MS = 50
MAX_BLOCKS = 5000           # lines kept in the view (a port that never stops talking)


class SerialMonitor(QDialog):
    """A window of its own, not modal: the charger's raw bytes beside the IDE."""

    def __init__(self, target: Callable[[], tuple[str, int]], protocol_owns_port: Callable[[], bool],
                 parent: QWidget | None = None):
        super().__init__(parent)
        self.setObjectName("serialMonitor")
        self.setWindowTitle(_("Serial Monitor"))
        self._target = target                   # () -> (port or URL, baud) as the Device panel shows them
        self._owned = protocol_owns_port
        self.port = None
        self.received = b""                     # everything read since the port was opened (the view's source)
        # What was sent, as the charger's parser holds it: kept across sends, modes and reopening the
        # port (the charger's parser does not reset when the host closes its end).
        self.guard = RawSendGuard()

        self.where = QLabel()
        self.where.setObjectName("monitorPort")
        self.where.setWordWrap(True)
        self.open_button = QPushButton(_("Open"))
        self.open_button.setObjectName("monitorOpen")
        self.open_button.clicked.connect(self.toggle)
        self.text_mode = QRadioButton(_("Text"))
        self.hex_mode = QRadioButton(_("Hex"))
        self.text_mode.setChecked(True)
        modes = QButtonGroup(self)
        for button in (self.text_mode, self.hex_mode):
            modes.addButton(button)
            button.toggled.connect(self._redraw)
        self.timestamps = QCheckBox(_("Timestamps"))
        self.timestamps.setObjectName("monitorTimestamps")
        self.timestamps.setToolTip(_("Each line with the time it arrived; in Hex a line per burst of bytes"))
        self.timestamps.toggled.connect(self._redraw)
        self._lines = MonitorLines()
        self._bursts: list[tuple[float, bytes]] = []    # what came in, with when: the view is drawn again from it
        clear = QPushButton(_("Clear"))
        clear.clicked.connect(self.clear)
        self.view = QPlainTextEdit()
        self.view.setObjectName("monitorView")
        self.view.setReadOnly(True)
        self.view.setMaximumBlockCount(MAX_BLOCKS)
        self.view.setFont(QFontDatabase.systemFont(QFontDatabase.SystemFont.FixedFont))
        self.send_line = QLineEdit()
        self.send_line.setObjectName("monitorSend")
        self.send_line.setPlaceholderText(_("text to send (\\n, \\r, \\xNN escapes) or hex bytes in Hex mode"))
        self.send_line.returnPressed.connect(self.send)
        self.ending = QComboBox()
        self.ending.setObjectName("monitorEnding")
        for key, label in (("none", _("no line ending")), ("lf", "LF"), ("cr", "CR"), ("crlf", "CR+LF")):
            self.ending.addItem(label, key)
        self.send_button = QPushButton(_("Send"))
        self.send_button.clicked.connect(self.send)
        self.message = QLabel()
        self.message.setObjectName("monitorMessage")
        self.message.setWordWrap(True)

        top = QHBoxLayout()
        top.addWidget(self.where, 1)
        top.addWidget(self.text_mode)
        top.addWidget(self.hex_mode)
        top.addWidget(self.timestamps)
        top.addWidget(clear)
        top.addWidget(self.open_button)
        bottom = QHBoxLayout()
        bottom.addWidget(self.send_line, 1)
        bottom.addWidget(self.ending)
        bottom.addWidget(self.send_button)
        layout = QVBoxLayout(self)
        layout.addLayout(top)
        layout.addWidget(self.view, 1)
        layout.addLayout(bottom)
        layout.addWidget(self.message)
        self.resize(720, 460)

        self._timer = QTimer(self, interval=POLL_MS)
        self._timer.timeout.connect(self._poll)
        self.refresh()

    # -- state ---------------------------------------------------------------------------------
    def is_open(self) -> bool:
        return self.port is not None

    def refresh(self) -> None:
        """Enable what may be used now: nothing while the Device panel's protocol has the port."""
        url, baud = self._target()
        owned = self._owned()
        if owned and self.is_open():
            self.close_port(_("Closed: the Device panel connected to the charger."))
        self.where.setText(_("{port} at {baud} baud").format(port=url, baud=baud) if url != VIRTUAL
                           else _("the built-in virtual charger has no port to watch: choose a port in the "
                                  "Device panel"))
        self.open_button.setEnabled(not owned and (self.is_open() or url != VIRTUAL))
        self.open_button.setText(_("Close") if self.is_open() else _("Open"))
        self.send_line.setEnabled(self.is_open())
        self.send_button.setEnabled(self.is_open())
        if owned:
            self.say(_("The Device panel is connected: its protocol owns the port. Disconnect there to watch "
                       "the raw bytes here."))

    def say(self, text: str) -> None:
        self.message.setText(text)

    # -- the port ------------------------------------------------------------------------------
    def toggle(self) -> None:
        if self.is_open():
            self.close_port(_("Closed."))
        else:
            self.open_port()

    def open_port(self) -> bool:
        url, baud = self._target()
        if self._owned() or url == VIRTUAL:
            self.refresh()
            return False
        try:
            port = open_serial(url, baud)
        except DeviceLinkError as exc:
            self.say(str(exc))
            return False
        port.timeout = 0                        # reads return what is there, at once
        self.port = port
        self.clear()
        self._timer.start()
        self.say(_("Open: {port} at {baud} baud.").format(port=url, baud=baud))
        self.refresh()
        return True

    def close_port(self, why: str = "") -> None:
        self._timer.stop()
        port, self.port = self.port, None
        if port is not None:
            try:
                port.close()
            except OSError:
                pass                            # unplugged meanwhile: closed all the same
        if why:
            self.say(why)
        self.refresh()

    def _poll(self) -> None:
        if self.port is None:
            return
        try:
            data = self.port.read(self.port.in_waiting or 1)
        except OSError as exc:                  # pyserial's SerialException is one: the port went away
            self.close_port(_("The port closed: {reason}").format(reason=exc))
            return
        if data:
            self.received += data
            self._append(data)

    def send(self) -> bool:
        if self.port is None:
            return False
        try:
            data = parse_send(self.send_line.text(), self.hex_mode.isChecked(), self.ending.currentData())
        except SendLineError as exc:
            self.say(str(exc))
            return False
        verdict = self.guard.judge(data)
        if not verdict.safe:
            # Writing, starting or storing goes through the Device panel, whose check judges the macro.
            self.say(_("Not sent: with what was sent before, the line completes a ZUML request that changes the "
                       "charger; use the Device panel, whose safety check guards what reaches it. ({why})").format(
                    why=verdict.errors[0]))
            return False
        try:
            self.port.write(data)
        except OSError as exc:                  # pyserial's SerialException and its timeout are OSErrors
            self.close_port(_("The port closed: {reason}").format(reason=exc))
            return False
        self.guard.sent(data)
        self.say(ngettext("Sent {n} byte.", "Sent {n} bytes.", len(data)).format(n=len(data)))
        self.send_line.clear()
        return True

    # -- the view ------------------------------------------------------------------------------
    def _options(self) -> None:
        self._lines.hex_mode = self.hex_mode.isChecked()
        self._lines.timestamps = self.timestamps.isChecked()

    def _append(self, data: bytes) -> None:
        when = time.time()
        self._bursts.append((when, data))
        if len(self._bursts) > MAX_BLOCKS:          # the view keeps as many lines: older bursts are gone from it
            del self._bursts[:len(self._bursts) - MAX_BLOCKS]
        self._options()
        cursor = self.view.textCursor()
        cursor.movePosition(QTextCursor.MoveOperation.End)
        cursor.insertText(self._lines.render(when, data))
        self.view.setTextCursor(cursor)
        self.view.ensureCursorVisible()

    def _redraw(self) -> None:
        self._options()
        self.view.setPlainText(self._lines.render_all(self._bursts))
        self.view.moveCursor(QTextCursor.MoveOperation.End)

    def clear(self) -> None:
        self.received = b""
        self._bursts.clear()
        self._lines.render_all([])
        self.view.clear()

    def text(self) -> str:
        return self.view.toPlainText()

    def closeEvent(self, event) -> None:
        self.close_port()
        super().closeEvent(event)

    def keyPressEvent(self, event) -> None:
        # Esc would close a dialog; the monitor is a window: it closes by its title bar.
        if event.key() != Qt.Key.Key_Escape:
            super().keyPressEvent(event)
