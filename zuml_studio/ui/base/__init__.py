"""The foundations every other ui package may use: the light and dark colour sets (``theme``),
times as chargers show them (``timefmt``), the forms' number boxes and cell fields, one call off
the GUI thread (``background``), the GUI thread's collector (``gui_thread_gc``), values read back
from settings.ini, window sizes for a screen, the window's language, and Qt's platform libraries
checked before Qt starts. Imports no other ui package; importing this package loads no Qt."""
