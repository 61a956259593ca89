"""The Visual tab follows the light and dark palettes, and at 1366x768 shows several cards."""
import pytest
from PySide6.QtCore import QEventLoop, QRect, QTimer
from PySide6.QtGui import QColor
from PySide6.QtWidgets import QApplication, QBoxLayout

from helpers import MACROS
from zuml_studio.ui.base import theme
from zuml_studio.ui.visual import style
from zuml_studio.ui.visual.cards import PhaseCard


def _settle():
    loop = QEventLoop()
    QTimer.singleShot(200, loop.quit)
    loop.exec()


@pytest.mark.parametrize("choice", ["dark", "light"])
def test_the_cards_take_their_colours_from_the_palette(visual, system_theme, choice):
    v = visual()
    theme.apply_theme(choice)
    QApplication.processEvents()
    card = v.view.findChildren(PhaseCard)[0]
    paper = card.grab().toImage().pixelColor(card.width() - 4, card.height() // 2)
    page = v.view.grab().toImage().pixelColor(2, v.view.height() // 2)
    assert (paper.lightness() < 128, page.lightness() < 128) == (choice == "dark",) * 2
    colours = style.DARK if choice == "dark" else style.LIGHT
    assert (paper, page) == (QColor(colours["card"]), QColor(colours["page"]))
    assert theme.is_dark(card.palette()) == (choice == "dark")      # the fields' text is drawn to match


def test_several_cards_are_visible_at_1366x768(make_window):
    w = make_window(str(MACROS / "LiPo.zuml"))
    w.resize(1366, 768)
    _settle()
    w.show_visual()
    _settle()
    viewport = w.visual.scroll.viewport()
    cards = w.visual.findChildren(PhaseCard)
    assert len(cards) == 3
    whole = [c.path for c in cards if viewport.rect().contains(QRect(c.mapTo(viewport, c.rect().topLeft()), c.size()))]
    assert len(whole) >= 2, f"only {whole} fully visible in a {viewport.size()} viewport"


def test_the_height_the_visual_tab_borrows_goes_back_when_it_leaves(make_window):
    w = make_window(str(MACROS / "LiPo.zuml"))
    w.resize(1366, 768)
    _settle()
    before = w.sim_dock.height()
    w.show_visual()
    _settle()
    shrunk = w.sim_dock.height()
    assert shrunk < before                        # room made for the cards
    w.hex_dock.raise_()
    _settle()
    # Given back (the layout may round by a tab bar's height): far nearer the old height than the squeezed one.
    assert abs(w.sim_dock.height() - before) < (before - shrunk) / 4, (before, shrunk, w.sim_dock.height())


@pytest.mark.parametrize("name", ["LiPo", "NiMh-dV", "LiIon-CCCV", "Pb-float"])
def test_the_cards_fit_the_width_at_1366x768_without_a_horizontal_scroll_bar(make_window, name):
    w = make_window(str(MACROS / f"{name}.zuml"))
    w.resize(1366, 768)
    _settle()
    w.show_visual()
    _settle()
    bar = w.visual.scroll.horizontalScrollBar()
    assert bar.maximum() == 0 and not bar.isVisible(), (bar.maximum(), w.visual.scroll.viewport().width())
    assert w.visual.cols.direction() == QBoxLayout.Direction.LeftToRight      # the sections side by side


def test_too_narrow_for_both_sections_they_stack_instead_of_scrolling_sideways(visual):
    v = visual(size=(800, 650))
    _settle()
    assert v.view.cols.direction() == QBoxLayout.Direction.LeftToRight
    v.view.resize(420, 650)
    _settle()
    assert v.view.cols.direction() == QBoxLayout.Direction.TopToBottom
    assert v.view.scroll.horizontalScrollBar().maximum() == 0
    v.view.resize(800, 650)
    _settle()
    assert v.view.cols.direction() == QBoxLayout.Direction.LeftToRight
