"""Help > Command Reference (F1): one page per command of the opcode table, a search field
that filters them, and the page of the command under the editor's cursor shown first."""
from __future__ import annotations

import html

from PySide6.QtCore import Qt
from PySide6.QtWidgets import (QDialog, QLineEdit, QListWidget, QListWidgetItem, QSplitter,
                               QTextBrowser, QVBoxLayout, QWidget)

from ...i18n import _, ngettext
from ...lang import opcodes
from ...lang.docgen import operands_text, places_text

_OP = Qt.ItemDataRole.UserRole


def topic_title(op: opcodes.Op) -> str:
    return op.signature()


def topic_html(op: opcodes.Op) -> str:
    """A command's page: how it is written, what it does, its operands, where it may stand, its code."""
    where = places_text(op)
    size = ngettext("{n} byte", "{n} bytes", op.size).format(n=op.size)
    rows = [(_("Operands"), operands_text(op).replace("`", "")), (_("Where"), where),
            (_("Byte code"), f"{op.code} ({op.mnemonic}), {size}")]
    table = "".join(f"<tr><td><b>{html.escape(k)}</b>&nbsp;&nbsp;</td><td>{html.escape(v)}</td></tr>"
                    for k, v in rows)
    return (f"<h2><code>{html.escape(op.signature())}</code></h2><p>{html.escape(op.help)}</p>"
            f"<table cellspacing='4'>{table}</table>")


def matches(op: opcodes.Op, query: str) -> bool:
    """Whether a search (words, any order, any case) finds this command's page."""
    text = " ".join((op.signature(), op.mnemonic, op.help, operands_text(op))).lower()
    return all(word in text for word in query.lower().split())


class HelpBrowser(QDialog):
    def __init__(self, parent: QWidget | None = None):
        super().__init__(parent)
        self.setObjectName("helpBrowser")
        self.setWindowTitle(_("ZUML 2.0 commands"))
        self.search = QLineEdit()
        self.search.setObjectName("helpSearch")
        self.search.setPlaceholderText(_("Search commands (e.g. voltage, pulse, IF)"))
        self.search.setClearButtonEnabled(True)
        self.topics = QListWidget()
        self.topics.setObjectName("helpTopics")
        for op in opcodes.OPCODES:
            item = QListWidgetItem(topic_title(op))
            item.setData(_OP, op.code)
            item.setToolTip(op.help)
            self.topics.addItem(item)
        self.page = QTextBrowser()
        self.page.setObjectName("helpPage")
        splitter = QSplitter(Qt.Orientation.Horizontal)
        splitter.addWidget(self.topics)
        splitter.addWidget(self.page)
        splitter.setSizes([280, 520])
        layout = QVBoxLayout(self)
        layout.addWidget(self.search)
        layout.addWidget(splitter, 1)
        self.search.textChanged.connect(self._filter)
        self.topics.currentItemChanged.connect(self._show_item)
        self.resize(860, 520)

    def show_ops(self, ops: tuple[opcodes.Op, ...] = ()) -> None:
        """Show the first of these commands' pages (the whole list, search cleared); the first
        command of the table when none."""
        self.search.clear()
        code = ops[0].code if ops else opcodes.OPCODES[0].code
        for row in range(self.topics.count()):
            if self.topics.item(row).data(_OP) == code:
                self.topics.setCurrentRow(row)
                break

    def shown_title(self) -> str:
        item = self.topics.currentItem()
        return item.text() if item is not None else ""

    def visible_titles(self) -> list[str]:
        return [self.topics.item(r).text() for r in range(self.topics.count()) if not self.topics.item(r).isHidden()]

    def _filter(self, query: str) -> None:
        first = None
        for row in range(self.topics.count()):
            item = self.topics.item(row)
            hit = matches(opcodes.BY_CODE[item.data(_OP)], query)
            item.setHidden(not hit)
            if hit and first is None:
                first = item
        current = self.topics.currentItem()
        if first is not None and (current is None or current.isHidden()):
            self.topics.setCurrentItem(first)

    def _show_item(self, item: QListWidgetItem | None, _previous=None) -> None:
        if item is not None:
            self.page.setHtml(topic_html(opcodes.BY_CODE[item.data(_OP)]))
