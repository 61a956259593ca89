"""Colours and the style sheet of the visual editor (light cards, section accents)."""
from __future__ import annotations

ACCENTS = {"discharge": "#c0453c", "charge": "#2f6db3"}
SECTION_TITLES = {"discharge": "Discharge", "charge": "Charge"}

STYLE = """
#visualEditor { background: #f3f5f8; }
#visualContent, #visualScroll, #visualScroll > QWidget > QWidget { background: #f3f5f8; }
#visualScroll { border: none; }

#visualBanner { background: #fff4d6; color: #6b4a00; padding: 5px 8px; border: 1px solid #e8c872;
                border-radius: 4px; }
#visualStatus { color: #4a5563; padding: 2px 4px; }
#visualStatus[problem="true"] { color: #b00020; }

#introBox { background: #ffffff; border: 1px solid #d6dce4; border-radius: 8px; }
#introBox QLabel[role="field"] { color: #5b6675; }
#introBox QLabel:disabled { color: #a0a7b0; }

QLabel[role="sectionTitle"] { font-weight: 600; font-size: 11pt; padding: 0 2px; }
QLabel[role="sectionTitle"][section="discharge"] { color: #a8352d; }
QLabel[role="sectionTitle"][section="charge"] { color: #255c9c; }
QFrame[role="sectionBar"][section="discharge"] { background: #c0453c; border-radius: 2px; }
QFrame[role="sectionBar"][section="charge"] { background: #2f6db3; border-radius: 2px; }
QLabel[role="count"] { color: #7a8391; padding: 0 2px; }
QLabel[role="empty"] { color: #8a93a0; font-style: italic; padding: 6px 4px; }

#phaseCard { background: #ffffff; border: 1px solid #d6dce4; border-radius: 8px; }
#phaseCard[section="discharge"] { border-top: 3px solid #c0453c; }
#phaseCard[section="charge"] { border-top: 3px solid #2f6db3; }
#phaseCard[dragging="true"] { background: #f7f9fc; border-style: dashed; }
#phaseCard:disabled { background: #f6f7f9; border-color: #e0e3e8; }
#phaseCard QLabel[role="sentence"] { color: #1d2733; font-size: 10pt; font-weight: 600; }
#phaseCard QLabel[role="sentence"]:disabled { color: #9aa1ab; }
#phaseCard QLabel[role="badge"] { border-radius: 3px; padding: 0 5px; font-size: 8pt; font-weight: 600; }
#phaseCard[section="discharge"] QLabel[role="badge"] { color: #a8352d; background: #fcefed; }
#phaseCard[section="charge"] QLabel[role="badge"] { color: #255c9c; background: #eaf1fb; }
#phaseCard QLabel[role="badge"]:disabled { color: #9aa1ab; background: #eef0f3; }
QLabel[role="field"] { color: #5b6675; }
QLabel[role="field"]:disabled, QLabel[role="group"]:disabled, QLabel[role="unit"]:disabled { color: #a9b0b9; }
QLabel[role="group"] { color: #7a8391; font-size: 8pt; font-weight: 600; padding: 4px 0 0 0; margin: 0; }
QLabel[role="grip"] { color: #a3abb6; }
QLabel[role="unit"] { color: #5b6675; }

#cycleBox { background: #f8fafc; border: 1px dashed #9aa6b5; border-radius: 10px; }
#cycleBox:disabled { border-color: #d3d8de; }
#cycleBox QLabel[role="cycleTitle"] { color: #3c4756; font-weight: 600; }

#commandChip { background: #eef1f5; border: 1px solid #d3d9e1; border-radius: 12px; }
#commandChip:disabled { background: #f4f5f7; }
#conditionChip { background: #f1f4f8; border: 1px solid #d3d9e1; border-radius: 12px; }

QToolButton[role="icon"] { border: none; border-radius: 4px; padding: 1px 3px; color: #6b7583; background: transparent; }
QToolButton[role="icon"]:hover { background: #e6eaf0; color: #1d2733; }
QToolButton[role="icon"]:disabled { color: #c3c8cf; }
QToolButton[role="remove"] { border: none; border-radius: 4px; padding: 0 3px; color: #9aa3ae; background: transparent; }
QToolButton[role="remove"]:hover { background: #fbe3e1; color: #b3261e; }
QToolButton[role="remove"]:disabled { color: #cdd2d8; }
QToolButton[role="add"] { border: 1px dashed #b9c2cd; border-radius: 5px; padding: 2px 8px; color: #3f5f86;
                         background: transparent; }
QToolButton[role="add"]:hover { background: #eaf1fb; border-color: #7ea3cf; }
QToolButton[role="add"]::menu-indicator { image: none; width: 0; }
QToolButton[role="add"]:disabled { color: #b7bec7; border-color: #dde1e6; }
"""
