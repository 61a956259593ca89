"""GUI-thread time per keystroke in the code editor (target: under 5 ms for a 100-line macro).

Builds a CodeEditor offscreen, loads a 100-line macro (phases of the NiMh seed repeated),
then types 200 keys at a position mid-document with QTest.keyClick and processes the
events after each (colouring, extra selections, gutter, painting). Two runs: letters (a word
no completion matches, on a fresh line in the middle; a new line every 25 letters, not
timed, so the line stays on screen instead of scrolling sideways), and realistic statements
(completion popup opening and filtering, Return with auto-indent, closer dedent, every key
timed). Prints median and p90; no assertions.

Run: QT_QPA_PLATFORM=offscreen python benchmarks/bench_editor_keystroke.py
"""
from __future__ import annotations

import os
import statistics
import sys
import time
from pathlib import Path

os.environ.setdefault("QT_QPA_PLATFORM", "offscreen")
sys.path.insert(0, str(Path(__file__).resolve().parent.parent))

from PySide6.QtCore import Qt, qInstallMessageHandler
from PySide6.QtGui import QTextCursor
from PySide6.QtTest import QTest
from PySide6.QtWidgets import QApplication

from zuml_studio.lang.compiler import compile_source
from zuml_studio.ui.editor.code_editor import EditorWithFind

KEYS = 200


def hundred_line_macro() -> str:
    head = ["MACRO NiMh-long", "  AKK_TYPE=NiMh", "  SERIES=4", "  CAPACITY=2000", "  DISCHARGE_SECTION",
            "    FAZE", "      CONSTANT_I=1C", "      IF(V<1S) STOP_FAZE()", "    END_FAZE", "  END_SECTION",
            "  CHARGE_SECTION"]
    phase = ["    FAZE", "      CONSTANT_I=INPUT", "      IF(DELTA_PEAK=0.2S) STOP_FAZE()",
             "      IF(T>45) STOP_FAZE  // too warm", "      IF(tf>90min) STOP_FAZE", "    END_FAZE"]
    tail = ["  END_SECTION", "  MUSIC(STOP)", "END_MACRO"]
    lines = head + phase * ((100 - len(head) - len(tail)) // len(phase))
    lines += ["    // spare line"] * (100 - len(lines) - len(tail)) + tail
    return "\n".join(lines) + "\n"


def _key(editor, ch: str) -> None:
    if ch == "\n":
        QTest.keyClick(editor, Qt.Key.Key_Return)
    else:
        QTest.keyClick(editor, ch)


def time_keys(app: QApplication, editor, keys: str, untimed_return_every: int = 0) -> list[float]:
    """Milliseconds per key (key press + release + the events they cause, painting included)."""
    times = []
    for i, ch in enumerate(keys):
        if untimed_return_every and i and i % untimed_return_every == 0:
            _key(editor, "\n")              # a new line now and then, as a typist makes
            app.processEvents()
        t0 = time.perf_counter()
        _key(editor, ch)
        app.processEvents()
        times.append((time.perf_counter() - t0) * 1000)
    return times


def report(label: str, times: list[float]) -> None:
    ordered = sorted(times)
    print(f"{label}: median {statistics.median(ordered):.2f} ms, p90 {ordered[int(len(ordered) * 0.9)]:.2f} ms, "
          f"max {ordered[-1]:.2f} ms over {len(ordered)} keystrokes")


def fresh(box, text: str, diagnostics) -> None:
    editor = box.editor
    editor.setPlainText(text)
    editor.set_diagnostics(diagnostics)
    editor.goto(50)
    cursor = editor.textCursor()
    cursor.movePosition(QTextCursor.MoveOperation.EndOfBlock)
    editor.setTextCursor(cursor)


def main() -> None:
    app = QApplication.instance() or QApplication([])
    qInstallMessageHandler(lambda *_: None)   # offscreen: "does not support raise()" for each popup
    box = EditorWithFind()
    box.resize(900, 700)
    box.show()
    app.processEvents()
    text = hundred_line_macro()
    assert text.count("\n") == 100
    diagnostics = compile_source(text.replace("IF(T>45)", "IF(T>45.5)")).diagnostics
    print(f"macro: {text.count(chr(10))} lines, {len(diagnostics)} diagnostics shown")

    fresh(box, text, diagnostics)
    QTest.keyClick(box.editor, Qt.Key.Key_Return)        # a new line in the middle of a phase
    app.processEvents()
    letters = ("qwxzj" * KEYS)[:KEYS]
    report("letters at line 51 of 100 (new line every 25 letters, untimed)",
           time_keys(app, box.editor, letters, untimed_return_every=25))

    fresh(box, text, diagnostics)
    statement = "\nFAZE\nCONSTANT_V=4.2S\nIF(I<0.1A) STOP_FAZE\nEND_FAZE"
    keys = (statement * 10)[:KEYS]
    report("statements with completion, auto-indent, dedent", time_keys(app, box.editor, keys))
    box.close()


if __name__ == "__main__":
    main()
