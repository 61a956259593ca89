"""The pieces of the visual editor: phase cards, cycle boxes, command chips and the section
columns that hold them. Each piece knows the path of its node in the macro
(``visual_edits.path_of``) and asks its host, the VisualEditor, for every change; it
never changes anything itself. ``bind(node, …)`` shows a node's values again, so a
check that keeps the macro's shape refreshes the cards in place."""
from __future__ import annotations

import json

from PySide6.QtCore import QMimeData, QPoint, Qt
from PySide6.QtGui import QAction, QColor, QDrag, QPainter, QPen, QPixmap
from PySide6.QtWidgets import (QApplication, QComboBox, QFrame, QGridLayout, QHBoxLayout, QLabel, QMenu, QSizePolicy,
                               QSpinBox, QToolButton, QVBoxLayout, QWidget)

from ...lang import visual_edits as ve
from ...i18n import N_, _, ngettext
from ...lang import opcodes as ops
from ...lang.ast import Cycle, Phase, Statement
from .fields import Field, make_field
from .style import SECTION_TITLES, colours

MIME = "application/x-zuml-visual-item"

_OPERAND_LABELS = {
    ops.CONSTANT_I: [N_("Current")], ops.CONSTANT_V: [N_("Voltage")],
    ops.CHARGE_EX: [N_("Charge for"), N_("at"), N_("Discharge for"), N_("at"), N_("Measure at")],
    ops.TRICKLE: [N_("Current"), N_("On below"), N_("Off at")],
}
_COMMAND_LABELS = {ops.BY_KEYWORD["MUSIC"]: ("♪", N_("Music")), ops.BY_KEYWORD["LIGHT"]: ("✦", N_("Lights"))}
ADD_PHASE_TIPS = {"charge": N_("Add a phase at the end of the charge section"),
                  "discharge": N_("Add a phase at the end of the discharge section")}
NO_SECTION_TEXTS = {"charge": N_("No charge section: the charger uses its default."),
                    "discharge": N_("No discharge section: the charger uses its default.")}


def _command_label(op: ops.Op) -> str:
    """MUSIC and LIGHT by a sign and a word; another command by its keyword."""
    if op in _COMMAND_LABELS:
        sign, word = _COMMAND_LABELS[op]
        return f"{sign} {_(word)}"
    return op.keyword.title()


def _label(text: str, role: str = "field", tip: str = "") -> QLabel:
    label = QLabel(text)
    label.setProperty("role", role)
    if tip:
        label.setToolTip(tip)
    return label


def _tool(text: str, tip: str, role: str = "icon", name: str = "") -> QToolButton:
    button = QToolButton()
    button.setText(text)
    button.setToolTip(tip)
    button.setProperty("role", role)
    button.setCursor(Qt.CursorShape.PointingHandCursor)
    button.setFocusPolicy(Qt.FocusPolicy.TabFocus)
    if name:
        button.setObjectName(name)
    return button


def encode_path(path: tuple) -> bytes:
    return json.dumps(list(path)).encode()


def decode_path(data: bytes) -> tuple:
    return tuple(json.loads(bytes(data).decode()))


# -- dragging ------------------------------------------------------------------------------------

class DragSource:
    """Mixin for a QWidget with ``host`` and ``path``: pulled, it starts a QDrag of its path;
    pressed and released without moving, it is 'clicked'."""

    _press: QPoint | None = None

    def grabbed_at(self, pos: QPoint) -> bool:
        """Whether a press there may start a drag (a box is dragged by its header only)."""
        return True

    def mousePressEvent(self, event) -> None:
        if event.button() == Qt.MouseButton.LeftButton and self.grabbed_at(event.position().toPoint()):
            self._press = event.position().toPoint()
            event.accept()
            return
        super().mousePressEvent(event)

    def mouseMoveEvent(self, event) -> None:
        if self._press is not None and (event.buttons() & Qt.MouseButton.LeftButton):
            if (event.position().toPoint() - self._press).manhattanLength() >= QApplication.startDragDistance():
                self._press = None
                self.start_drag()
                return
        super().mouseMoveEvent(event)

    def mouseReleaseEvent(self, event) -> None:
        if self._press is not None and event.button() == Qt.MouseButton.LeftButton:
            self._press = None
            self.clicked()
            event.accept()
            return
        super().mouseReleaseEvent(event)

    def clicked(self) -> None:
        self.host.goto(self.path)

    def mime(self) -> QMimeData:
        data = QMimeData()
        data.setData(MIME, encode_path(self.path))
        return data

    def start_drag(self) -> None:
        drag = QDrag(self)
        drag.setMimeData(self.mime())
        pixmap = self.grab()
        if pixmap.width() > 360:
            pixmap = pixmap.scaledToWidth(360, Qt.TransformationMode.SmoothTransformation)
        faded = QPixmap(pixmap.size())
        faded.fill(Qt.GlobalColor.transparent)
        painter = QPainter(faded)
        painter.setOpacity(0.75)
        painter.drawPixmap(0, 0, pixmap)
        painter.end()
        drag.setPixmap(faded)
        drag.setHotSpot(QPoint(min(20, faded.width() // 2), 12))
        self.setProperty("dragging", True)
        self._repolish()
        drag.exec(Qt.DropAction.MoveAction)
        if self.parent() is not None:                     # may be gone: the drop rebuilt the cards
            self.setProperty("dragging", False)
            self._repolish()

    def _repolish(self) -> None:
        self.style().unpolish(self)
        self.style().polish(self)


class DraggableFrame(DragSource, QFrame):
    """A card or chip: dragged from anywhere on it."""

    def __init__(self, host, path: tuple, parent: QWidget | None = None):
        super().__init__(parent)
        self.host = host
        self.path = path


class DropZone(QFrame):
    """Holds items (cards, cycle boxes, chips) in order and takes drops of its own items:
    a drag may reorder only within the container it came from."""

    def __init__(self, host, path: tuple, parent: QWidget | None = None):
        super().__init__(parent)
        self.host = host
        self.path = path
        self.setAcceptDrops(True)
        self._indicator: int | None = None
        self.items_layout = QVBoxLayout()
        self.items_layout.setContentsMargins(0, 0, 0, 0)
        self.items_layout.setSpacing(8)
        self.item_widgets: list[QWidget] = []

    def add_item(self, widget: QWidget) -> None:
        self.item_widgets.append(widget)
        self.items_layout.addWidget(widget)

    def _source(self, event) -> tuple | None:
        if not event.mimeData().hasFormat(MIME):
            return None
        path = decode_path(event.mimeData().data(MIME))
        return path if tuple(path[:-1]) == tuple(self.path) else None

    def drop_index(self, y: int, source: tuple) -> int:
        """The index the dragged item gets when dropped at ``y`` (this widget's coordinates)."""
        before = 0
        for widget in self.item_widgets:
            centre = widget.mapTo(self, QPoint(0, widget.height() // 2)).y()
            if centre < y:
                before += 1
        start = source[-1]
        to = before if before <= start else before - 1
        return max(0, min(to, len(self.item_widgets) - 1))

    def _indicator_y(self, y: int) -> int:
        ys = []
        for widget in self.item_widgets:
            top = widget.mapTo(self, QPoint(0, 0)).y()
            ys.append((top + widget.height() // 2, top - 4, top + widget.height() + 4))
        for centre, top, _bottom in ys:
            if y < centre:
                return top
        return ys[-1][2] if ys else y

    def dragEnterEvent(self, event) -> None:
        if self._source(event) is not None:
            event.acceptProposedAction()
        else:
            event.ignore()

    def dragMoveEvent(self, event) -> None:
        if self._source(event) is None:
            event.ignore()
            return
        event.acceptProposedAction()
        self._indicator = self._indicator_y(event.position().toPoint().y())
        self.update()

    def dragLeaveEvent(self, event) -> None:
        self._indicator = None
        self.update()

    def dropEvent(self, event) -> None:
        source = self._source(event)
        self._indicator = None
        self.update()
        if source is None:
            event.ignore()
            return
        event.acceptProposedAction()
        to = self.drop_index(event.position().toPoint().y(), source)
        self.host.drop_item(tuple(self.path), source[-1], to)

    def paintEvent(self, event) -> None:
        super().paintEvent(event)
        if self._indicator is not None:
            painter = QPainter(self)
            pen = QPen(QColor(colours(self.palette())["charge"]), 3, Qt.PenStyle.SolidLine, Qt.PenCapStyle.RoundCap)
            painter.setPen(pen)
            painter.drawLine(10, self._indicator, self.width() - 10, self._indicator)
            painter.end()


# -- shared menu -------------------------------------------------------------------------------

def _item_menu(host, path: tuple, parent: QWidget, first: bool, last: bool, in_cycle: bool,
               is_phase: bool) -> QMenu:
    menu = QMenu(parent)
    menu.setObjectName("itemMenu")

    def add(text: str, slot, enabled: bool = True) -> QAction:
        action = menu.addAction(text)
        action.triggered.connect(slot)
        action.setEnabled(enabled)
        return action

    add(_("Move up"), lambda: host.move_item(path, -1), not first)
    add(_("Move down"), lambda: host.move_item(path, +1), not last)
    menu.addSeparator()
    if is_phase:
        add(_("Wrap in cycle"), lambda: host.wrap(path), not in_cycle)
        add(_("Remove from cycle"), lambda: host.remove_from_cycle(path), in_cycle)
        menu.addSeparator()
    add(_("Delete phase"), lambda: host.delete_item(path))
    return menu


# -- a phase -----------------------------------------------------------------------------------

class PhaseCard(DraggableFrame):
    """One phase: its sentence, its action with values, its stop conditions."""

    def __init__(self, host, path: tuple, section: str, phase: Phase, parent: QWidget | None = None):
        super().__init__(host, path, parent)
        self.setObjectName("phaseCard")
        self.setProperty("section", section)
        self.section = section
        self.setCursor(Qt.CursorShape.OpenHandCursor)
        self.setFocusPolicy(Qt.FocusPolicy.ClickFocus)
        self.setSizePolicy(QSizePolicy.Policy.Preferred, QSizePolicy.Policy.Maximum)
        self.in_cycle = len(path) > 2
        self.first = self.last = False

        self.grip = _label("⠿", "grip", _("Drag to reorder"))
        self.badge = _label(_("PHASE"), "badge")
        self.up = _tool("▲", _("Move up"), name="moveUp")
        self.down = _tool("▼", _("Move down"), name="moveDown")
        self.more = _tool("⋯", _("More"), name="more")
        self.up.clicked.connect(lambda: self.host.move_item(self.path, -1))
        self.down.clicked.connect(lambda: self.host.move_item(self.path, +1))
        self.more.clicked.connect(lambda: self._menu().exec(self.more.mapToGlobal(QPoint(0, self.more.height()))))
        head = QHBoxLayout()
        head.setSpacing(4)
        head.addWidget(self.grip)
        head.addWidget(self.badge)
        head.addStretch(1)
        for button in (self.up, self.down, self.more):
            head.addWidget(button)

        self.sentence = _label("", "sentence")
        self.sentence.setObjectName("phaseSentence")
        self.sentence.setWordWrap(True)
        self.sentence.setMinimumWidth(160)

        self.grid = QGridLayout()
        self.grid.setHorizontalSpacing(8)
        self.grid.setVerticalSpacing(2)
        self.grid.setColumnStretch(3, 1)
        self.grid.setColumnMinimumWidth(0, 72)           # the fields line up from card to card

        self.action_combo = QComboBox()
        self.action_combo.setObjectName("actionKind")
        for kind in ve.action_kinds():
            self.action_combo.addItem(kind.label, kind.key)
            self.action_combo.setItemData(self.action_combo.count() - 1, kind.ops[0].help
                                          if len(kind.ops) == 1 else ops.CONSTANT_I.help, Qt.ItemDataRole.ToolTipRole)
        self.action_combo.activated.connect(self._action_picked)
        row = 0
        self.action_combo.setSizePolicy(QSizePolicy.Policy.Maximum, QSizePolicy.Policy.Fixed)
        self.action_combo.setMinimumContentsLength(14)
        self.grid.addWidget(_label(_("Action")), row, 0)
        self.grid.addWidget(self.action_combo, row, 1, 1, 3, Qt.AlignmentFlag.AlignLeft)
        row += 1

        self.action_fields: list[tuple[int, int, Field]] = []        # (statement index, operand, field)
        self.condition_fields: list[tuple[int, Field]] = []
        for k, st in enumerate(phase.statements):
            if st.op.role is not ops.Role.ACTION:
                continue
            names = _OPERAND_LABELS.get(st.op, [o.name for o in st.op.operands])
            for i, operand in enumerate(st.op.operands):
                field = make_field(operand)
                field.setToolTip(st.op.help)
                field.committed.connect(lambda text, k=k, i=i: self.host.edit_value(self.path + ("st", k), i, text))
                self.grid.addWidget(_label(_(names[i]) if i < len(names) else operand.name, tip=st.op.help), row, 0)
                self.grid.addWidget(field, row, 1)
                self.action_fields.append((k, i, field))
                row += 1

        conditions = [(k, st) for k, st in enumerate(phase.statements) if st.op.role is ops.Role.CONDITION]
        self.stop_label = _label(_("STOP WHEN") if conditions else _("NO STOP CONDITION"), "group")
        self.stop_label.setIndent(0)
        self.grid.addWidget(self.stop_label, row, 0)
        stop_row = row
        row += 1
        for k, st in conditions:
            field = make_field(st.op.operands[0])
            field.setToolTip(st.op.help)
            field.committed.connect(lambda text, k=k: self.host.edit_value(self.path + ("st", k), 0, text))
            remove = _tool("✕", _("Remove this condition"), "remove", name="removeCondition")
            remove.clicked.connect(lambda _=False, k=k: self.host.remove_statement(self.path + ("st", k)))
            self.grid.addWidget(_label(ve.condition_label(st.op), tip=st.op.help), row, 0)
            self.grid.addWidget(field, row, 1)
            self.grid.addWidget(remove, row, 2)
            self.condition_fields.append((k, field))
            row += 1

        self.add_condition = _tool("+ " + _("Condition"), _("Add a stop condition"), "add", name="addCondition")
        self.add_condition.setPopupMode(QToolButton.ToolButtonPopupMode.InstantPopup)
        self.add_menu = QMenu(self.add_condition)
        self.add_menu.setObjectName("addConditionMenu")
        self.add_condition.setMenu(self.add_menu)
        # On the STOP WHEN line, not a row of its own: at 1366x768 the dock shows several cards.
        self.grid.addWidget(self.add_condition, stop_row, 1, 1, 3, Qt.AlignmentFlag.AlignRight)

        layout = QVBoxLayout(self)
        layout.setContentsMargins(10, 4, 8, 6)
        layout.setSpacing(4)
        layout.addLayout(head)
        layout.addWidget(self.sentence)
        layout.addLayout(self.grid)
        self.bind(phase, 1, True, True)

    def bind(self, phase: Phase, number: int, first: bool, last: bool) -> None:
        self.phase = phase
        self.first, self.last = first, last
        self.badge.setText(_("PHASE {n}").format(n=number))
        self.sentence.setText(ve.describe_phase(phase, self.section, nbsp=True))
        self.up.setEnabled(not first)
        self.down.setEnabled(not last)
        key = ve.action_key(phase)
        self.action_combo.setCurrentIndex(max(0, self.action_combo.findData(key)))
        for k, i, field in self.action_fields:
            if not field.busy():
                field.set_raw(phase.statements[k].args[i].raw)
        for k, field in self.condition_fields:
            if not field.busy():
                field.set_raw(phase.statements[k].args[0].raw)
        self.add_menu.clear()
        missing = ve.missing_conditions(phase)
        for op in missing:
            action = self.add_menu.addAction(f"{ve.condition_label(op)} x")
            action.setToolTip(op.help)
            action.setStatusTip(op.help)
            action.setData(op.code)
            action.triggered.connect(lambda _=False, op=op: self.host.add_condition(self.path, op))
        self.add_menu.setToolTipsVisible(True)
        self.add_condition.setEnabled(bool(missing))

    def _action_picked(self, index: int) -> None:
        key = self.action_combo.itemData(index)
        if key != ve.action_key(self.phase):
            self.host.set_action(self.path, key)

    def _menu(self) -> QMenu:
        return _item_menu(self.host, self.path, self, self.first, self.last, self.in_cycle, True)

    def contextMenuEvent(self, event) -> None:
        self._menu().exec(event.globalPos())


# -- a cycle -----------------------------------------------------------------------------------

class CycleBox(DragSource, DropZone):
    """A framed box around the items of a CYCLE, with its count."""

    def __init__(self, host, path: tuple, section: str, parent: QWidget | None = None):
        super().__init__(host, path, parent)
        self.setObjectName("cycleBox")
        self.setProperty("section", section)
        self.setSizePolicy(QSizePolicy.Policy.Preferred, QSizePolicy.Policy.Maximum)
        self.first = self.last = False

        self.grip = _label("⠿", "grip", _("Drag to reorder"))
        title = _label("↻ " + _("Repeat"), "cycleTitle")
        self.count = QSpinBox()
        self.count.setObjectName("cycleCount")
        self.count.setRange(1, 255)
        self.count.setKeyboardTracking(False)
        self.count.setSuffix(" ×")
        self.count.setFixedWidth(62)
        self.count.setToolTip(ops.CYCLE.help)
        self.count.editingFinished.connect(self._count_done)
        self.count.valueChanged.connect(self._count_stepped)
        self._count_shown = None
        self._setting = False
        self.up = _tool("▲", _("Move up"), name="moveUp")
        self.down = _tool("▼", _("Move down"), name="moveDown")
        self.unwrap_button = _tool(_("Unwrap"), _("Remove CYCLE/END_CYCLE, keep the phases"), name="unwrapCycle")
        self.more = _tool("⋯", _("More"), name="more")
        self.up.clicked.connect(lambda: self.host.move_item(self.path, -1))
        self.down.clicked.connect(lambda: self.host.move_item(self.path, +1))
        self.unwrap_button.clicked.connect(lambda: self.host.unwrap(self.path))
        self.more.clicked.connect(lambda: self._menu().exec(self.more.mapToGlobal(QPoint(0, self.more.height()))))
        head = QHBoxLayout()
        head.setSpacing(4)
        head.addWidget(self.grip)
        head.addWidget(title)
        head.addWidget(self.count)
        head.addStretch(1)
        for button in (self.unwrap_button, self.up, self.down, self.more):
            head.addWidget(button)
        layout = QVBoxLayout(self)
        layout.setContentsMargins(8, 6, 8, 8)
        layout.setSpacing(6)
        layout.addLayout(head)
        layout.addLayout(self.items_layout)

    def bind(self, cycle: Cycle, first: bool, last: bool) -> None:
        self.cycle = cycle
        self.first, self.last = first, last
        self.up.setEnabled(not first)
        self.down.setEnabled(not last)
        if not self.count.hasFocus():
            self._setting = True
            self.count.setValue(cycle.count.raw)
            self._setting = False
            self._count_shown = cycle.count.raw

    def _count_stepped(self, _value: int) -> None:
        if not self._setting and not self.count.lineEdit().hasFocus():
            self._count_done()

    def _count_done(self) -> None:
        if self.count.value() != self._count_shown:
            self._count_shown = self.count.value()
            self.host.set_cycle_count(self.path, self.count.value())

    def _menu(self) -> QMenu:
        menu = QMenu(self)
        menu.addAction(_("Unwrap cycle"), lambda: self.host.unwrap(self.path))
        menu.addSeparator()
        up = menu.addAction(_("Move up"), lambda: self.host.move_item(self.path, -1))
        up.setEnabled(not self.first)
        down = menu.addAction(_("Move down"), lambda: self.host.move_item(self.path, +1))
        down.setEnabled(not self.last)
        menu.addSeparator()
        menu.addAction(_("Delete cycle and its phases"), lambda: self.host.delete_item(self.path))
        return menu

    def contextMenuEvent(self, event) -> None:
        self._menu().exec(event.globalPos())

    def grabbed_at(self, pos: QPoint) -> bool:
        return pos.y() < 34           # the header: the box's own area, not its cards


# -- a command between phases / in the conclusion ---------------------------------------------

class CommandChip(DraggableFrame):
    """MUSIC(n) or LIGHT(n) as a small chip with its value."""

    def __init__(self, host, path: tuple, st: Statement, parent: QWidget | None = None, movable: bool = True):
        super().__init__(host, path, parent)
        self.setObjectName("commandChip")
        self.setSizePolicy(QSizePolicy.Policy.Maximum, QSizePolicy.Policy.Maximum)
        self.setToolTip(st.op.help)
        self.movable = movable
        self.first = self.last = False
        self.field = make_field(st.op.operands[0])
        self.field.committed.connect(lambda text: self.host.edit_value(self.path, 0, text))
        remove = _tool("✕", _("Remove {command}").format(command=st.op.keyword), "remove", name="removeCommand")
        remove.clicked.connect(lambda: self.host.remove_statement(self.path))
        layout = QHBoxLayout(self)
        layout.setContentsMargins(10, 2, 4, 2)
        layout.setSpacing(6)
        layout.addWidget(_label(_command_label(st.op), "field"))
        layout.addWidget(self.field)
        layout.addWidget(remove)
        self.bind(st, True, True)

    def bind(self, st: Statement, first: bool, last: bool) -> None:
        self.first, self.last = first, last
        if not self.field.busy():
            self.field.set_raw(st.args[0].raw)

    def start_drag(self) -> None:
        if self.movable:
            super().start_drag()

    def contextMenuEvent(self, event) -> None:
        if not self.movable:
            return
        menu = QMenu(self)
        up = menu.addAction(_("Move up"), lambda: self.host.move_item(self.path, -1))
        up.setEnabled(not self.first)
        down = menu.addAction(_("Move down"), lambda: self.host.move_item(self.path, +1))
        down.setEnabled(not self.last)
        menu.addSeparator()
        menu.addAction(_("Remove"), lambda: self.host.remove_statement(self.path))
        menu.exec(event.globalPos())


# -- a section -----------------------------------------------------------------------------------

class SectionColumn(DropZone):
    """One section as a column: its title, its items, and '+ Phase'."""

    def __init__(self, host, kind: str, parent: QWidget | None = None):
        super().__init__(host, (kind,), parent)
        self.kind = kind
        self.setObjectName(f"{kind}Column")
        title = _label(_(SECTION_TITLES[kind]), "sectionTitle")
        title.setProperty("section", kind)
        self.count = _label("", "count")
        self.count.setObjectName(f"{kind}Count")
        heading = QHBoxLayout()
        heading.setContentsMargins(0, 0, 0, 0)
        heading.addWidget(title)
        heading.addStretch(1)
        heading.addWidget(self.count, 0, Qt.AlignmentFlag.AlignBottom)
        bar = QFrame()
        bar.setProperty("role", "sectionBar")
        bar.setProperty("section", kind)
        bar.setFixedHeight(3)
        self.empty = _label("", "empty")
        self.empty.setWordWrap(True)
        self.add_phase = _tool("+ " + _("Phase"), _(ADD_PHASE_TIPS[kind]), "add", name="addPhase")
        self.add_phase.clicked.connect(lambda: self.host.add_phase(self.kind))
        foot = QHBoxLayout()
        foot.addWidget(self.add_phase)
        foot.addStretch(1)
        layout = QVBoxLayout(self)
        layout.setContentsMargins(2, 0, 2, 4)
        layout.setSpacing(8)
        layout.addLayout(heading)
        layout.addWidget(bar)
        layout.addLayout(self.items_layout)
        layout.addWidget(self.empty)
        layout.addLayout(foot)
        layout.addStretch(1)

    def clear_items(self) -> None:
        for widget in self.item_widgets:
            widget.hide()
            widget.setParent(None)
            widget.deleteLater()
        self.item_widgets = []

    def set_empty_text(self, present: bool, count: int, phases: int = 0) -> None:
        self.count.setText(ngettext("{n} phase", "{n} phases", phases).format(n=phases) if present else "")
        if count:
            self.empty.hide()
            return
        self.empty.setText(_(NO_SECTION_TEXTS[self.kind]) if not present else _("This section has no phase yet."))
        self.empty.show()
