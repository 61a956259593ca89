"""Unsaved work and where files go: generated macros, the read-only standard macros, the
folders the dialogs start in, reopening the last file."""
from pathlib import Path

from PySide6.QtCore import QSize
from PySide6.QtGui import QImage, QTextCursor

from helpers import MACROS
from zuml_studio import data
from zuml_studio.wizard import Answers, new_macro

STANDARD_MACROS = data.standard_macros_dir()

LIPO = str(MACROS / "LiPo.zuml")


def _recovery_files(window):
    return sorted((window.config / "recovery").glob("*.zuml"))


def test_a_template_is_unsaved_work_written_to_recovery_and_asked_about(make_window):
    w = make_window()
    assert w.new_from_template(STANDARD_MACROS / "NiMh.zuml")
    assert w.path is None and w.is_dirty() and w.isWindowModified()
    assert [p.read_text() for p in _recovery_files(w)] == [w.text()]
    asked = []
    w.ask_unsaved = lambda: asked.append("new") or "cancel"
    assert not w.new_file()                                        # Ctrl+N asks first
    w.ask_unsaved = lambda: asked.append("open") or "cancel"
    assert not w.open_file(LIPO)                                   # so does Open
    w.ask_unsaved = lambda: asked.append("quit") or "cancel"
    assert not w.close()                                           # and Ctrl+Q
    assert asked == ["new", "open", "quit"]
    w.ask_unsaved = lambda: "discard"


def test_a_wizard_macro_is_unsaved_work(make_window):
    w = make_window()
    assert w.new_generated(new_macro(Answers("LiPo", 3, 2200, None, True)))
    assert w.is_dirty() and len(_recovery_files(w)) == 1


def test_the_empty_new_macro_is_clean_and_without_warnings(make_window):
    w = make_window()
    assert not w.is_dirty()
    assert w.validate_now().ok and w.validate_now().diagnostics == []


def test_a_standard_macro_opens_read_only_and_save_goes_to_my_macros(make_window, qtbot):
    standard = STANDARD_MACROS / "LiPo.zuml"
    before = standard.read_bytes()
    w = make_window(str(standard))
    assert w.is_read_only() and "read-only" in w.windowTitle()
    w.editor.moveCursor(QTextCursor.MoveOperation.End)
    qtbot.keyClicks(w.editor, "// mine")
    asked = []

    def answer(title, suggested, filters):
        asked.append(suggested)
        return suggested

    w.ask_save_path = answer
    assert w.save()                                                 # Ctrl+S: Save As, not an overwrite
    assert asked == [str(w.user_macros / "LiPo.zuml")]
    assert standard.read_bytes() == before
    assert Path(w.path) == (w.user_macros / "LiPo.zuml").resolve() and not w.is_read_only()
    assert "// mine" in (w.user_macros / "LiPo.zuml").read_text()


def test_save_as_into_the_standard_folder_is_refused(make_window):
    standard = STANDARD_MACROS / "NiMh.zuml"
    before = standard.read_bytes()
    w = make_window()
    w.ask_save_path = lambda *a: str(standard)
    assert not w.save_as()
    assert standard.read_bytes() == before


def test_exports_start_in_my_macros_or_the_documents_never_the_current_folder(make_window, monkeypatch):
    from zuml_studio.ui.window import documents

    w = make_window(str(STANDARD_MACROS / "LiPo.zuml"))
    monkeypatch.setattr(documents, "documents_dir", lambda: w.config / "Documents")
    asked = []
    w.ask_save_path = lambda title, suggested, filters: asked.append(suggested) or ""
    w.ask_png_options = lambda title: (title, QSize(800, 600))
    w.export_record()
    w.sim_panel.simulate()
    w.sim_panel.wait(60_000)
    w.export_csv()
    w.export_png()
    assert asked == [str(w.user_macros / "LiPo.bin"), str(w.config / "Documents" / "LiPo.csv"),
                     str(w.config / "Documents" / "LiPo.png")]


def test_exports_confirm_in_the_status_bar(make_window, tmp_path):
    w = make_window(LIPO)
    w.ask_png_options = lambda title: ("LiPo charge", QSize(900, 700))
    w.sim_panel.simulate()
    w.sim_panel.wait(60_000)
    for export, name in ((w.export_csv, "run.csv"), (w.export_png, "run.png")):
        w.ask_save_path = lambda *a, n=name: str(tmp_path / n)
        export()
        assert (tmp_path / name).is_file()
        assert str(tmp_path / name) in w.statusBar().currentMessage()


def test_the_last_file_reopens_at_the_next_start(make_window, tmp_path):
    config = tmp_path / "same-config"
    first = make_window(LIPO, config)
    assert first.close()
    second = make_window(None, config)
    assert second.path == str(Path(LIPO).resolve())
    (tmp_path / "gone.zuml").write_text(Path(LIPO).read_text())
    second.open_file(str(tmp_path / "gone.zuml"), ask=False)
    assert second.close()
    (tmp_path / "gone.zuml").unlink()
    third = make_window(None, config)
    assert third.path is None                                        # a file since removed: a new macro


def test_the_png_has_the_chosen_size_title_and_details(make_window, tmp_path):
    w = make_window(LIPO)
    w.sim_panel.simulate()
    w.sim_panel.wait(60_000)
    shown = w.sim_panel.plot.size()
    w.ask_png_options = lambda title: ("LiPo, 3 cells", QSize(1200, 800))
    w.ask_save_path = lambda *a: str(tmp_path / "plot.png")
    w.export_png()
    image = QImage(str(tmp_path / "plot.png"))
    assert (image.width(), image.height()) == (1200, 800)
    assert w.sim_panel.plot.size() == shown                 # the window's plot is back as it was
    top = image.copy(0, 0, 1200, 60)
    dark = sum(1 for x in range(0, 1200, 2) for y in range(0, 60, 2) if top.pixelColor(x, y).lightness() < 100)
    assert dark > 50                                         # the title and details are written there


def test_file_new_is_a_lipo_charged_cc_cv_that_fills_the_cell_by_its_own_end_condition():
    """Issue 25: the new macro was CC only (1831 of 2000 mAh)."""
    from zuml_studio.lang.compiler import compile_source
    from zuml_studio.sim.interpreter import StartParams
    from zuml_studio.sim.simulate import simulate
    from zuml_studio.ui.window.documents import EMPTY_MACRO

    checked = compile_source(EMPTY_MACRO)
    assert checked.ok and not checked.diagnostics
    assert "CONSTANT_V=4.2S" in EMPTY_MACRO
    run = simulate(checked.record, StartParams("charge", 1, 2000, 2.0, None, 1, True))
    (phase,) = run.phases
    assert phase.reason == "IF(I<0.1C) STOP_FAZE"
    assert run.totals()["mah_in"] >= 0.95 * 2000
