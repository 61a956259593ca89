"""The smaller points of a laptop session (issue 34, section 2): warnings stay in Problems while
the text has an error, the Visual editor's refusal goes with its macro, the pack trend follows a
theme chosen while it is open, the Logs window fits its screen, and Open starts where the user
keeps documents, then where the last macro was opened or saved."""
from PySide6.QtCore import Qt
from PySide6.QtGui import QColor

from helpers import MACROS


def test_the_last_valid_versions_warnings_stay_greyed_while_the_text_has_an_error(make_window):
    w = make_window(str(MACROS / "LiPo.zuml"))          # the library's LiPo: W304 on its discharge
    w.validate_now()
    warned = [w.problems.topLevelItem(i).text(3) for i in range(w.problems.topLevelItemCount())]
    assert "W304" in warned
    w.editor.setPlainText(w.text().replace("END_MACRO", "END_MACR"))
    w.validate_now()
    codes = [w.problems.topLevelItem(i).text(3) for i in range(w.problems.topLevelItemCount())]
    assert any(code.startswith("E") for code in codes) and "W304" in codes
    stale = next(w.problems.topLevelItem(i) for i in range(w.problems.topLevelItemCount())
                 if w.problems.topLevelItem(i).text(3) == "W304")
    assert "(last valid version)" in stale.text(2)


def test_the_visual_editors_message_goes_when_another_macro_is_opened(make_window):
    w = make_window(str(MACROS / "LiPo.zuml"))
    w.visual.say("Not changed: something", problem=True)
    assert w.open_file(str(MACROS / "NiMh.zuml"))
    assert "Not changed" not in w.visual.status.text() and not w.visual.status.property("problem")


def test_the_pack_trend_follows_the_theme_chosen_while_it_is_open(qapp, system_theme):
    from zuml_studio.packs.health import TrendPoint
    from zuml_studio.ui.base import theme
    from zuml_studio.ui.packs.trend_plot import PackTrendPlot
    theme.apply_theme("dark")
    plot = PackTrendPlot()
    fields = {f: None for f in TrendPoint.__dataclass_fields__}
    plot.show_trend([TrendPoint(**{**fields, "recorded": "2026-01-02", "capacity_pct": 95.0})])
    assert plot.backgroundBrush().color() == QColor(theme.DARK.plot.paper)
    theme.apply_theme("light")
    qapp.processEvents()
    assert plot.backgroundBrush().color() == QColor(theme.LIGHT.plot.paper)
    assert len(plot.points["capacity_pct"][0]) == 1                    # drawn again in the new colours


def test_the_logs_window_fits_the_screen_it_opens_on(make_window):
    w = make_window()
    logs = w.open_log(str(MACROS / "LiPo.zuml"))            # any file: the window opens before it is read
    available = logs.screen().availableGeometry()
    assert logs.width() <= available.width() and logs.height() <= available.height()
    assert available.contains(logs.geometry())
    logs.close()


def test_open_starts_in_the_documents_then_where_the_last_macro_was(make_window, monkeypatch, tmp_path):
    from zuml_studio.ui.window.documents import documents_dir
    w = make_window()
    asked = []
    monkeypatch.setattr(w, "ask_open_path", lambda title, start, filters: asked.append(start) or "")
    w.open_dialog()
    assert asked[-1] == str(documents_dir())
    assert w.open_file(str(MACROS / "NiMh.zuml"))          # a standard macro: the package's folder is no start
    w.open_dialog()
    assert asked[-1] == str(documents_dir())
    mine = tmp_path / "mine" / "m.zuml"
    mine.parent.mkdir()
    mine.write_text((MACROS / "NiMh.zuml").read_text())
    assert w.open_file(str(mine))
    w.open_dialog()
    assert asked[-1] == str(mine.parent)


def test_a_squeezed_problems_list_gives_the_message_its_width(make_window, qtbot):
    w = make_window(str(MACROS / "LiPo.zuml"))
    w.validate_now()
    problems = w.problems
    narrow = Qt.Orientation.Horizontal     # the user drags the dock's edge, as a test resizes the dock
    w.resizeDocks([w.problems_dock], [150], narrow)
    qtbot.waitUntil(lambda: problems.isColumnHidden(1) and problems.isColumnHidden(3))
    item = problems.topLevelItem(0)
    assert item.toolTip(2).startswith(f"{item.text(1)} {item.text(3)}: ")       # where and which: on the tooltip
    w.resizeDocks([w.problems_dock], [400], narrow)
    qtbot.waitUntil(lambda: not problems.isColumnHidden(1) and not problems.isColumnHidden(3))
