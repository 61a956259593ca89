"""The Problems list wraps a message onto as many lines as it needs: in the narrow dock (and in
Russian) no message ends in a cut."""
from zuml_studio.lang.compiler import compile_source
from zuml_studio.ui.editor.problems import MESSAGE, ProblemsView

from helpers import MACROS


def test_a_long_message_wraps_and_its_row_grows_with_it(qtbot):
    view = ProblemsView()
    qtbot.addWidget(view)
    view.resize(300, 500)
    view.show()
    diagnostics = compile_source((MACROS / "NiMh.zuml").read_text()).diagnostics
    assert diagnostics
    view.set_diagnostics(diagnostics)
    metrics = view.fontMetrics()
    for row in range(view.topLevelItemCount()):
        item = view.topLevelItem(row)
        text = item.text(MESSAGE)
        qtbot.waitUntil(lambda: view.visualItemRect(item).height() > 0)
        width = view.header().sectionSize(MESSAGE)
        if metrics.horizontalAdvance(text) > width:
            lines_needed = metrics.horizontalAdvance(text) // width + 1
            assert view.visualItemRect(item).height() >= lines_needed * metrics.lineSpacing() * 0.8, text
    view.resize(1200, 500)                  # wider: the rows shrink back
    first = view.topLevelItem(0)
    qtbot.waitUntil(lambda: view.visualItemRect(first).height() < 3 * metrics.lineSpacing())
