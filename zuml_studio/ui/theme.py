"""Light and dark colour sets, chosen from the palette a widget is drawn with, and the
application-wide theme choice ("system", "light" or "dark").

Colours that sit on the text background (syntax, the bytes view's labelled rows, status
texts) come from here, so each has a readable pair on both backgrounds; a widget asks
``colours(self.palette())`` whenever its palette changes."""
from __future__ import annotations

from dataclasses import dataclass

from PySide6.QtGui import QColor, QPalette
from PySide6.QtWidgets import QApplication

THEMES = ("system", "light", "dark")


@dataclass(frozen=True)
class Colours:
    dark: bool
    syntax: dict[str, tuple[str, bool, bool]]     # highlighter category -> (colour, bold, italic)
    header_row: str                               # bytes view: header and name rows
    check_row: str                                # bytes view: the check byte
    stale_text: str                               # bytes of the last valid version
    current_line: str
    linked_line: str
    find_match: str
    ok: str                                       # "✔ valid"
    error: str                                    # "✖ 2 error(s)", error messages
    warning: str
    muted: str                                    # placeholders, hints
    quantities: dict[str, str]                    # "voltage", "current", "temp", "heatsink": a readout's values


LIGHT = Colours(
    dark=False,
    syntax={
        "structure": ("#1b3f8b", True, False),     # dark blue
        "declaration": ("#2a5db0", False, False),  # blue
        "action": ("#00796b", True, False),        # teal
        "condition": ("#7b1fa2", True, False),     # purple
        "outcome": ("#7b1fa2", False, False),
        "variable": ("#9c27b0", True, True),
        "command": ("#8d4a12", True, False),       # brown
        "number": ("#c75000", False, False),       # dark orange
        "value": ("#a3245e", False, False),        # raspberry
        "name": ("#202124", True, False),
        "comment": ("#567558", False, True),       # green-grey italic
    },
    header_row="#eef3fb", check_row="#eef8ee", stale_text="#9a9a9a",
    current_line="#edf2fa", linked_line="#e2f4e8", find_match="#ffe68a",
    ok="#1b7f3b", error="#b00020", warning="#9a5b00", muted="#888888",
    # the plots' hues (ui/stacked_plot.py), current and temperature a shade darker for text on a grey window
    quantities={"voltage": "#1f4e9c", "current": "#1c7033", "temp": "#b83d14", "heatsink": "#7b5ea7"},
)

# The same hues, lighter, for a background near #1e1e1e (each at least 4.5:1 against it).
DARK = Colours(
    dark=True,
    syntax={
        "structure": ("#7fa8f5", True, False),
        "declaration": ("#8fb8ff", False, False),
        "action": ("#4fd1bd", True, False),
        "condition": ("#d59cf5", True, False),
        "outcome": ("#d59cf5", False, False),
        "variable": ("#e39cf0", True, True),
        "command": ("#e0a870", True, False),
        "number": ("#ffa657", False, False),
        "value": ("#f28bb8", False, False),
        "name": ("#e8e8e8", True, False),
        "comment": ("#8fb493", False, True),
    },
    header_row="#26344d", check_row="#253d2c", stale_text="#7a7a7a",
    current_line="#2a2f3a", linked_line="#23452f", find_match="#6b5a12",
    ok="#5cc97a", error="#ff6b7a", warning="#f0a848", muted="#9a9a9a",
    quantities={"voltage": "#8fb8ff", "current": "#6fd08a", "temp": "#ff9a6b", "heatsink": "#c9a8f5"},
)


def is_dark(palette: QPalette) -> bool:
    """Whether text is drawn on a dark background in this palette."""
    return palette.color(QPalette.ColorRole.Base).lightness() < 128


def colours(palette: QPalette) -> Colours:
    return DARK if is_dark(palette) else LIGHT


def dark_palette() -> QPalette:
    """A dark palette for the Fusion style (what "dark" means on a light desktop)."""
    p = QPalette()
    role, group = QPalette.ColorRole, QPalette.ColorGroup
    for r, c in ((role.Window, "#2b2b2b"), (role.WindowText, "#e6e6e6"), (role.Base, "#1e1e1e"),
                 (role.AlternateBase, "#262626"), (role.ToolTipBase, "#333333"), (role.ToolTipText, "#e6e6e6"),
                 (role.PlaceholderText, "#8a8a8a"), (role.Text, "#e6e6e6"), (role.Button, "#353535"),
                 (role.ButtonText, "#e6e6e6"), (role.BrightText, "#ff5555"), (role.Link, "#7fa8f5"),
                 (role.Highlight, "#2f65ca"), (role.HighlightedText, "#ffffff"), (role.Light, "#4a4a4a"),
                 (role.Midlight, "#3c3c3c"), (role.Mid, "#2f2f2f"), (role.Dark, "#1a1a1a"), (role.Shadow, "#000000")):
        p.setColor(r, QColor(c))
    for r in (role.WindowText, role.Text, role.ButtonText):
        p.setColor(group.Disabled, r, QColor("#7a7a7a"))
    return p


class ThemeSwitch:
    """Applies a theme choice to the application; "system" gives back the palette and style
    the application started with (the desktop's)."""

    def __init__(self, app: QApplication):
        self.app = app
        self._system_palette = QPalette(app.palette())
        self._system_style = app.style().name()
        self.current = "system"

    def apply(self, choice: str) -> None:
        if choice not in THEMES:
            raise ValueError(f"theme must be one of {', '.join(THEMES)}, not {choice!r}")
        if choice == self.current:
            return
        self.current = choice
        # A style is replaced only when it must be (every widget is re-polished), and by name:
        # the application then creates and owns it.
        style = self._system_style if choice == "system" else "fusion"    # native styles may ignore a palette
        if self.app.style().name().lower() != style.lower():
            self.app.setStyle(style)
        if choice == "system":
            self.app.setPalette(self._system_palette)
        else:
            self.app.setPalette(dark_palette() if choice == "dark" else self.app.style().standardPalette())


_switch: ThemeSwitch | None = None


def apply_theme(choice: str) -> None:
    """Set the running application's theme ("system", "light" or "dark")."""
    global _switch
    app = QApplication.instance()
    if _switch is None or _switch.app is not app:
        _switch = ThemeSwitch(app)
    _switch.apply(choice)
