"""Light and dark palettes: the syntax colours and the bytes view's labelled rows follow the
palette the window is drawn with, and the theme choice sets that palette."""
import pytest
from PySide6.QtGui import QColor, QGuiApplication
from PySide6.QtWidgets import QApplication

from helpers import MACROS, contrast_ratio
from zuml_studio.ui.base import theme
from zuml_studio.ui.editor.highlighter import CATEGORIES

LIPO = str(MACROS / "LiPo.zuml")


@pytest.mark.parametrize("scheme, base", [(theme.LIGHT, "#ffffff"), (theme.DARK, "#1e1e1e")])
def test_every_syntax_colour_is_readable_on_its_background(scheme, base):
    assert set(scheme.syntax) == set(CATEGORIES)
    for category, (colour, _bold, _italic) in scheme.syntax.items():
        assert contrast_ratio(QColor(colour), QColor(base)) >= 4.5, category
    for row in (scheme.header_row, scheme.check_row):
        assert contrast_ratio(QColor(row), QColor(base)) < 1.6          # a tint, not a block of paper


@pytest.mark.parametrize("choice", ["dark", "light"])
def test_the_window_follows_the_chosen_palette(make_window, system_theme, choice):
    w = make_window(LIPO)
    w.sim_panel.wait()                  # the auto re-simulation, done before the palette changes
    theme.apply_theme(choice)
    QApplication.processEvents()
    scheme = theme.DARK if choice == "dark" else theme.LIGHT
    assert theme.is_dark(w.editor.palette()) == (choice == "dark")
    assert w.editor.highlighter.scheme is scheme
    first = w.editor.document().firstBlock().layout().formats()
    assert first and first[0].format.foreground().color() == QColor(scheme.syntax["structure"][0])
    header = w.hex_view.tree.topLevelItem(0)
    assert header.background(1).color() == QColor(scheme.header_row)
    text = w.hex_view.tree.palette().color(w.hex_view.tree.palette().ColorRole.Text)
    assert contrast_ratio(text, header.background(1).color()) >= 7


def test_system_means_the_desktops_palette(make_window, system_theme):
    app = QApplication.instance()
    desktop = QGuiApplication.palette()
    w = make_window(LIPO)
    w.sim_panel.wait()
    app.setPalette(theme.dark_palette())          # a dark desktop
    QApplication.processEvents()
    assert w.editor.highlighter.scheme is theme.DARK
    app.setPalette(desktop)
    QApplication.processEvents()
    assert w.editor.highlighter.scheme is theme.LIGHT


def test_an_unknown_theme_is_refused():
    with pytest.raises(ValueError, match="system, light, dark"):
        theme.apply_theme("purple")
