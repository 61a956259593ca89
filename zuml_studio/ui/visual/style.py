"""Colours and the style sheet of the visual editor (cards, section accents), in a light and
a dark set chosen like the rest of the window's colours (``theme.is_dark``)."""
from __future__ import annotations

from string import Template

from PySide6.QtGui import QPalette

from ..base import theme
from ...i18n import N_

SECTION_TITLES = {"discharge": N_("Discharge"), "charge": N_("Charge")}

LIGHT = dict(
    page="#f3f5f8", card="#ffffff", card_off="#f6f7f9", drag="#f7f9fc", line="#d6dce4", line_off="#e0e3e8",
    text="#1d2733", text_off="#9aa1ab", field="#5b6675", field_off="#a9b3c0", group="#7a8391", grip="#a3abb6",
    status="#4a5563", problem="#b00020", empty="#8a93a0",
    banner="#fff4d6", banner_text="#6b4a00", banner_line="#e8c872",
    discharge="#c0453c", discharge_text="#a8352d", discharge_tint="#fcefed",
    charge="#2f6db3", charge_text="#255c9c", charge_tint="#eaf1fb", badge_off="#eef0f3",
    cycle="#f8fafc", cycle_line="#9aa6b5", cycle_line_off="#d3d8de", cycle_text="#3c4756",
    chip="#eef1f5", chip_off="#f4f5f7", chip_line="#d3d9e1", condition_chip="#f1f4f8",
    icon="#6b7583", icon_hover="#e6eaf0", icon_off="#c3c8cf", remove="#9aa3ae", remove_hover="#fbe3e1",
    remove_hover_text="#b3261e", remove_off="#cdd2d8", add_line="#b9c2cd", add_text="#3f5f86",
    add_hover_line="#7ea3cf", add_off="#b7bec7", add_line_off="#dde1e6",
)

# The same roles for a window near #2b2b2b: cards a step lighter than the page, accents lighter.
DARK = dict(
    page="#23272d", card="#2e333a", card_off="#272b31", drag="#343a42", line="#434a54", line_off="#353a41",
    text="#e6e9ee", text_off="#7b838e", field="#aab3bf", field_off="#6b737e", group="#9aa3ae", grip="#6f7986",
    status="#aab3bf", problem="#ff6b7a", empty="#8f98a4",
    banner="#4a3d17", banner_text="#f3d58a", banner_line="#8a6d1f",
    discharge="#d9645b", discharge_text="#f0938b", discharge_tint="#4a2a28",
    charge="#4a8ad6", charge_text="#8fbaf0", charge_tint="#22344d", badge_off="#353a41",
    cycle="#282c32", cycle_line="#6b7785", cycle_line_off="#434a54", cycle_text="#cfd5dd",
    chip="#343a42", chip_off="#2b2f35", chip_line="#4a525c", condition_chip="#31363d",
    icon="#aab3bf", icon_hover="#3d444d", icon_off="#5a626c", remove="#8f98a4", remove_hover="#4a2a28",
    remove_hover_text="#ff8a80", remove_off="#59616b", add_line="#5d6874", add_text="#8fbaf0",
    add_hover_line="#4a8ad6", add_off="#5a626c", add_line_off="#3d444d",
)

_SHEET = Template("""
#visualEditor { background: $page; }
#visualContent, #visualScroll, #visualScroll > QWidget > QWidget { background: $page; }
#visualScroll { border: none; }

#visualBanner { background: $banner; color: $banner_text; padding: 5px 8px; border: 1px solid $banner_line;
                border-radius: 4px; }
#visualStatus { color: $status; padding: 2px 4px; }
#visualStatus[problem="true"] { color: $problem; }

#introBox { background: $card; border: 1px solid $line; border-radius: 8px; }
#introBox QLabel[role="field"] { color: $field; }
#introBox QLabel:disabled { color: $field_off; }

QLabel[role="sectionTitle"] { font-weight: 600; font-size: 11pt; padding: 0 2px; }
QLabel[role="sectionTitle"][section="discharge"] { color: $discharge_text; }
QLabel[role="sectionTitle"][section="charge"] { color: $charge_text; }
QFrame[role="sectionBar"][section="discharge"] { background: $discharge; border-radius: 2px; }
QFrame[role="sectionBar"][section="charge"] { background: $charge; border-radius: 2px; }
QLabel[role="count"] { color: $group; padding: 0 2px; }
QLabel[role="empty"] { color: $empty; font-style: italic; padding: 6px 4px; }

#phaseCard { background: $card; border: 1px solid $line; border-radius: 8px; }
#phaseCard[section="discharge"] { border-top: 3px solid $discharge; }
#phaseCard[section="charge"] { border-top: 3px solid $charge; }
#phaseCard[dragging="true"] { background: $drag; border-style: dashed; }
#phaseCard:disabled { background: $card_off; border-color: $line_off; }
#phaseCard QLabel[role="sentence"] { color: $text; font-size: 10pt; font-weight: 600; }
#phaseCard QLabel[role="sentence"]:disabled { color: $text_off; }
#phaseCard QLabel[role="badge"] { border-radius: 3px; padding: 0 5px; font-size: 8pt; font-weight: 600; }
#phaseCard[section="discharge"] QLabel[role="badge"] { color: $discharge_text; background: $discharge_tint; }
#phaseCard[section="charge"] QLabel[role="badge"] { color: $charge_text; background: $charge_tint; }
#phaseCard QLabel[role="badge"]:disabled { color: $text_off; background: $badge_off; }
QLabel[role="field"] { color: $field; }
QLabel[role="field"]:disabled, QLabel[role="group"]:disabled, QLabel[role="unit"]:disabled { color: $field_off; }
QLabel[role="group"] { color: $group; font-size: 8pt; font-weight: 600; padding: 4px 0 0 0; margin: 0; }
QLabel[role="grip"] { color: $grip; }
QLabel[role="unit"] { color: $field; }

#cycleBox { background: $cycle; border: 1px dashed $cycle_line; border-radius: 10px; }
#cycleBox:disabled { border-color: $cycle_line_off; }
#cycleBox QLabel[role="cycleTitle"] { color: $cycle_text; font-weight: 600; }

#commandChip { background: $chip; border: 1px solid $chip_line; border-radius: 12px; }
#commandChip:disabled { background: $chip_off; }
#conditionChip { background: $condition_chip; border: 1px solid $chip_line; border-radius: 12px; }

QToolButton[role="icon"] { border: none; border-radius: 4px; padding: 1px 3px; color: $icon;
                          background: transparent; }
QToolButton[role="icon"]:hover { background: $icon_hover; color: $text; }
QToolButton[role="icon"]:disabled { color: $icon_off; }
QToolButton[role="remove"] { border: none; border-radius: 4px; padding: 0 3px; color: $remove;
                            background: transparent; }
QToolButton[role="remove"]:hover { background: $remove_hover; color: $remove_hover_text; }
QToolButton[role="remove"]:disabled { color: $remove_off; }
QToolButton[role="add"] { border: 1px dashed $add_line; border-radius: 5px; padding: 2px 8px; color: $add_text;
                         background: transparent; }
QToolButton[role="add"]:hover { background: $charge_tint; border-color: $add_hover_line; }
QToolButton[role="add"]::menu-indicator { image: none; width: 0; }
QToolButton[role="add"]:disabled { color: $add_off; border-color: $add_line_off; }
""")


def colours(palette: QPalette) -> dict[str, str]:
    """The visual editor's colour set for a palette (dark text backgrounds get the dark set)."""
    return DARK if theme.is_dark(palette) else LIGHT


def style_sheet(palette: QPalette) -> str:
    return _SHEET.substitute(colours(palette))
