"""The battery logbook (no Qt): a register of the user's packs and every session (an imported log, a
live run) attached to one, with its figures, the trends over the pack's life and a health verdict,
kept in one SQLite database in the user's data folder (``db.py``).

May import: ``safety``, ``sim``, ``logs``, ``streams``, ``protocol``, ``lang``, ``domain`` and the top-level
modules below; not ``device`` (beside it)."""
