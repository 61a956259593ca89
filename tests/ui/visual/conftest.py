"""Visual-editor fixtures: the view over a plain editor + validator, or wired into the main window."""
from types import SimpleNamespace

import pytest

from helpers import bare_seed



@pytest.fixture
def visual(qtbot):
    """A CodeEditor, a Validator (short debounce) and the VisualEditor, wired as the window does."""
    from zuml_studio.ui.editor.code_editor import CodeEditor
    from zuml_studio.ui.editor.validation import Validator
    from zuml_studio.ui.visual import VisualEditor

    def make(text=None, size=(800, 650)):
        editor = CodeEditor()
        qtbot.addWidget(editor)
        editor.setPlainText(text if text is not None else bare_seed("LiPo"))
        validator = Validator(delay_ms=10)
        view = VisualEditor(editor)
        qtbot.addWidget(view)
        validator.validated.connect(view.show_result)
        editor.textChanged.connect(lambda: validator.schedule(editor.toPlainText()))
        validator.run_now(editor.toPlainText())
        view.resize(*size)
        view.show()
        editor.show()
        return SimpleNamespace(editor=editor, validator=validator, view=view)

    return make


@pytest.fixture
def window_with_visual(make_window, qtbot, tmp_path):
    """The real main window with the visual editor wired to its editor and validator (on the LiPo seed
    without its comments, as the tests compare its lines)."""
    from zuml_studio.ui.visual import VisualEditor
    bare = tmp_path / "LiPo.zuml"
    bare.write_text(bare_seed("LiPo"))

    def make(path=None):
        w = make_window(str(bare) if path is None else path)
        view = VisualEditor(w.editor)
        qtbot.addWidget(view)
        w.validator.validated.connect(view.show_result)
        view.show_result(w.validator.last)
        view.resize(800, 650)
        view.show()
        return w, view

    return make
