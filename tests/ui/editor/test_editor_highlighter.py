"""Colouring: driven by the opcode table, read back from the block layouts."""
from PySide6.QtGui import QTextCharFormat

from zuml_studio.lang import opcodes
from zuml_studio.ui.editor import highlighter as hl


def formats_of(editor, line):
    """[(text, QTextCharFormat)] of the coloured ranges of a 1-based line."""
    block = editor.document().findBlockByNumber(line - 1)
    text = block.text()
    return [(text[r.start:r.start + r.length], QTextCharFormat(r.format)) for r in block.layout().formats()]


def format_for(editor, line, word):
    for text, fmt in formats_of(editor, line):
        if text == word:
            return fmt
    raise AssertionError(f"{word!r} not coloured in line {line}: {[t for t, _ in formats_of(editor, line)]}")


def key(fmt):
    return (fmt.foreground().color().name(), fmt.fontWeight(), fmt.fontItalic())


def test_keyword_number_comment_and_variable_get_different_formats(editor):
    editor.setPlainText("    IF(V<2.8S) STOP_FAZE() // empty\n    FAZE\n    CONSTANT_I=1C\n  MUSIC(STOP)\n")
    keyword = format_for(editor, 2, "FAZE")
    number = format_for(editor, 1, "2.8S")
    comment = format_for(editor, 1, "// empty")
    variable = format_for(editor, 1, "V")
    condition = format_for(editor, 1, "IF")
    action = format_for(editor, 3, "CONSTANT_I")
    command = format_for(editor, 4, "MUSIC")
    value = format_for(editor, 4, "STOP")
    keys = [key(f) for f in (keyword, number, comment, variable, condition, action, command, value)]
    assert len(set(keys)) == len(keys)
    assert comment.fontItalic()
    assert key(format_for(editor, 1, "STOP_FAZE")) == key(editor.highlighter.formats[hl.OUTCOME])


def test_numbers_keep_their_unit(editor):
    editor.setPlainText("CHARGE_EX(30, 1C, 1, 0.1A, 2)\nIF(tm>2h) STOP_MACRO\nCONSTANT_I=500mA\nCONSTANT_V=4.2S")
    assert [t for t, _ in formats_of(editor, 1)] == ["CHARGE_EX", "30", "1C", "1", "0.1A", "2"]
    assert "2h" in [t for t, _ in formats_of(editor, 2)]
    assert "500mA" in [t for t, _ in formats_of(editor, 3)]
    assert "4.2S" in [t for t, _ in formats_of(editor, 4)]


def test_T_is_a_variable_only_inside_IF(editor):
    editor.setPlainText("IF(T>45) STOP_FAZE\nT\nIF(t>2h) STOP_FAZE\nIF(Tc>70) PAUSE_MACRO\nIF(tc>70) PAUSE_MACRO")
    variable = key(editor.highlighter.formats[hl.VARIABLE])
    assert key(format_for(editor, 1, "T")) == variable
    assert "T" not in [t for t, _ in formats_of(editor, 2)]
    assert key(format_for(editor, 3, "t")) == variable          # t (phase time) and T (temperature) both
    assert key(format_for(editor, 4, "Tc")) == variable
    assert "tc" not in [t for t, _ in formats_of(editor, 5)]    # Tc is case-sensitive


def test_case_insensitive_keywords_and_variables(editor):
    editor.setPlainText("if(v<1s) stop_faze\nif(delta_peak=0.2S) STOP_FAZE\nconstant_i=input")
    assert key(format_for(editor, 1, "v")) == key(editor.highlighter.formats[hl.VARIABLE])
    assert key(format_for(editor, 2, "delta_peak")) == key(editor.highlighter.formats[hl.VARIABLE])
    assert key(format_for(editor, 3, "constant_i")) == key(editor.highlighter.formats[hl.ACTION])
    assert key(format_for(editor, 3, "input")) == key(editor.highlighter.formats[hl.VALUE])


def test_words_come_from_the_opcode_table():
    for op in opcodes.OPCODES:
        assert op.keyword.upper() in hl.KEYWORDS
    for outcome in opcodes.CONDITION_OUTCOMES:
        assert hl.KEYWORDS[outcome] == hl.OUTCOME
    for var in opcodes.condition_variables():
        assert [s.category for s in hl.classify_line(f"IF({var}>1)")][:2] == [hl.CONDITION, hl.VARIABLE]
    assert {"INPUT", "AUTO", "LIPO", "NIMH", "STOP", "ATTENTION", "FAST", "SLOW"} <= set(hl.SYMBOLIC_VALUES)


def test_context_decides_between_keyword_value_and_name():
    cats = {s.word: s.category for s in hl.classify_line("LIGHT(FAZE) MUSIC(STOP)")}
    assert cats == {"LIGHT": hl.COMMAND, "FAZE": hl.VALUE, "MUSIC": hl.COMMAND, "STOP": hl.VALUE}
    assert [(s.word, s.category) for s in hl.classify_line("MACRO LiPo CCCV // seed")] == [
        ("MACRO", hl.STRUCTURE), ("LiPo CCCV", hl.NAME), ("// seed", hl.COMMENT)]
    assert [s.category for s in hl.classify_line("AKK_TYPE=Lilon")] == [hl.DECLARATION, hl.VALUE]


def test_a_keystroke_rehighlights_only_its_own_line(editor, qtbot):
    editor.setPlainText("\n".join(["    FAZE", "    CONSTANT_I=1C", "    END_FAZE"] * 30))
    seen = []
    original = editor.highlighter.highlightBlock

    def spy(text):
        seen.append(text)
        original(text)

    editor.highlighter.highlightBlock = spy
    editor.goto(40, 5)
    qtbot.keyClicks(editor, "x")
    assert len(seen) == 1


def test_a_keystroke_repaints_its_line_not_the_whole_view(editor, qtbot):
    # QSyntaxHighlighter marks a re-coloured line dirty in a way the stock plain-text layout
    # takes for a multi-line change (a full repaint per keystroke); the editor's layout keeps
    # it to the line.
    editor.resize(600, 400)
    editor.show()
    editor.setPlainText("\n".join(["    FAZE", "    IF(T>45) STOP_FAZE", "    END_FAZE"] * 20))
    editor.goto(5, 12)                                       # after "45" in IF(T>45)
    qtbot.wait(10)
    rects = []
    editor.updateRequest.connect(lambda rect, dy: rects.append((rect.height(), dy)))
    qtbot.keyClicks(editor, "5")
    assert editor.document().findBlockByNumber(4).text() == "    IF(T>455) STOP_FAZE"
    assert "455" in [t for t, _ in formats_of(editor, 5)]
    line = editor.fontMetrics().height()
    assert rects and all(h <= 2 * line and dy == 0 for h, dy in rects), rects
