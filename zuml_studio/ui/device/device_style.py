"""What the device panel's parts share: message colours, headings, rules, form fields, elided labels and
the controls' scroll area."""
from __future__ import annotations

import weakref

from PySide6.QtCore import QEvent, QSize, Qt, Signal
from PySide6.QtGui import QPalette
from PySide6.QtWidgets import (QAbstractSpinBox, QApplication, QBoxLayout, QComboBox, QDoubleSpinBox, QFrame,
                               QHBoxLayout, QLabel, QScrollArea, QSizePolicy, QSpinBox, QSplitter, QStyle, QStyleOptionComboBox,
                               QStylePainter, QToolTip, QVBoxLayout, QWidget)

from ..base import theme
from ..base.number_boxes import double_spin_box, form_field, spin_box

FIELD_WIDTH = 92
DEFAULT_BATTERY = ("NiMh", 2000, 4)


def colour(widget: QWidget, kind: str) -> str:
    """A message colour ("info", "ok", "error", "warn") readable on the widget's palette."""
    c = theme.colours(widget.palette())
    return {"ok": c.ok, "error": c.error, "warn": c.warning}.get(kind, c.muted)


class _Tints:
    """Gives each tinted widget its colour again when the application's palette changes (light
    <-> dark): a widget with a style sheet gets no PaletteChange of its own."""

    def __init__(self):
        self.widgets: weakref.WeakSet = weakref.WeakSet()
        QApplication.instance().paletteChanged.connect(self._recolour)

    def _recolour(self, _palette=None) -> None:
        for widget in list(self.widgets):
            try:
                _apply_tint(widget)
            except RuntimeError:        # its C++ side is gone
                self.widgets.discard(widget)


_tints: _Tints | None = None


def _apply_tint(widget: QWidget) -> None:
    kind = widget.property("tint")
    c = theme.colours(QApplication.palette())
    hue = {"ok": c.ok, "error": c.error, "warn": c.warning, "none": ""}.get(kind, c.muted)
    sheet = f"color:{hue};" if hue else ""
    if widget.styleSheet() != sheet:        # a new sheet re-polishes the widget: only when it changes
        widget.setStyleSheet(sheet)


def tint(widget: QWidget, kind: str) -> None:
    """Draw ``widget``'s text in the colour of ``kind`` ("info", "ok", "error", "warn"; "none":
    the palette's own), from the application palette's light or dark set, now and after the
    palette changes."""
    global _tints
    if _tints is None:
        _tints = _Tints()
    _tints.widgets.add(widget)
    widget.setProperty("tint", kind)
    _apply_tint(widget)


def heading(text: str) -> QLabel:
    label = QLabel(text)
    font = label.font()
    font.setBold(True)
    label.setFont(font)
    return label


def heading_row(text: str, button: QWidget) -> QHBoxLayout:
    """A part's bold title with its one tool button at the right (⟳ read again)."""
    row = QHBoxLayout()
    row.setSpacing(4)
    row.addWidget(heading(text), 1)
    row.addWidget(button)
    return row


def vline() -> QFrame:
    """A thin rule between the columns, in the palette's own mid tone (light or dark)."""
    line = QFrame()
    line.setFrameShape(QFrame.Shape.VLine)
    line.setFrameShadow(QFrame.Shadow.Plain)
    line.setForegroundRole(QPalette.ColorRole.Mid)
    return line


def field_spin(*args) -> QSpinBox:
    return form_field(spin_box(*args), min_width=60)


def field_double(*args) -> QDoubleSpinBox:
    return form_field(double_spin_box(*args), min_width=60)


class ElidedCombo(QComboBox):
    """A combo box whose closed face elides a choice too long for it ("Junsi iCharger (106B/…"),
    its whole text then heading the tooltip; the list shows every choice whole.

    ``size_by(texts)``: the box asks for the width of the longest of these texts (in the language
    shown), not of its longest choice: choices the user adds (a saved battery's name) then elide
    rather than widen the panel, and a language with longer words still gets its words whole."""
    _size_texts: tuple[str, ...] = ()

    def size_by(self, texts) -> None:
        self._size_texts = tuple(texts)
        self.updateGeometry()

    def sizeHint(self) -> QSize:  # noqa: N802
        return self._capped(super().sizeHint())

    def minimumSizeHint(self) -> QSize:  # noqa: N802
        return self._capped(super().minimumSizeHint())

    def _capped(self, hint: QSize) -> QSize:
        if not self._size_texts:
            return hint
        opt = QStyleOptionComboBox()
        self.initStyleOption(opt)
        text = max(self.fontMetrics().horizontalAdvance(t) for t in self._size_texts)
        wanted = self.style().sizeFromContents(QStyle.ContentsType.CT_ComboBox, opt,
                                               QSize(text + 4, self.fontMetrics().height()), self)
        return QSize(min(hint.width(), wanted.width()), hint.height())

    def elided(self) -> bool:
        return self._face()[1]

    def _face(self) -> tuple[str, bool]:
        opt = QStyleOptionComboBox()
        self.initStyleOption(opt)
        room = self.style().subControlRect(QStyle.ComplexControl.CC_ComboBox, opt,
                                           QStyle.SubControl.SC_ComboBoxEditField, self).width()
        text = self.currentText()
        shown = self.fontMetrics().elidedText(text, Qt.TextElideMode.ElideRight, max(10, room - 2))
        return shown, shown != text

    def paintEvent(self, event) -> None:  # noqa: N802
        painter = QStylePainter(self)
        opt = QStyleOptionComboBox()
        self.initStyleOption(opt)
        opt.currentText = self._face()[0]
        painter.drawComplexControl(QStyle.ComplexControl.CC_ComboBox, opt)
        painter.drawControl(QStyle.ControlElement.CE_ComboBoxLabel, opt)

    def event(self, event) -> bool:  # noqa: A003
        if event.type() == QEvent.Type.ToolTip and self.elided():
            tip = self.toolTip()
            QToolTip.showText(event.globalPos(), self.currentText() + ("\n\n" + tip if tip else ""), self)
            return True
        return super().event(event)


class ElidedLabel(QLabel):
    """A one-line label that elides its (plain) text to its width; the whole text is the tooltip."""

    def __init__(self, text: str = "", parent: QWidget | None = None,
                 mode: Qt.TextElideMode = Qt.TextElideMode.ElideRight):
        super().__init__(parent)
        self._full = ""
        self._mode = mode
        self.setSizePolicy(QSizePolicy.Policy.Ignored, QSizePolicy.Policy.Preferred)
        self.setMinimumWidth(40)
        self.set_full_text(text)

    def set_full_text(self, text: str) -> None:
        self._full = text
        self.setToolTip(text)
        self._elide()

    def full_text(self) -> str:
        return self._full

    def sizeHint(self) -> QSize:  # noqa: N802
        """The whole text's width: a layout that respects the hint (Preferred) gives it that where
        the row has room, and elides it only down to the minimum width where it has not."""
        hint = super().sizeHint()
        return QSize(self.fontMetrics().horizontalAdvance(self._full) + 2 * self.margin() + 4, hint.height())

    def resizeEvent(self, event) -> None:  # noqa: N802
        super().resizeEvent(event)
        self._elide()

    def _elide(self) -> None:
        width = max(10, self.width() - 2)
        super().setText(self.fontMetrics().elidedText(self._full, self._mode, width))


STACK_PX = 480      # from this height the controls stand in one column


class ControlsScroll(QScrollArea):
    """The controls in two narrow columns (what is on the charger; the run and the passport),
    preferring the width its columns want (QScrollArea caps its size hint at 36 lines of text,
    which would squeeze the fields), and scrolling vertically only when the dock is too low. Standing
    in one column it may hold another part under the run's (``hold``): the live view's phases."""
    stackedChanged = Signal(bool)

    def __init__(self, charger: QWidget, run: QWidget, passport: QWidget, parent: QWidget | None = None):
        super().__init__(parent)
        col_b = QWidget()
        col_b.setObjectName("runColumn")
        b = QVBoxLayout(col_b)
        b.setContentsMargins(0, 0, 0, 0)
        b.setSpacing(3)
        b.addWidget(run)
        b.addWidget(passport)
        b.addStretch(1)
        self._run_layout = b
        columns = QWidget()
        cols = QHBoxLayout(columns)
        cols.setContentsMargins(0, 0, 4, 0)
        cols.setSpacing(10)
        cols.addWidget(charger, 10)
        self._line = vline()
        cols.addWidget(self._line)
        cols.addWidget(col_b, 11)
        self._cols, self._charger, self._run = cols, charger, col_b
        self.setObjectName("deviceControls")
        self.setWidget(columns)
        self.setWidgetResizable(True)
        self.setFrameShape(QFrame.Shape.NoFrame)
        self.setHorizontalScrollBarPolicy(Qt.ScrollBarPolicy.ScrollBarAlwaysOff)
        # At least this narrow-column width, and never narrower than the texts (Russian runs longer).
        charger.setMinimumWidth(max(215, charger.minimumSizeHint().width()))
        col_b.setMinimumWidth(max(265, col_b.minimumSizeHint().width()))
        self.setMinimumWidth(columns.minimumSizeHint().width() + 14)

    def is_stacked(self) -> bool:
        return self._cols.direction() == QBoxLayout.Direction.TopToBottom

    def showEvent(self, event) -> None:  # noqa: N802
        super().showEvent(event)
        self._guard_wheel()

    def _guard_wheel(self) -> None:
        """A wheel turned over a box the user has not clicked scrolls the column (it used to change
        the cells or the task while the user scrolled past); a focused box still takes it."""
        for box in self.widget().findChildren(QWidget):
            if isinstance(box, (QComboBox, QAbstractSpinBox)) and not box.property("wheelGuarded"):
                box.setProperty("wheelGuarded", True)
                box.setFocusPolicy(Qt.FocusPolicy.StrongFocus)
                box.installEventFilter(self)

    def eventFilter(self, watched, event) -> bool:  # noqa: N802
        if event.type() == QEvent.Type.Wheel and isinstance(watched, (QComboBox, QAbstractSpinBox)) \
                and watched.property("wheelGuarded") and not watched.hasFocus():
            QApplication.sendEvent(self.verticalScrollBar(), event)
            return True
        return super().eventFilter(watched, event)

    def resizeEvent(self, event) -> None:  # noqa: N802
        super().resizeEvent(event)
        self._stack(self.height() >= STACK_PX)

    def _stack(self, stacked: bool) -> None:
        """With the window's height to itself (the Charge mode) the two columns become one, the run
        first (Start and Stop stay in view) and what is on the charger below, so the live plot gets the
        width; the splitter it stands in gives it just that column's width."""
        if stacked == self.is_stacked():
            return
        for widget in (self._charger, self._line, self._run):
            self._cols.removeWidget(widget)
        order = (self._run, self._line, self._charger) if stacked else (self._charger, self._line, self._run)
        for widget, stretch in zip(order, (0, 0, 1) if stacked else (10, 0, 11)):
            self._cols.addWidget(widget, stretch)
        self._line.setVisible(not stacked)
        self._cols.setDirection(QBoxLayout.Direction.TopToBottom if stacked else QBoxLayout.Direction.LeftToRight)
        self.stackedChanged.emit(stacked)
        self.setMinimumWidth(self.widget().minimumSizeHint().width() + 14)
        splitter = self.parentWidget()
        if isinstance(splitter, QSplitter) and splitter.count() == 2:
            mine = self.sizeHint().width()
            splitter.setSizes([mine, max(1, sum(splitter.sizes()) - mine)])

    def hold(self, widget: QWidget) -> None:
        """``widget`` under the run's part, taking the column's spare height (it leaves when another
        layout takes it)."""
        self._run_layout.insertWidget(2, widget, 1)
        widget.show()

    def sizeHint(self):  # noqa: N802
        hint = super().sizeHint()
        widget = self.widget()
        if widget is not None:
            hint.setWidth(widget.sizeHint().width() + self.verticalScrollBar().sizeHint().width()
                          + 2 * self.frameWidth())
        return hint


class MessageLine(QLabel):
    """The panel's message line: the last thing that happened, coloured by its kind."""

    def __init__(self, parent: QWidget | None = None):
        super().__init__("", parent)
        self.full_text = ""             # as said, with its line breaks
        self.setObjectName("deviceMessage")
        self.setWordWrap(True)
        self.setTextInteractionFlags(Qt.TextInteractionFlag.TextSelectableByMouse)
        self.setSizePolicy(QSizePolicy.Policy.Expanding, QSizePolicy.Policy.Preferred)

    def say(self, text: str, kind: str = "info") -> None:
        self.full_text = text
        # One paragraph: the line is as wide as the panel, a list's line breaks would take the plot's height.
        self.setText("  ".join(line.strip() for line in text.split("\n") if line.strip()))
        tint(self, kind)
        self.setToolTip(text if len(text) > 80 else "")
