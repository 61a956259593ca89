"""The editor rendered offscreen: gutter dots, underlines and colours are really painted."""
from PySide6.QtGui import QColor

from helpers import MACROS
from zuml_studio.lang.compiler import compile_source
from zuml_studio.ui.editor.code_editor import EditorWithFind


def test_render_lipo_with_diagnostics(qtbot, tmp_path):
    text = (MACROS / "LiPo.zuml").read_text().replace("IF(V>4.1S)", "IF(V>4.1)").replace("1C", "1.005C")
    diagnostics = compile_source(text).diagnostics
    assert {d.severity.value for d in diagnostics} >= {"error", "warning"}
    w = EditorWithFind()
    qtbot.addWidget(w)
    w.editor.setPlainText(text)
    w.editor.set_diagnostics(diagnostics)
    w.editor.set_linked_lines({14, 15})
    w.editor.goto(12, 5)
    w.resize(700, 500)
    w.show()
    qtbot.waitExposed(w)
    image = w.grab().toImage()
    assert image.save(str(tmp_path / "editor.png"))
    editor = w.editor
    gutter = editor.line_number_area.width()

    def row_pixels(line, x_from, x_to):
        block = editor.document().findBlockByNumber(line - 1)
        top = editor.blockBoundingGeometry(block).translated(editor.contentOffset()).top()
        h = editor.fontMetrics().height()
        return [QColor(image.pixel(x, y)) for y in range(int(top), int(top) + h) for x in range(x_from, x_to)]

    def reddish(c):
        return c.red() > 180 and c.green() < 110 and c.blue() < 110

    def orangish(c):
        return c.red() > 200 and 100 < c.green() < 190 and c.blue() < 80

    # Gutter dots: red on the error line, orange on the warning line, none elsewhere.
    assert any(reddish(c) for c in row_pixels(12, 0, 12))
    assert any(orangish(c) for c in row_pixels(5, 0, 12))
    assert not any(reddish(c) or orangish(c) for c in row_pixels(3, 0, 12))
    # The red wave under "4.1" on line 12 (no red text anywhere else in the palette).
    assert any(reddish(c) for c in row_pixels(12, gutter, w.width()))
    assert not any(reddish(c) for c in row_pixels(11, gutter, w.width()))
