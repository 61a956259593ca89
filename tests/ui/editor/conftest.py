"""Editor fixtures: a shown, focused code editor."""
import pytest


@pytest.fixture
def editor(qtbot):
    from zuml_studio.ui.editor.code_editor import CodeEditor

    e = CodeEditor()
    qtbot.addWidget(e)
    e.resize(600, 400)
    e.show()
    e.setFocus()
    return e
