"""Light and dark colour sets, chosen from the palette a widget is drawn with, and the
application-wide theme choice ("system", "light" or "dark").

Colours that sit on the text background (syntax, the bytes view's labelled rows, status
texts) and every plot's colours (``PlotColours``: paper, ink, bands, curve hues) come from
here, so each has a readable pair on both backgrounds; a widget asks
``colours(self.palette())`` whenever its palette changes."""
from __future__ import annotations

from dataclasses import dataclass

from PySide6.QtGui import QColor, QPalette
from PySide6.QtWidgets import QApplication

THEMES = ("system", "light", "dark")


@dataclass(frozen=True)
class PlotColours:
    """What a plot is drawn with besides the quantities' hues (``Colours.quantities``). Every
    hue drawn as a curve, and the ink, is at least 3:1 against the paper."""
    paper: str                                    # the plot's background
    ink: str                                      # tick labels, axis titles, legend and readout text
    axis: str                                     # axis lines and ticks
    grid: str                                     # grid lines, opaque (mixed over the paper)
    grid_alpha: float                             # pyqtgraph's own grid (the log viewer): axis colour at this share
    zero: str                                     # the current plot's zero line
    cursor: str                                   # the readout's vertical line
    placeholder: str                              # "no simulation yet"
    legend_fill: tuple[int, int, int, int]        # behind a legend or the readout: the paper, nearly opaque
    readout_border: str
    band_label: str                               # a phase band's label
    band_warning: str                             # ... of a phase a default ended
    bands: dict[str, tuple[int, int, int]]        # "charge", "discharge", "pause": the band's hue
    band_alpha: tuple[int, int]                   # neighbouring bands alternate between two strengths
    band_edge_alpha: int
    selected_alpha: int                           # the phase selected in the table
    pause: tuple[int, int, int, int]              # a heat-sink pause, translucent over the bands
    current_fill_alpha: int                       # the area under the current, in the current's hue
    cells: tuple[str, ...]                        # a log's cell voltages
    pack_cells: tuple[str, ...]                   # a pack's cells beside its voltage (simulator, live view): not its blue
    overlays: tuple[str, ...]                     # logs or cycles laid over the first
    compare: dict[str, str]                       # Compare with Log: "real", "model", "diff"

    def band_rgb(self, section: str) -> tuple[int, int, int]:
        return self.bands.get(section, self.bands["pause"])


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
    warning_row: str                              # a flagged row's background (the phase table)
    muted: str                                    # placeholders, hints
    key_text: str                                 # the names in a table of figures (a log's totals)
    quantities: dict[str, str]                    # "voltage", "current", "temp", "heatsink": curves and readouts
    plot: PlotColours


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
    ok="#1b7f3b", error="#b00020", warning="#9a5b00", warning_row="#fff3d6", muted="#888888",
    key_text="#606060",
    # current and temperature dark enough for text on a grey window too (the live readout)
    quantities={"voltage": "#1f4e9c", "current": "#1c7033", "temp": "#b83d14", "heatsink": "#7b5ea7"},
    plot=PlotColours(
        paper="#ffffff", ink="#303030", axis="#8a8a8a", grid="#e7e7e7", grid_alpha=0.12, zero="#707070",
        cursor="#505050", placeholder="#8a8a8a", legend_fill=(255, 255, 255, 215), readout_border="#b0b0b0",
        band_label="#1c2a44", band_warning="#b34700",
        bands={"charge": (74, 134, 232), "discharge": (232, 96, 74), "pause": (150, 150, 150)},
        band_alpha=(34, 16), band_edge_alpha=110, selected_alpha=80, pause=(90, 90, 90, 70), current_fill_alpha=28,
        cells=("#2f6db5", "#c0392b", "#5a7d1e", "#7048a8", "#1f7f95", "#c25e00", "#1d3f6e", "#7a2b28", "#4f6628",
               "#4d3b62", "#276a7c", "#a14f0a"),
        pack_cells=("#c62828", "#00838f", "#2e7d32", "#c25400", "#7b3fb0", "#8c564b", "#c2185b", "#7a7a00"),
        overlays=("#b06c00", "#8e44ad", "#127d68", "#c0392b", "#66737a", "#2c3e50", "#b34700", "#1e8449"),
        compare={"real": "#202020", "model": "#1f5fd0", "diff": "#c03030"},
    ),
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
    ok="#5cc97a", error="#ff6b7a", warning="#f0a848", warning_row="#4a3d17", muted="#9a9a9a",
    key_text="#a8a8a8",
    quantities={"voltage": "#8fb8ff", "current": "#6fd08a", "temp": "#ff9a6b", "heatsink": "#c9a8f5"},
    # The paper is the dark palette's Base; bands need more strength to show on it.
    plot=PlotColours(
        paper="#1e1e1e", ink="#d8d8d8", axis="#8c8c8c", grid="#363636", grid_alpha=0.18, zero="#9a9a9a",
        cursor="#b0b0b0", placeholder="#9a9a9a", legend_fill=(30, 30, 30, 215), readout_border="#5a5a5a",
        band_label="#c8d6f0", band_warning="#ffa657",
        bands={"charge": (90, 150, 240), "discharge": (240, 110, 90), "pause": (150, 150, 150)},
        band_alpha=(52, 28), band_edge_alpha=130, selected_alpha=100, pause=(200, 200, 200, 40),
        current_fill_alpha=40,
        cells=("#6fa0e0", "#ef7a6e", "#a9cf6a", "#b294dc", "#6cc6dc", "#f7a55e", "#a9c4f0", "#f5aaa3", "#cfe3a3",
               "#d2bff0", "#a6e0ee", "#fbc996"),
        pack_cells=("#ff6b6b", "#5fe0ee", "#7ee08a", "#ffb25c", "#c5a3ff", "#d9a88a", "#ff9bd9", "#e0e060"),
        overlays=("#f0a030", "#c08adf", "#3fcfae", "#f07868", "#b0bcbd", "#8fa8c8", "#ff9550", "#5fd08a"),
        compare={"real": "#e6e6e6", "model": "#7fb0ff", "diff": "#ff7a7a"},
    ),
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
