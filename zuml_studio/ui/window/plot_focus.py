"""A plot maximised in place: a double-click on a watched plot hides the editor, the other
docks and the plot's neighbours in its own panel, so the plot fills the window where it
stands; Esc (or another double-click) brings the layout back as it was. Ctrl+double-click
stays the plot's own (a band's FAZE in the editor)."""
from __future__ import annotations

from PySide6.QtCore import QEvent, QObject, Qt, Signal
from PySide6.QtGui import QAction, QKeySequence
from PySide6.QtWidgets import QDockWidget, QMainWindow, QSplitterHandle, QWidget

from ...i18n import _


class PlotFocus(QObject):
    """Maximises one of the watched plots at a time."""
    changed = Signal(bool)

    def __init__(self, window: QMainWindow, central: QWidget):
        super().__init__(window)
        self.window = window
        self.central = central
        self._watched: dict[QObject, tuple[QWidget, QDockWidget, tuple[QWidget, ...]]] = {}
        self._saved: tuple[QWidget, bytes, bool, list[QWidget]] | None = None
        self.back = QAction(_("Restore the Layout"), window)
        self.back.setShortcut(QKeySequence(Qt.Key.Key_Escape))
        self.back.setEnabled(False)         # Esc is the find bar's and the dialogs' while nothing is maximised
        self.back.triggered.connect(self.restore)
        window.addAction(self.back)

    def watch(self, plot: QWidget, dock: QDockWidget, keep: tuple[QWidget, ...] = ()) -> None:
        """Maximise ``plot`` (inside ``dock``) on a double-click; ``keep``: its neighbours that
        stay (a readout the plot is read with)."""
        target = plot.viewport() if hasattr(plot, "viewport") else plot
        self._watched[target] = (plot, dock, keep)
        target.installEventFilter(self)

    def maximised(self) -> QWidget | None:
        return self._saved[0] if self._saved else None

    def eventFilter(self, obj: QObject, event: QEvent) -> bool:
        if (event.type() == QEvent.Type.MouseButtonDblClick and obj in self._watched
                and not event.modifiers() & Qt.KeyboardModifier.ControlModifier):
            plot, dock, keep = self._watched[obj]
            self.restore() if self._saved else self.maximise(plot, dock, keep)
        return False

    def maximise(self, plot: QWidget, dock: QDockWidget, keep: tuple[QWidget, ...] = ()) -> None:
        """``plot`` takes the window: everything else in its dock and the window is hidden."""
        if self._saved:
            self.restore()
        state = self.window.saveState()
        hidden: list[QWidget] = []
        child = plot
        while child.parentWidget() not in (dock, None):
            parent = child.parentWidget()
            for sibling in parent.findChildren(QWidget, options=Qt.FindChildOption.FindDirectChildrenOnly):
                if (sibling is not child and sibling not in keep and sibling.isVisible() and not sibling.isWindow()
                        and not isinstance(sibling, QSplitterHandle)):     # a splitter hides those itself
                    sibling.hide()
                    hidden.append(sibling)
            child = parent
        central = self.central.isVisible()
        self.central.hide()
        for other in self.window.findChildren(QDockWidget):
            if other is not dock and other.isVisible():
                other.hide()
        dock.show()
        dock.raise_()
        self._saved = (plot, state, central, hidden)
        self.back.setEnabled(True)
        self.window.statusBar().showMessage(_("The plot is maximised: Esc or a double-click brings the layout back."),
                                            6000)
        self.changed.emit(True)

    def restore(self) -> None:
        """The layout as it was before the plot was maximised."""
        if not self._saved:
            return
        _plot, state, central, hidden = self._saved
        self._saved = None
        for widget in hidden:
            widget.show()
        self.central.setVisible(central)
        self.window.restoreState(state)
        self.back.setEnabled(False)
        self.changed.emit(False)
