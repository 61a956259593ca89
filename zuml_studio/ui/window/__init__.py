"""The main window's parts, each with one job: its actions and menus (``actions``), its docks
(``docks``), the modes that arrange them (``modes``), a plot maximised in place
(``plot_focus``), the document's files (``documents``) and the toolbar's icons (``icons``).
``ui/window/main_window.py`` builds the window from them and wires the panels together."""
