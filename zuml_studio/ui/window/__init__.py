"""The main window (``main_window``) and its parts, each with one job: its actions and menus
(``actions``), its docks (``docks``), the modes that arrange them (``modes``), a plot maximised
in place (``plot_focus``), the document's files (``documents``), the toolbar's icons
(``icons``) and Edit > Preferences (``preferences``). ``main_window`` builds the window from
them and wires the feature panels together. May import every ui package but ``app``."""
