"""The iMAX B6's front panel in the device panel: its 16×2 display as the ZUML firmware writes it, and,
for the simulated B6 (``virtual.simulated_b6``), its four buttons, which press the simulated ones live:
a button is down while the mouse holds it, so a short press and START held 0.5 s both work as on the
charger. A real B6 heard on its TX alone (driver zuml-tx) shows its display only: its buttons are its own.
"""
from __future__ import annotations

import time

from PySide6.QtCore import Qt
from PySide6.QtGui import QFontDatabase
from PySide6.QtWidgets import QFrame, QHBoxLayout, QLabel, QPushButton, QVBoxLayout

from ...i18n import N_, _

COLUMNS = 16
# (the simulator's name, the label, what it does) in the B6's order, left to right
BUTTONS = (("stop", N_("STOP"), N_("Stop the run; back from setting the current")),
           ("dec", N_("DEC −"), N_("The slot before, or 0.1 A less")),
           ("inc", N_("INC +"), N_("The next slot, or 0.1 A more")),
           ("start", N_("START"), N_("Show the charge current; held 0.5 s: start the slot shown")))
# An LCD's own colours (a yellow-green glass, dark pixels), the same in a light or a dark window: it is
# the charger's display, not the window's.
LCD_STYLE = ("QLabel#b6Lcd { background: #9fb83a; color: #1d2a07; border: 2px solid #3c4a14; "
             "border-radius: 3px; padding: 3px 6px; }")


class B6FrontPanel(QFrame):
    def __init__(self, parent=None) -> None:
        super().__init__(parent)
        self.setObjectName("b6FrontPanel")
        self._b6 = None                 # the simulated B6 while connected to it
        self._listening = False         # a real B6 on its TX: its display only
        self._down: dict[str, float] = {}
        self.lcd = QLabel()
        self.lcd.setObjectName("b6Lcd")
        font = QFontDatabase.systemFont(QFontDatabase.SystemFont.FixedFont)
        font.setPointSizeF(font.pointSizeF() * 1.3)
        font.setBold(True)
        self.lcd.setFont(font)
        self.lcd.setStyleSheet(LCD_STYLE)
        self.lcd.setTextFormat(Qt.TextFormat.PlainText)
        self.lcd.setToolTip(_("The charger's display, as its firmware writes it"))
        self.title = QLabel(_("iMAX B6 (ZUML firmware)"))
        self.title.setObjectName("b6Title")
        self.buttons: dict[str, QPushButton] = {}
        keys = QHBoxLayout()
        keys.setSpacing(4)
        for name, label, tip in BUTTONS:
            button = QPushButton(_(label))
            button.setObjectName(f"b6{name.capitalize()}")
            button.setToolTip(_(tip))
            button.setFocusPolicy(Qt.FocusPolicy.NoFocus)
            button.pressed.connect(lambda name=name: self.press(name))
            button.released.connect(lambda name=name: self.release(name))
            self.buttons[name] = button
            keys.addWidget(button)
        side = QVBoxLayout()
        side.setSpacing(2)
        side.addWidget(self.title)
        side.addLayout(keys)
        layout = QHBoxLayout(self)
        layout.setContentsMargins(0, 2, 0, 2)
        layout.setSpacing(10)
        layout.addWidget(self.lcd, 0)
        layout.addLayout(side, 0)
        layout.addStretch(1)
        self.show_lcd("", "")
        self.setVisible(False)

    # -- what it shows ------------------------------------------------------------------------------
    def show_device(self, b6) -> None:
        """The simulated B6 (``SimulatedB6``) whose buttons these are, or None: hidden, nothing pressed."""
        self._b6 = b6
        self._listening = False
        self._down.clear()
        for button in self.buttons.values():
            button.setVisible(b6 is not None)
        self.title.setText(_("Simulated iMAX B6 (ZUML firmware)") if b6 is not None else
                           _("iMAX B6 (ZUML firmware), heard on its TX"))
        if b6 is None:
            self.show_lcd("", "")
        else:
            self.show_lcd(*b6.lcd)
        self.setVisible(b6 is not None)

    def listen(self) -> None:
        """A charger heard on its TX alone: its display is shown once its stream carries one."""
        self.show_device(None)
        self._listening = True

    def show_lcd(self, line1: str, line2: str) -> None:
        if not (self._b6 or self._listening) and (line1 or line2):
            return                      # a line that arrives after the link closed
        self.lcd.setText(f"{line1[:COLUMNS]:<{COLUMNS}}\n{line2[:COLUMNS]:<{COLUMNS}}")
        if (line1 or line2) and not self.isVisible():
            self.setVisible(True)

    def text(self) -> tuple[str, str]:
        """The display's two lines, trailing spaces cut."""
        lines = self.lcd.text().split("\n")
        return lines[0].rstrip(), lines[1].rstrip()

    # -- the buttons ----------------------------------------------------------------------------------
    def press(self, name: str) -> None:
        if self._b6 is None:
            return
        self._down[name] = time.monotonic()
        self._b6.press(name)

    def release(self, name: str) -> None:
        since = self._down.pop(name, None)
        if self._b6 is None or since is None:
            return
        self._b6.release(name, time.monotonic() - since)
